// wedges-additive (Assarsson & Akenine-Möller 2003): V = clamp(V_hard - Σ coverage, 0, 1).
// - V_hard: the light centre's z-fail volumes (as `hard`);
// - one wedge per directed silhouette edge, built on the GPU from the edge (WedgePass), each
//   pixel inside it subtracting the edge's signed coverage of the light;
// - exact for one silhouette; where penumbrae of different silhouettes overlap the sum
//   double-counts (DESIGN.md §4): the resolve counts the pixels its clamp touched;
// - only the groups and wedges that can reach a tile of visible surface are drawn
//   (GroupBatches.h: visibleSets; RenderSettings::depthAwareCulling).
#include "engine/DebugViews.h"
#include "engine/Method.h"
#include "passes/FullscreenPass.h"
#include "passes/StencilVolumePass.h"
#include "passes/WedgePass.h"
#include "methods/GroupBatches.h"
#include "methods/MethodUtil.h"

namespace gpu {

namespace {

class AdditiveWedgesMethod final : public VisibilityMethod {
public:
    explicit AdditiveWedgesMethod(const MethodResources& r)
        : mSurface(r.shaders), mVolumes(r.shaders), mAccumulate(r.shaders), mWedges(r.shaders) {}

    void execute(const FrameContext& ctx) override {
        const Targets& t = ctx.targets;
        const std::vector<CasterRange> runs = casterRuns(ctx.casters, ctx.casterSubset);
        // Only the groups and wedges that can reach the visible surface (GroupBatches.h).
        const std::optional<VisibleSets> visible = visibleSets(ctx, mSurface, ctx.light, /*wedges=*/true);
        drawHardVisibility(ctx, runs, mVolumes, mAccumulate,
                           visible ? &visible->volumes : nullptr);
        {
            ScopedPass pass(&ctx.timers, "wedge-setup");
            mWedges.beginFrame(ctx.casters.edgeCount());
            mWedges.setup(runs);
        }
        {
            ScopedPass pass(&ctx.timers, "wedges");
            DrawSet all;
            if (!visible)
                for (const CasterRange& r : runs) all.add(r);
            mWedges.draw(t.visibilityFbo, t, visible ? visible->wedges : all);
        }
        {
            ScopedPass pass(&ctx.timers, "resolve");
            mWedges.resolve(t);
        }
        const WedgeCounts c = mWedges.counts();
        addWedgeCounters(ctx, c, runs);
        ctx.addCounter("groups_culled", countCulledGroups(ctx));
        ctx.addCounter("pixels_clamped", c.clampedPixels);
    }

    bool drawDebug(DebugView view, const FrameContext& ctx, DebugViews& debug) override {
        return view == DebugView::WedgeWireframe && drawWedgeWireframe(ctx, mWedges, debug);
    }

private:
    SurfaceTilePass mSurface;
    StencilVolumePass mVolumes;
    AccumulatePass mAccumulate;
    WedgePass mWedges;
};

} // namespace

std::unique_ptr<VisibilityMethod> createAdditiveWedgesMethod(const MethodResources& r) {
    return std::make_unique<AdditiveWedgesMethod>(r);
}

} // namespace gpu
