// hard: one z-fail stencil shadow-volume pass from the light centre (DESIGN.md §4), drawn by
// vertex pulling from the frame's silhouette groups, then V = 1 where the count is zero. Only
// the groups whose volume can reach a tile of visible surface are drawn (GroupBatches.h:
// visibleSets; RenderSettings::depthAwareCulling).
#include "engine/Method.h"
#include "passes/FullscreenPass.h"
#include "passes/StencilVolumePass.h"
#include "passes/VolumeStates.h"
#include "methods/GroupBatches.h"
#include "methods/MethodUtil.h"

namespace gpu {

namespace {

class HardMethod final : public VisibilityMethod {
public:
    explicit HardMethod(const MethodResources& r)
        : mSurface(r.shaders), mVolumes(r.shaders), mAccumulate(r.shaders) {}

    void execute(const FrameContext& ctx) override {
        // Only the groups whose volume can reach the visible surface (a light of zero size at
        // the centre: the tightest cone).
        geometry::RectLight centre = ctx.light;
        centre.u = centre.v = glm::vec3(0.0f);
        const std::optional<VisibleSets> visible = visibleSets(ctx, mSurface, centre, /*wedges=*/false);
        drawHardVisibility(ctx, casterRuns(ctx.casters, ctx.casterSubset), mVolumes,
                           mAccumulate, visible ? &visible->volumes : nullptr);
    }

private:
    SurfaceTilePass mSurface;
    StencilVolumePass mVolumes;
    AccumulatePass mAccumulate;
};

} // namespace

std::unique_ptr<VisibilityMethod> createHardMethod(const MethodResources& r) {
    return std::make_unique<HardMethod>(r);
}

} // namespace gpu
