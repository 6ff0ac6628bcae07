// hard: one z-fail stencil shadow-volume pass from the light centre (DESIGN.md §4), drawn by
// vertex pulling from the frame's silhouette groups, then V = 1 where the count is zero.
#include "../Method.h"
#include "../passes/FullscreenPass.h"
#include "../passes/StencilVolumePass.h"
#include "../passes/VolumeStates.h"
#include "MethodUtil.h"

namespace gpu {

namespace {

class HardMethod final : public VisibilityMethod {
public:
    explicit HardMethod(const MethodResources& r) : mVolumes(r.shaders), mAccumulate(r.shaders) {}

    void execute(const FrameContext& ctx) override {
        drawHardVisibility(ctx, casterRuns(ctx.casters, ctx.casterSubset), mVolumes,
                           mAccumulate);
    }

private:
    StencilVolumePass mVolumes;
    AccumulatePass mAccumulate;
};

} // namespace

std::unique_ptr<VisibilityMethod> createHardMethod(const MethodResources& r) {
    return std::make_unique<HardMethod>(r);
}

} // namespace gpu
