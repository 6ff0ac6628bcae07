// One exact hard-shadow pass from one point of the light, added where lit: the step of the
// `reference` method (N of them, stratified over the light), and of the renderer's progressive
// reference behind the error heat-map debug view (a few per frame). Volumes by the two-sided
// multiplicity rule, built on the CPU per point (geometry/shadow/ShadowVolume.h): exact for any mesh,
// no silhouette reuse to trust.
#pragma once

#include "engine/Method.h"
#include "passes/FullscreenPass.h"
#include "passes/StencilVolumePass.h"

#include <geometry/shadow/ShadowVolume.h>

#include <glm/glm.hpp>

#include <vector>

namespace gpu {

class ReferenceSampler {
public:
    explicit ReferenceSampler(const ShaderLoader& shaders)
        : mVolumes(shaders), mAccumulate(shaders) {}

    // The z-fail volumes of ctx.casterSubset from `lightPoint` into the stencil, then the frame's
    // accumulation weight (FrameContext::setAccumulationWeight) added into `target` where the
    // count is zero. `target` must hold the shared depth-stencil attachment.
    void add(const FrameContext& ctx, const glm::vec3& lightPoint, const Framebuffer& target);

private:
    // Volumes of the casters for one light point; front caps first (StencilVolumePass).
    std::size_t buildVolume(const FrameContext& ctx, const glm::vec3& light);

    StencilVolumePass mVolumes;
    AccumulatePass mAccumulate;
    geometry::ShadowVolumeGeometry mVolume, mPart;
    std::vector<glm::vec4> mRest;
};

} // namespace gpu
