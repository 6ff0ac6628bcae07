// raytrace: the G-buffer positions read back and traced on the CPU with Embree (N stratified
// rays per pixel to the light; geometry/reference/RayTracer.h), written into V. transmittance=on:
// each ray carries the product of (1 - alpha) of the surfaces it crosses (the deep-sm method's
// rule; off, the default, alpha-tests them).
#include "engine/Method.h"
#include "engine/MethodOptions.h"

#include <geometry/reference/RayTracer.h>

#include <limits>

namespace gpu {

namespace {

class RaytraceMethod final : public VisibilityMethod {
public:
    explicit RaytraceMethod(const MethodResources& r)
        : mScene(r.scene), mOptions(raytraceOptions(r.parameters)) {}

    // CPU memory of a frame: positions and normals read back (RGBA32F each), points and normals
    // (3 floats each), V (1 float).
    std::size_t targetBytesPerPixel() const override { return 16 + 16 + 12 + 12 + 4; }

    void execute(const FrameContext& ctx) override {
        if (!mTracer) {
            auto t0 = Clock::now();
            mTracer = std::make_unique<geometry::RayTracer>(mScene);
            ctx.addCpuTime("raytrace-build", msSince(t0));
        }
        const Targets& t = ctx.targets;
        auto t0 = Clock::now();
        const std::vector<float> pos = t.position.readFloat(4);
        const std::vector<float> nrm = t.normal.readFloat(4);
        const std::size_t n = static_cast<std::size_t>(t.width) * t.height;
        std::vector<glm::vec3> points(n), normals(n);
        const float nan = std::numeric_limits<float>::quiet_NaN();
        for (std::size_t i = 0; i < n; ++i) {
            const bool surface = pos[4 * i + 3] != 0.0f;
            points[i] = surface ? glm::vec3(pos[4 * i], pos[4 * i + 1], pos[4 * i + 2])
                                : glm::vec3(nan);
            normals[i] = glm::vec3(nrm[4 * i], nrm[4 * i + 1], nrm[4 * i + 2]);
        }
        ctx.addCpuTime("gbuffer-readback", msSince(t0));
        t0 = Clock::now();
        std::vector<float> v(n);
        geometry::RayTraceSettings rt;
        rt.samples = ctx.settings.samples;
        rt.seed = ctx.settings.seed;
        rt.transmittance = mOptions.transmittance;
        mTracer->visibility(ctx.light, points, normals, rt, v);
        ctx.addCpuTime("raytrace", msSince(t0));
        glTextureSubImage2D(t.visibility.id(), 0, 0, 0, t.width, t.height, GL_RED, GL_FLOAT,
                            v.data());
    }

private:
    const geometry::Scene& mScene;
    RaytraceOptions mOptions;
    std::unique_ptr<geometry::RayTracer> mTracer; // built on the first frame (BVH over all)
};

} // namespace

std::unique_ptr<VisibilityMethod> createRaytraceMethod(const MethodResources& r) {
    return std::make_unique<RaytraceMethod>(r);
}

} // namespace gpu
