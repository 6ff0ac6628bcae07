// Batches of silhouette groups that cannot interact on screen, for the per-silhouette methods
// (Forest et al. 2006): a pass sequence per group would grow with the number of groups
// (hundreds to thousands on a level); groups whose screen-space influence rectangles do not
// overlap can share one sequence, so the passes grow with the overlap depth instead.
// - Each group's rectangle is the projection of its influence bounds (volume ∪ wedges, clamped to
//   the scene), clipped to the half-space in front of the eye; groups whose bounds miss the view
//   frustum are culled.
// - Depth-aware tiles: a group changes a pixel only where the pixel's visible surface point lies
//   in its influence region. Per 16x16 tile the world bounds of the visible surface are measured
//   on the GPU (SurfaceTilePass); of the tiles in a group's rectangle it keeps those whose
//   surface box meets both its influence bounds and its shadow cone (geometry/ShadowCone.h: the
//   region its occluder can shade from the light). A group with no tile left is hidden (behind
//   walls, in another room) and draws nothing; the others' rectangles shrink to their tiles.
//   Inside a level this is what keeps the passes few: the influence boxes alone span rooms.
//   Within a drawn group, an edge's wedge is drawn only if the edge's own shadow cone (the
//   segment as the occluder) meets one of the group's tiles: a wedge changes nothing outside
//   it, and its hull's stencil mark there only sends a pixel through the combine step with no
//   coverage, which gives what the umbra or untouched step gives.
// - Greedy colouring of the overlap graph on the tile grid: a group joins the first batch none
//   of whose tiles it touches (conservative: tiles only ever separate more).
#pragma once

#include "engine/CasterSet.h"

#include <gpu/gl/Objects.h>
#include <gpu/gl/ShaderLoader.h>
#include <gpu/gl/State.h>

#include <geometry/core/Types.h>

#include <glm/glm.hpp>

#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <vector>

namespace gpu {

struct FrameContext;
struct Targets;
class StencilVolumePass;
class WedgePass;

struct GroupBatch {
    DrawSet set;          // the batch's groups' cap triangles and edges (their volumes)
    DrawSet wedgeSet;     // the edges whose wedges can reach a surface the group's tiles hold
    ScissorRect rect;     // union of its groups' rectangles (pixels)
    std::uint32_t groups = 0;
    std::uint64_t pixels = 0; // area of `rect`: the pixels the batch's scissored passes cover
    std::uint64_t groupPixels = 0; // sum of its groups' own rectangles (<= pixels)
};

struct GroupBatches {
    std::vector<GroupBatch> batches;
    std::uint32_t culledGroups = 0; // influence bounds outside the view frustum
    std::uint32_t hiddenGroups = 0; // in the frustum, but no visible surface in their reach
    std::uint32_t hiddenWedges = 0; // of drawn groups: no visible surface in the edge's cone
    std::uint32_t drawnGroups = 0;
};

// World bounds of the visible surface per tile of `tile` x `tile` pixels, row by row from the
// bottom left; an empty box where a tile has no surface pixel.
struct SurfaceTiles {
    int tile = 16, tilesX = 0, tilesY = 0;
    std::vector<geometry::Aabb> boxes;
};

// Measures SurfaceTiles from the G-buffer's positions (shaders/surface-tiles.comp) and reads
// them back: the CPU batching needs them before the batches' passes (a wait for the G-buffer).
class SurfaceTilePass {
public:
    static constexpr int kTile = 16; // pixels per tile side (shaders/surface-tiles.comp)
    explicit SurfaceTilePass(const ShaderLoader& shaders);
    SurfaceTiles measure(const Targets& t);

private:
    Program mProgram;
    Buffer mTiles;
    std::vector<glm::vec4> mScratch;
};

// Batches on a grid of `tile` pixels; with `surface` (same tile size) and `light`, only the
// tiles whose surface a group can reach (above), else every tile of its rectangle. `wedges`
// false: no wedge sets (GroupBatch::wedgeSet stays empty; no per-edge tests).
GroupBatches batchGroups(const CasterSet& casters, std::span<const std::uint32_t> casterSubset,
                         const glm::mat4& viewProj, int width, int height, int tile = 16,
                         const SurfaceTiles* surface = nullptr,
                         const geometry::RectLight* light = nullptr, bool wedges = true);

// The methods that draw every group in one pass (hard, wedges-additive), with
// RenderSettings::depthAwareCulling and at least 64 silhouette groups (fewer are not worth the
// pass and its wait): measures the surface tiles and returns the groups'
// volumes and the wedges that can reach one for `light` (hard: a light of zero size at the
// centre), with the counters "groups_hidden" and (`wedges`) "wedges_hidden". std::nullopt
// otherwise (draw every caster).
struct VisibleSets {
    DrawSet volumes, wedges; // `wedges` empty unless asked for
};
std::optional<VisibleSets> visibleSets(const FrameContext& ctx, SurfaceTilePass& surface,
                                       const geometry::RectLight& light, bool wedges);

// The frame of the per-silhouette methods (multiply, blend): the visible surface's tiles
// (SurfaceTilePass: a wait for the G-buffer; skipped as visibleSets skips it); batches; every
// wedge set up once; the stencil cleared once; then per batch, scissored to it:
// 1. the batch's groups' z-fail volumes: the count in the stencil's low bits (VolumeStates.h);
// 2. their wedges (GroupBatch::wedgeSet) into `target` (the method's per-silhouette targets,
//    holding their empty values everywhere), marking the touched pixels in the stencil
//    (kStencilWedgeMark);
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
// ("groups_hidden", "wedges_hidden": left out by the surface tiles; "wedges_drawn";
// "pixels_blended": the samples of step 3's draws — the touched pixels, once per round of a
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
void runSilhouetteBatches(const FrameContext& ctx, SurfaceTilePass& surface,
                          StencilVolumePass& volumes, WedgePass& wedges, const Framebuffer& target,
                          const BatchSteps& steps);

} // namespace gpu
