#include "methods/ReferenceSampler.h"

#include "methods/MethodUtil.h"
#include "engine/ShaderBindings.h"

namespace gpu {

void ReferenceSampler::add(const FrameContext& ctx, const glm::vec3& lightPoint,
                           const Framebuffer& target) {
    auto t0 = Clock::now();
    const std::size_t frontCaps = buildVolume(ctx, lightPoint);
    ctx.addCpuTime("shadow-volume-build", msSince(t0));
    {
        ScopedPass pass(&ctx.timers, "shadow-volume");
        clearStencil(ctx.targets);
        mVolumes.drawVertices(ctx.targets, mVolume, frontCaps);
    }
    ScopedPass pass(&ctx.timers, "accumulate");
    glBindTextureUnit(TEXUNIT_POSITION, ctx.targets.position.id());
    glBindTextureUnit(TEXUNIT_NORMAL, ctx.targets.normal.id());
    mAccumulate.executeFromPoint(target, ctx.targets.width, ctx.targets.height, lightPoint);
}

std::size_t ReferenceSampler::buildVolume(const FrameContext& ctx, const glm::vec3& light) {
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

} // namespace gpu
