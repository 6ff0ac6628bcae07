// Small helpers shared by the methods.
#pragma once

#include "engine/CasterSet.h"
#include "engine/Method.h"
#include "engine/Targets.h"
#include "passes/FullscreenPass.h"

#include <gpu/gl/State.h>

#include <cstdint>
#include <span>
#include <vector>

namespace gpu {

// Blending that multiplies the target by the pass's output (V = V_target * V_pass): the
// per-silhouette products of wedges-multiply and auto's composition of its parts.
constexpr PipelineState kMultiplyState{
    .blend = true,
    .blendSrc = GL_DST_COLOR,
    .blendDst = GL_ZERO,
};

// V as the product of the V of several methods in one frame (auto's paths; pdsm's static and
// dynamic casters): the first method writes V; before each later one V is saved and the target
// cleared (methods start from V = 0, engine/Method.h), after it the saved V multiplies in. The
// passes are timed as "compose".
class VisibilityProduct {
public:
    VisibilityProduct(const ShaderLoader& shaders, const char* label);
    void resize(int width, int height);
    void beforeFactor(const FrameContext& ctx); // saves V, clears the target
    void afterFactor(const FrameContext& ctx);  // V = saved V * V
    // Its target memory per pixel (the saved V, R32F).
    static constexpr std::size_t kBytesPerPixel = 4;

private:
    FullscreenPass mMultiply;
    Texture mSaved;
};

// Zeroes the stencil counts (with the write mask a volume pass would leave on).
void clearStencil(const Targets& t);

// The frame ranges of `subset` (ascending caster indices), adjacent casters merged into one
// range each so that the usual case, every caster, is one draw per volume part.
std::vector<CasterRange> casterRuns(const CasterSet& casters,
                                    std::span<const std::uint32_t> subset);

class StencilVolumePass;
class AccumulatePass;

// V = 1 where the light centre is visible, 0 elsewhere: the z-fail volumes of `runs` (or of
// `visible` alone: the groups that can reach the visible surface, GroupBatches.h), then the
// accumulate pass (the `hard` method, and the start value of wedges-additive).
void drawHardVisibility(const FrameContext& ctx, std::span<const CasterRange> runs,
                        StencilVolumePass& volumes, const AccumulatePass& accumulate,
                        const DrawSet* visible = nullptr);

// Whether a world box lies wholly outside one plane of the view frustum of `viewProj` (reversed
// Z, infinite far plane: the side planes and the near plane). The same test as
// shaders/lib/Frustum.glsl, which culls wedges on the GPU.
bool boxOutsideFrustum(const geometry::Aabb& box, const glm::mat4& viewProj);

// Groups of the casters in `ctx.casterSubset` whose influence bounds miss the view frustum.
std::uint32_t countCulledGroups(const FrameContext& ctx);

class WedgePass;
class DebugViews;
// The WedgeWireframe debug view of a wedge method: the hulls of the wedges `wedges` set up this
// frame for ctx.casterSubset, with a note. true (the method has wedges).
bool drawWedgeWireframe(const FrameContext& ctx, WedgePass& wedges, DebugViews& debug);

struct WedgeCounts;
// The wedge counters of the report (kinds, culled, around the camera, fragments) for the edges
// of `runs`.
void addWedgeCounters(const FrameContext& ctx, const WedgeCounts& counts,
                      std::span<const CasterRange> runs);

} // namespace gpu
