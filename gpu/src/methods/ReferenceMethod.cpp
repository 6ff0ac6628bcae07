// reference: N exact hard-shadow passes from stratified points of the light, each adding 1/N
// where lit (DESIGN.md §4 "Reference"). Volumes by the two-sided multiplicity rule, built on the
// CPU per sample (geometry/ShadowVolume.h): exact for any mesh, no silhouette reuse to trust.
#include "../Method.h"
#include "../passes/FullscreenPass.h"
#include "../passes/StencilVolumePass.h"
#include "MethodUtil.h"

#include <geometry/Sampling.h>
#include <geometry/ShadowVolume.h>

#include <algorithm>

namespace gpu {

namespace {

class ReferenceMethod final : public VisibilityMethod {
public:
    explicit ReferenceMethod(const MethodResources& r)
        : mVolumes(r.shaders), mAccumulate(r.shaders) {}

    void execute(const FrameContext& ctx) override {
        const RenderSettings& s = ctx.settings;
        const auto samples = geometry::stratifiedSquare(s.samples, s.seed);
        const int total = static_cast<int>(samples.size());
        ctx.setAccumulationWeight(1.0f / static_cast<float>(total));
        const int step = std::max(1, total / 10);
        for (int i = 0; i < total; ++i) {
            const glm::vec3 light = ctx.light.point(samples[i].x, samples[i].y);
            auto t0 = Clock::now();
            const std::size_t frontCaps = buildVolume(ctx, light);
            ctx.addCpuTime("shadow-volume-build", msSince(t0));
            {
                ScopedPass pass(&ctx.timers, "shadow-volume");
                clearStencil(ctx.targets);
                mVolumes.drawVertices(ctx.targets, mVolume, frontCaps);
            }
            {
                ScopedPass pass(&ctx.timers, "accumulate");
                mAccumulate.execute(ctx.targets.visibilityFbo, ctx.targets.width,
                                    ctx.targets.height);
            }
            if (s.progress && ((i + 1) % step == 0 || i + 1 == total)) {
                glFinish(); // progress should reflect finished work, not queued commands
                s.progress(i + 1, total);
            }
        }
        ctx.setAccumulationWeight(1.0f);
    }

private:
    // Volumes of the casters for one light point; front caps first (StencilVolumePass).
    std::size_t buildVolume(const FrameContext& ctx, const glm::vec3& light) {
        mVolume.clear();
        mRest.clear();
        std::size_t frontCapVertices = 0;
        for (const std::uint32_t c : ctx.casterSubset) {
            const geometry::Topology& topology = ctx.casters.topology(c);
            mPart.clear();
            geometry::appendHardShadowVolume(topology, light, mPart);
            const auto front = static_cast<std::ptrdiff_t>(3 * topology.triangles().size());
            mVolume.vertices.insert(mVolume.vertices.end(), mPart.vertices.begin(),
                                    mPart.vertices.begin() + front);
            mRest.insert(mRest.end(), mPart.vertices.begin() + front, mPart.vertices.end());
            frontCapVertices += static_cast<std::size_t>(front);
        }
        mVolume.vertices.insert(mVolume.vertices.end(), mRest.begin(), mRest.end());
        return frontCapVertices;
    }

    StencilVolumePass mVolumes;
    AccumulatePass mAccumulate;
    geometry::ShadowVolumeGeometry mVolume, mPart;
    std::vector<glm::vec4> mRest;
};

} // namespace

std::unique_ptr<VisibilityMethod> createReferenceMethod(const MethodResources& r) {
    return std::make_unique<ReferenceMethod>(r);
}

} // namespace gpu
