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
//   surface box meets both its influence bounds and its shadow cone (geometry/shadow/ShadowCone.h: the
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
#include "passes/SurfaceTilePass.h"

#include <gpu/gl/State.h>

#include <geometry/core/Types.h>

#include <glm/glm.hpp>

#include <cstdint>
#include <optional>
#include <span>
#include <vector>

namespace gpu {

struct FrameContext;

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

// wedges-bitmask silhouettes=potential (one wedge pass over every caster, no groups): per
// segment [a[i], b[i]] (a potential silhouette edge, world), whether its shadow cone for `light`
// (geometry/shadow/ShadowCone.h, the segment as the occluder) meets the visible surface of some
// tile within the screen rectangle of its influence bounds (the segment's reach, clamped to
// `sceneBounds`). A wedge whose edge reaches no visible surface changes no pixel: its m and
// region are zero for every receiver it does not shade.
std::vector<std::uint8_t> segmentsReachingSurface(std::span<const glm::vec3> a,
                                                  std::span<const glm::vec3> b,
                                                  const geometry::Aabb& sceneBounds,
                                                  const SurfaceTiles& surface,
                                                  const geometry::RectLight& light,
                                                  const glm::mat4& viewProj, int width, int height);

// Whether this frame culls by the visible surface (RenderSettings::depthAwareCulling and at least
// 64 silhouette groups), and the tiles measured for it (timed as the "surface-tiles" pass).
bool depthAwareFrame(const FrameContext& ctx);
// Measured once a frame: kept in the frame's FrameScratch, where a later method (auto's paths)
// finds it without a second wait.
SurfaceTiles measureSurface(const FrameContext& ctx, SurfaceTilePass& surface);

// Surface boxes grown by a relative margin (float: the G-buffer position and the point a
// shader reconstructs or depth-tests may differ in their last bits), with their spheres (for
// geometry::sphereMayMeetCone); an empty box where a tile has no surface.
struct TileSphere {
    geometry::Aabb box;
    glm::vec3 centre{0.0f};
    float radius = 0.0f;
};
std::vector<TileSphere> tileSpheres(const SurfaceTiles& surface);

} // namespace gpu
