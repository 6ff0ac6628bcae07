// wedges-bitmask evaluate=tiles: the wedges of the frame's set binned to the 8 x 8 pixel tiles
// whose visible surface their hulls may reach (the surface's world box per tile and per 32 x 32
// super-tile: surface-tiles.comp), in four stages (WEDGE_TILES_STAGE; the prefix sum in three
// dispatches):
// 0 per wedge slot of the frame's set (a list of slots, heads[uRun.x ...]): its TileWedge (what
//   wedge.vert hands the fragment shader) and the tiles of its hull's screen rectangle;
// 1 per slot: one more entry in heads[t] for each tile t whose surface box (and its 32 x 32
//   super-tile's) may meet the hull;
// 2 the tiles' first entries and fill cursors (a prefix sum, by rows), the total, and the ids of
//   the tiles whose list is not empty (the evaluation runs on those only);
// 3 per slot: the same tiles again, its slot into each one's list (where the count stage's
//   entries did not fit the pairs buffer);
// 4 per entry the count stage recorded (the usual way): its slot into its tile's list at the
//   index the count's atomic gave it, without testing any tile again.
// A wedge reaches a pixel's list wherever the rasterised hull would give the pixel a fragment
// inside its planes (the fragment shader's early out): the tiled evaluation processes the same
// (pixel, wedge) pairs.
// The order within a list depends on the atomics; the evaluation's sums do not (integers).
#include "lib/Bindings.h"
#include "shared/WedgeHull.h"
#include "shared/Spread.h"

#ifndef WEDGE_TILES_STAGE
#define WEDGE_TILES_STAGE 0
#endif

#if WEDGE_TILES_STAGE == 1 || WEDGE_TILES_STAGE == 3
// Small groups, so that the spread order below has many to deal out (lib/Bindings.h).
layout(local_size_x = WEDGE_TILES_SLOT_GROUP) in;
#else
layout(local_size_x = 64) in;
#endif

#include "lib/WedgeTiles.glsl"

layout(location = 0) uniform uvec2 uRun;  // where the slot list starts in heads[], its length
layout(location = 1) uniform ivec2 uTiles; // tiles across, down
layout(location = 2) uniform ivec2 uSize;  // the frame's pixels
#if WEDGE_TILES_STAGE == 2
layout(location = 4) uniform int uScanStep;
#endif
#if WEDGE_TILES_STAGE == 1 || WEDGE_TILES_STAGE == 3
layout(location = 6) uniform uint uSpread; // spreadStride of the work groups' number
#endif
#if WEDGE_TILES_STAGE == 1 || WEDGE_TILES_STAGE == 4
layout(std430, binding = BINDING_WEDGE_TILE_PAIRS) buffer TilePairs {
    uint tilePairs[]; // 3 per entry: slot, tile, index in the tile's list
};
layout(location = 5) uniform uint uPairCapacity; // entries tilePairs holds
#endif

#if WEDGE_TILES_STAGE == 1 || WEDGE_TILES_STAGE == 3
layout(std430, binding = BINDING_SURFACE_TILES) readonly buffer SurfaceTiles {
    vec4 tileBounds[]; // 2 per tile: min, max (min > max: no surface)
};
layout(std430, binding = BINDING_WEDGE_SUPERTILES) readonly buffer SurfaceSupertiles {
    vec4 supertileBounds[]; // the same per 32 x 32 pixels
};
#endif

#if WEDGE_TILES_STAGE == 0
#define WEDGE_APEXES 1
layout(std430, binding = BINDING_WEDGES) readonly buffer Wedges {
    GpuWedge wedges[];
};
layout(std430, binding = BINDING_GROUPS) readonly buffer Groups {
    GpuGroup groups[];
};
layout(std430, binding = BINDING_WELDED_POSITIONS) readonly buffer WeldedPositions {
    vec4 weldedPositions[];
};
layout(std430, binding = BINDING_EDGES) readonly buffer Edges {
    GpuEdge edges[];
};
layout(std430, binding = BINDING_EDGE_APEXES) readonly buffer EdgeApexes {
    uvec2 edgeApexes[];
};
#include "lib/WedgeCorners.glsl"

