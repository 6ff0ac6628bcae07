// Batches of silhouette groups that cannot interact on screen, for the per-silhouette methods
// (Forest et al. 2006): a pass sequence per group would grow with the number of groups
// (hundreds to thousands on a level); groups whose screen-space influence rectangles do not
// overlap can share one sequence, so the passes grow with the overlap depth instead.
// - Each group's rectangle is the projection of its influence bounds (volume ∪ wedges, clamped to
//   the scene), the whole screen when those reach behind the camera; groups whose bounds miss
//   the view frustum are culled.
// - Greedy colouring of the overlap graph on a coarse tile grid: a group joins the first batch
//   none of whose tiles it touches (conservative: tiles only ever separate more).
#pragma once

#include "../CasterSet.h"

#include <gpu/State.h>

#include <glm/glm.hpp>

#include <cstdint>
#include <functional>
#include <span>
#include <vector>

namespace gpu {

struct FrameContext;
class StencilVolumePass;
class WedgePass;

struct GroupBatch {
    DrawSet set;          // the batch's groups' cap triangles and edges
    ScissorRect rect;     // union of its groups' rectangles (pixels)
    std::uint32_t groups = 0;
    std::uint64_t pixels = 0; // area of `rect`: the pixels the batch's scissored passes cover
    std::uint64_t groupPixels = 0; // sum of its groups' own rectangles (<= pixels)
};

struct GroupBatches {
    std::vector<GroupBatch> batches;
    std::uint32_t culledGroups = 0;
    std::uint32_t drawnGroups = 0;
};

// `tile` pixels per grid cell.
GroupBatches batchGroups(const CasterSet& casters, std::span<const std::uint32_t> casterSubset,
                         const glm::mat4& viewProj, int width, int height, int tile = 16);

// The frame of the per-silhouette methods (multiply, blend): batches; every wedge set up once;
// the stencil cleared once; then per batch, scissored to it:
// 1. the batch's groups' z-fail volumes: the count in the stencil's low bits (VolumeStates.h);
// 2. their wedges into `target` (the method's per-silhouette targets, holding their empty
//    values everywhere), marking the touched pixels in the stencil (kStencilWedgeMark);
// 3. `combine` where a wedge touched: the method draws its combine pass under `lit` (the
//    group leaves the light centre visible there) and `occluded` (it hides it); `touched`
//    selects both without changing the stencil (for a method that needs several rounds, e.g.
//    wedges-blend's part sets: reset its targets and draw the wedges again in between);
// 4. `reset` where a wedge touched: the per-silhouette targets back to their empty values
//    (the given state zeroes those pixels' stencil);
// 5. `umbra` where no wedge touched but the count is non-zero (the group's umbra: its state
//    there is the full occlusion): drawn under `keep`, the last draw under `zero`, which
//    zeroes the stencil there.
// The stencil and the per-silhouette targets are thus clean again after every batch, touched
// only where the batch drew: no per-batch clears. Where no group's wedge or volume reaches, the
// final buffer is never touched. Adds the batch and wedge counters to the report
// ("pixels_blended": the samples of step 3's draws — the touched pixels, once per round of a
// method that needs several —, "pixels_umbra": those of step 5, summed over batches, by
// occlusion queries).
struct TouchedStates {
    PipelineState lit, occluded, touched;
};
struct UmbraStates {
    PipelineState keep, zero;
};
struct BatchSteps {
    std::function<void(const GroupBatch&, const TouchedStates&)> combine;
    std::function<void(const GroupBatch&, const PipelineState& stencil)> reset;
    std::function<void(const GroupBatch&, const UmbraStates&)> umbra;
};
// `base` with the stencil test and scissor of `stencil` (a state given to combine or reset).
inline PipelineState withStencil(PipelineState base, const PipelineState& stencil) {
    base.stencilTest = stencil.stencilTest;
    base.stencilWriteMask = stencil.stencilWriteMask;
    base.stencilFront = stencil.stencilFront;
    base.stencilBack = stencil.stencilBack;
    base.scissor = stencil.scissor;
    base.scissorRect = stencil.scissorRect;
    return base;
}
void runSilhouetteBatches(const FrameContext& ctx, StencilVolumePass& volumes, WedgePass& wedges,
                          const Framebuffer& target, const BatchSteps& steps);

} // namespace gpu
