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
// then per batch, scissored to it: `clear` (the stencil and the method's per-silhouette targets
// in `target`, state already scissored), the batch's groups' volumes into `target`'s stencil,
// `afterVolumes`, their wedges into `target`, and `combine` (into the final buffer). Adds the
// batch and wedge counters to the report.
struct BatchSteps {
    std::function<void()> clear;
    std::function<void(const GroupBatch&)> afterVolumes; // may be empty
    std::function<void(const GroupBatch&)> combine;
};
void runSilhouetteBatches(const FrameContext& ctx, StencilVolumePass& volumes, WedgePass& wedges,
                          const Framebuffer& target, const BatchSteps& steps);

} // namespace gpu