// The NDC rectangle of a bounded hull: its corners as wedge.vert draws them (a cut silhouette
// cone: the apex and apex + reach g; else e0, e1 and the directions g1..g4 at infinity), or the
// whole view when one lies on or behind the eye's plane (the camera may be inside).
vec4 hullScreenRect(GpuWedge wedge) {
    float reach = wedge.rays[3].w;
    vec3 apex = vec3(wedge.rays[0].w, wedge.rays[1].w, wedge.rays[2].w);
    vec2 rmin = vec2(1.0), rmax = vec2(-1.0);
    for (int c = 0; c < 6; ++c) {
        vec4 world = reach > 0.0 && c >= 2 ? vec4(apex + reach * wedge.rays[c - 2].xyz, 1.0)
                     : reach > 0.0         ? vec4(apex, 1.0)
                     : c >= 2              ? vec4(wedge.rays[c - 2].xyz, 0.0)
                     : c == 0              ? vec4(wedge.e0.xyz, 1.0)
                                           : vec4(wedge.e1.xyz, 1.0);
        vec4 clip = frame.viewProj * world;
        if (!(clip.w > 0.0)) return vec4(-1.0, -1.0, 1.0, 1.0);
        rmin = min(rmin, clip.xy / clip.w);
        rmax = max(rmax, clip.xy / clip.w);
    }
    return vec4(max(rmin, vec2(-1.0)), min(rmax, vec2(1.0)));
}
#endif

#if WEDGE_TILES_STAGE == 1 || WEDGE_TILES_STAGE == 3
#define WEDGE_SUPERTILE 32              // pixels per super-tile side (4 x 4 tiles)

// Whether a surface box [lo, hi] (lo.x > hi.x: no surface) may hold a pixel the wedge changes.
bool boundsMayHold(TileWedge w, vec4 lo, vec4 hi) {
    if (lo.x > hi.x) return false; // no surface
    return tileWedgeKind(w) == WEDGE_FULLSCREEN || boxMayMeetHull(w.planes, lo.xyz, hi.xyz);
}

#endif

