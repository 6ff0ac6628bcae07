// reference: N exact hard-shadow passes from stratified points of the light, each adding 1/N
// where lit (DESIGN.md §4 "Reference"; the pass: ReferenceSampler.h).
#include "engine/Method.h"
#include "methods/ReferenceSampler.h"

#include <geometry/core/Sampling.h>

#include <algorithm>

namespace gpu {

namespace {

class ReferenceMethod final : public VisibilityMethod {
public:
    explicit ReferenceMethod(const MethodResources& r) : mSampler(r.shaders) {}

    void execute(const FrameContext& ctx) override {
        const RenderSettings& s = ctx.settings;
        const auto samples = geometry::stratifiedSquare(s.samples, s.seed);
        const int total = static_cast<int>(samples.size());
        ctx.setAccumulationWeight(1.0f / static_cast<float>(total));
        const int step = std::max(1, total / 10);
        for (int i = 0; i < total; ++i) {
            mSampler.add(ctx, ctx.light.point(samples[i].x, samples[i].y),
                         ctx.targets.visibilityFbo);
            if (s.progress && ((i + 1) % step == 0 || i + 1 == total)) {
                glFinish(); // progress should reflect finished work, not queued commands
                s.progress(i + 1, total);
            }
        }
        ctx.setAccumulationWeight(1.0f);
    }

    bool countsOwnPlane() const override { return true; } // ReferenceSampler's accumulation

private:
    ReferenceSampler mSampler;
};

} // namespace

std::unique_ptr<VisibilityMethod> createReferenceMethod(const MethodResources& r) {
    return std::make_unique<ReferenceMethod>(r);
}

} // namespace gpu