void main() {
    int T = uTiles.x * uTiles.y;
#if WEDGE_TILES_STAGE == 2
    // The prefix sum in three steps (uScanStep), so that no invocation loops over more than a
    // row or a column of tiles (WEDGE_TILES_LOOP_BUDGET): 0, per row, the offsets within the
    // row and the row's total (kept in the cursor of its first tile); 1, one invocation, the
    // rows' offsets (in the same place) and the total; 2, per row, first entries and cursors.
    int row = int(gl_GlobalInvocationID.x);
    if (uScanStep == 1) {
        if (row != 0) return;
        uint total = 0u, overflow = heads[3 * T + WEDGE_TILES_OVERFLOW];
        for (int y = 0; y < uTiles.y; ++y) {
            uint c = heads[2 * T + y * uTiles.x];
            heads[2 * T + y * uTiles.x] = total;
            if (total + c < total) overflow = 1u;
            total += c;
        }
        heads[3 * T + WEDGE_TILES_TOTAL] = total;
        heads[3 * T + WEDGE_TILES_OVERFLOW] = overflow;
        return;
    }
    if (row >= uTiles.y) return;
    int t0 = row * uTiles.x;
    if (uScanStep == 0) {
        uint total = 0u;
        for (int x = 0; x < uTiles.x; ++x) {
            uint c = heads[t0 + x];
            heads[T + t0 + x] = total;
            if (total + c < total) atomicOr(heads[3 * T + WEDGE_TILES_OVERFLOW], 1u);
            total += c;
        }
        heads[2 * T + t0] = total;
    } else {
        uint offset = heads[2 * T + t0];
        for (int x = 0; x < uTiles.x; ++x) {
            uint first = heads[T + t0 + x] + offset;
            if (first < offset) atomicOr(heads[3 * T + WEDGE_TILES_OVERFLOW], 1u);
            heads[T + t0 + x] = first;
            heads[2 * T + t0 + x] = first;
            if (heads[t0 + x] != 0u) {
                uint at = atomicAdd(heads[3 * T + WEDGE_TILES_ACTIVE], 1u);
                heads[3 * T + WEDGE_TILES_HEADER + at] = uint(t0 + x);
            }
        }
    }
#elif WEDGE_TILES_STAGE == 4
    // One invocation per recorded entry (rows of work groups: gl_NumWorkGroups.x wide).
    uint k = (gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x) * 64u +
             gl_LocalInvocationIndex;
    if (k >= heads[3 * T + WEDGE_TILES_RECORDED]) return;
    uint t = tilePairs[3u * k + 1u];
    heads[uListBase + heads[T + t] + tilePairs[3u * k + 2u]] = tilePairs[3u * k];
#else
#if WEDGE_TILES_STAGE == 0
    uint index = gl_GlobalInvocationID.x;
#else
    // The count and fill stages: each work group takes WEDGE_TILES_SLOT_GROUP consecutive slots
    // (neighbours on a mesh, whose rectangles are alike: a SIMD vector of them waits less for
    // its largest), the groups from all over the list (shared/Spread.h: the slots are listed
    // caster by caster, and a slot's cost, the tiles of its rectangle, follows the caster's
    // size on screen). Measured on spheres-nine, 256²: the count stage 10.6-13.5 ms on two
    // threads where one slot per invocation in groups of 64, in list order, took 18-26 ms with
    // the second thread idle for a third of it; groups of 8 took 19-20 ms, of 32 14 ms.
    const uint size = WEDGE_TILES_SLOT_GROUP;
    uint groups = (uRun.y + size - 1u) / size;
    uint group = gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x;
    if (group >= groups) return;
    uint index = spreadIndex(group, groups, uSpread) * size + gl_LocalInvocationIndex;
#endif
    if (index >= uRun.y) return;
    uint slot = heads[uRun.x + index];
#if WEDGE_TILES_STAGE == 0
    GpuWedge wedge = wedges[slot];
    TileWedge w;
    w.e0 = vec4(wedge.e0.xyz, uintBitsToFloat(wedge.kind));
    w.e1 = vec4(wedge.e1.xyz, uintBitsToFloat(wedge.eyeInside));
    // A full-screen wedge's planes let every point through (the evaluation's first test; its
    // rectangle decides after).
    for (int i = 0; i < 4; ++i)
        w.planes[i] = wedge.kind == WEDGE_FULLSCREEN ? vec4(0.0, 0.0, 0.0, -1.0) : wedge.planes[i];
    GpuEdge edge = edges[wedge.edge]; // a twin slot's edge is another slot's
    uvec2 apex = edgeApexes[wedge.edge];
    trianglePlane(edge.v0, edge.v1, apex.x, w.tri0);
    trianglePlane(edge.v0, edge.v1, apex.y, w.tri1);
    w.tiles = ivec4(0, 0, -1, -1);
    w.bound = vec4(0.0, 0.0, 0.0, -1.0);
    float reach = wedge.rays[3].w;
    if (wedge.kind == WEDGE_BOUNDED && reach > 0.0) {
        // (wedgeHullTruncateCone's l, from the stored directions)
        // The cut cone's far face through apex + reach g (wedgeHullTruncateCone): l with
        // dot(l, g) = 1 for its three directions (slots 0 and 2, or 1 and 3, hold one of them).
        vec3 apex = vec3(wedge.rays[0].w, wedge.rays[1].w, wedge.rays[2].w);
        bool nearE1 = wedge.rays[0].xyz == wedge.rays[2].xyz;
        vec3 ga = nearE1 ? wedge.rays[0].xyz : wedge.rays[1].xyz;
        vec3 gb = nearE1 ? wedge.rays[1].xyz : wedge.rays[0].xyz;
        vec3 gc = nearE1 ? wedge.rays[3].xyz : wedge.rays[2].xyz;
        vec3 l = (cross(gb, gc) + cross(gc, ga) + cross(ga, gb)) / dot(ga, cross(gb, gc));
        w.bound = vec4(l, -dot(l, apex) - reach);
    }
    if (wedge.kind == WEDGE_BOUNDED || wedge.kind == WEDGE_FULLSCREEN) {
        // What the raster pass covers: a full-screen wedge's triangle over its group's
        // influence rectangle (taken as that rectangle), a bounded hull's own corners.
        vec4 r = wedge.kind == WEDGE_FULLSCREEN
                     ? screenRect(groups[wedge.group].influenceMin.xyz, groups[wedge.group].influenceMax.xyz)
                     : hullScreenRect(wedge);
        if (wedge.kind == WEDGE_FULLSCREEN) w.bound = r;
        // Pixels whose centres may lie in r (one more each side for rounding), as tiles.
        vec2 lo = floor((r.xy * 0.5 + 0.5) * vec2(uSize) - 0.5) - 1.0;
        vec2 hi = ceil((r.zw * 0.5 + 0.5) * vec2(uSize) - 0.5) + 1.0;
        ivec2 p0 = clamp(ivec2(lo), ivec2(0), uSize - 1);
        ivec2 p1 = clamp(ivec2(hi), ivec2(0), uSize - 1);
        if (r.x <= r.z && r.y <= r.w) w.tiles = ivec4(p0 / WEDGE_TILE, p1 / WEDGE_TILE);
    }
    tileWedges[slot] = w;
#else
    TileWedge w = tileWedges[slot];
    // Super-tiles of the rectangle first, then their tiles, each against its surface box.
    const int per = WEDGE_SUPERTILE / WEDGE_TILE;
    int superX = (uSize.x + WEDGE_SUPERTILE - 1) / WEDGE_SUPERTILE;
    int budget = WEDGE_TILES_LOOP_BUDGET;
    for (int sy = w.tiles.y / per; sy <= w.tiles.w / per && budget > 0; ++sy)
        for (int sx = w.tiles.x / per; sx <= w.tiles.z / per && budget > 0; ++sx) {
            budget -= 1;
            int s = sy * superX + sx;
            if (!boundsMayHold(w, supertileBounds[2 * s], supertileBounds[2 * s + 1])) continue;
            budget -= per * per;
            for (int ty = max(w.tiles.y, sy * per); ty <= min(w.tiles.w, sy * per + per - 1); ++ty)
                for (int tx = max(w.tiles.x, sx * per); tx <= min(w.tiles.z, sx * per + per - 1); ++tx) {
                    int t = ty * uTiles.x + tx;
                    if (!boundsMayHold(w, tileBounds[2 * t], tileBounds[2 * t + 1])) continue;
#if WEDGE_TILES_STAGE == 1
                    uint at = atomicAdd(heads[t], 1u);
                    uint k = atomicAdd(heads[3 * T + WEDGE_TILES_RECORDED], 1u);
                    if (k < uPairCapacity) {
                        tilePairs[3u * k] = slot;
                        tilePairs[3u * k + 1u] = uint(t);
                        tilePairs[3u * k + 2u] = at;
                    }
#else
                    uint at = atomicAdd(heads[2 * T + t], 1u);
                    heads[uListBase + at] = slot;
#endif
                }
        }
#if WEDGE_TILES_STAGE == 1
    // (the fill stage stops at the same place: the same lists, to be thrown away)
    if (budget <= 0) atomicAdd(heads[3 * T + WEDGE_TILES_TRUNCATED], 1u);
#endif
#endif
#endif
}
