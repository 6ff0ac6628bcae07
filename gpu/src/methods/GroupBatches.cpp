#include "methods/GroupBatches.h"

#include "methods/MethodUtil.h"

#include "engine/Method.h"
#include "engine/Targets.h"

#include <geometry/shadow/PotentialSilhouettes.h>
#include <geometry/shadow/ShadowCone.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace gpu {

namespace {

struct GroupRect {
    std::uint32_t caster, group;
    int x0, y0, x1, y1; // pixels, inclusive-exclusive
};

// Screen rectangle of a world box; false when the box misses the frustum. A box reaching behind
// the camera is clipped to the half-space in front of it (clip w >= kMinW): its rectangle bounds
// the corners in front and the points where the box's edges cross that plane (a convex set in
// front of the eye projects into the hull of its vertices' projections). Points near w = 0
// project far out and clamp to the screen's edge on their side, as they should.
constexpr float kMinW = 1e-6f;

bool screenRect(const geometry::Aabb& box, const glm::mat4& viewProj, int width, int height,
                GroupRect& r) {
    if (boxOutsideFrustum(box, viewProj)) return false;
    glm::vec2 lo(1e30f), hi(-1e30f);
    glm::vec4 clip[8];
    for (int c = 0; c < 8; ++c) {
        const glm::vec3 p((c & 1) ? box.max.x : box.min.x, (c & 2) ? box.max.y : box.min.y,
                          (c & 4) ? box.max.z : box.min.z);
        clip[c] = viewProj * glm::vec4(p, 1.0f);
    }
    auto add = [&](const glm::vec4& q) {
        const glm::vec2 ndc = glm::vec2(q) / q.w;
        lo = glm::min(lo, ndc);
        hi = glm::max(hi, ndc);
    };
    for (int c = 0; c < 8; ++c)
        if (clip[c].w >= kMinW) add(clip[c]);
    // The 12 edges: corners differing in one bit.
    for (int c = 0; c < 8; ++c)
        for (int bit = 1; bit < 8; bit <<= 1) {
            const int d = c | bit;
            if (d == c) continue;
            const float wa = clip[c].w, wb = clip[d].w;
            if ((wa >= kMinW) == (wb >= kMinW)) continue;
            const float t = (kMinW - wa) / (wb - wa);
            glm::vec4 q = clip[c] + t * (clip[d] - clip[c]);
            q.w = kMinW;
            add(q);
        }
    if (!(lo.x <= hi.x && lo.y <= hi.y)) return false; // nothing in front of the eye
    lo = glm::clamp(lo, glm::vec2(-1.0f), glm::vec2(1.0f));
    hi = glm::clamp(hi, glm::vec2(-1.0f), glm::vec2(1.0f));
    // One pixel of margin on each side: rasterisation rounds, the rectangle must not.
    r.x0 = std::max(0, static_cast<int>(std::floor((lo.x * 0.5f + 0.5f) * width)) - 1);
    r.y0 = std::max(0, static_cast<int>(std::floor((lo.y * 0.5f + 0.5f) * height)) - 1);
    r.x1 = std::min(width, static_cast<int>(std::ceil((hi.x * 0.5f + 0.5f) * width)) + 1);
    r.y1 = std::min(height, static_cast<int>(std::ceil((hi.y * 0.5f + 0.5f) * height)) + 1);
    return r.x1 > r.x0 && r.y1 > r.y0;
}


} // namespace

namespace {

bool overlaps(const geometry::Aabb& a, const geometry::Aabb& b) {
    return a.min.x <= b.max.x && b.min.x <= a.max.x && a.min.y <= b.max.y &&
           b.min.y <= a.max.y && a.min.z <= b.max.z && b.min.z <= a.max.z;
}

} // namespace

GroupBatches batchGroups(const CasterSet& casters, std::span<const std::uint32_t> casterSubset,
                         const glm::mat4& viewProj, int width, int height, int tile,
                         const SurfaceTiles* surface, const geometry::RectLight* light,
                         bool wedges) {
    GroupBatches out;
    const int tilesX = (width + tile - 1) / tile, tilesY = (height + tile - 1) / tile;
    const bool depthAware = surface && light;
    if (depthAware && (surface->tile != tile || surface->tilesX != tilesX ||
                       surface->tilesY != tilesY))
        throw std::logic_error("batchGroups: surface tiles of another grid");
    std::vector<TileSphere> spheres;
    if (depthAware) spheres = tileSpheres(*surface);

    // Per group its rectangle and its tiles (indices into the grid).
    std::vector<GroupRect> rects;
    std::vector<std::uint32_t> tileIndex; // every group's tiles, concatenated
    std::vector<std::uint32_t> tileStart; // per group in `rects`, then the end
    for (const std::uint32_t c : casterSubset) {
        const auto& groups = casters.frame(c).groups;
        for (std::uint32_t g = 0; g < groups.size(); ++g) {
            GroupRect r{c, g, 0, 0, 0, 0};
            if (!screenRect(groups[g].influenceBounds, viewProj, width, height, r)) {
                ++out.culledGroups;
                continue;
            }
            const auto first = static_cast<std::uint32_t>(tileIndex.size());
            const int tx0 = r.x0 / tile, ty0 = r.y0 / tile;
            const int tx1 = (r.x1 - 1) / tile, ty1 = (r.y1 - 1) / tile;
            if (!depthAware) {
                for (int ty = ty0; ty <= ty1; ++ty)
                    for (int tx = tx0; tx <= tx1; ++tx)
                        tileIndex.push_back(static_cast<std::uint32_t>(ty * tilesX + tx));
            } else {
                const geometry::SilhouetteGroup& group = groups[g];
                const geometry::ShadowCone cone = geometry::shadowCone(group.occluderBounds, *light);
                int kx0 = tilesX, ky0 = tilesY, kx1 = -1, ky1 = -1;
                for (int ty = ty0; ty <= ty1; ++ty)
                    for (int tx = tx0; tx <= tx1; ++tx) {
                        const auto i = static_cast<std::uint32_t>(ty * tilesX + tx);
                        const TileSphere& s = spheres[i];
                        if (s.box.empty() || !overlaps(s.box, group.influenceBounds) ||
                            !geometry::sphereMayMeetCone(cone, s.centre, s.radius))
                            continue;
                        tileIndex.push_back(i);
                        kx0 = std::min(kx0, tx), ky0 = std::min(ky0, ty);
                        kx1 = std::max(kx1, tx), ky1 = std::max(ky1, ty);
                    }
                if (kx1 < 0) {
                    ++out.hiddenGroups;
                    continue;
                }
                // The rectangle shrinks to its tiles (their pixels; the rectangle's margin was
                // inside the tiles it touched).
                r.x0 = std::max(r.x0, kx0 * tile);
                r.y0 = std::max(r.y0, ky0 * tile);
                r.x1 = std::min(r.x1, (kx1 + 1) * tile);
                r.y1 = std::min(r.y1, (ky1 + 1) * tile);
            }
            tileStart.push_back(first);
            rects.push_back(r);
        }
    }
    tileStart.push_back(static_cast<std::uint32_t>(tileIndex.size()));
    out.drawnGroups = static_cast<std::uint32_t>(rects.size());
    // Groups with many tiles first: they constrain the colouring most.
    std::vector<std::uint32_t> order(rects.size());
    for (std::uint32_t i = 0; i < order.size(); ++i) order[i] = i;
    std::stable_sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) {
        return tileStart[a + 1] - tileStart[a] > tileStart[b + 1] - tileStart[b];
    });
    std::vector<std::vector<bool>> occupied; // per batch, per tile
    struct Bounds {
        int x0 = 1 << 30, y0 = 1 << 30, x1 = 0, y1 = 0;
    };
    std::vector<Bounds> bounds;
    for (const std::uint32_t k : order) {
        const GroupRect& r = rects[k];
        const std::span<const std::uint32_t> tiles(tileIndex.data() + tileStart[k],
                                                   tileStart[k + 1] - tileStart[k]);
        std::size_t b = 0;
        for (; b < occupied.size(); ++b) {
            bool free = true;
            for (std::size_t i = 0; i < tiles.size() && free; ++i) free = !occupied[b][tiles[i]];
            if (free) break;
        }
        if (b == occupied.size()) {
            occupied.emplace_back(static_cast<std::size_t>(tilesX * tilesY), false);
            out.batches.emplace_back();
            bounds.emplace_back();
        }
        for (const std::uint32_t i : tiles) occupied[b][i] = true;
        GroupBatch& batch = out.batches[b];
        const CasterRange& range = casters.range(r.caster);
        const geometry::SilhouetteFrame& frame = casters.frame(r.caster);
        const geometry::SilhouetteGroup& g = frame.groups[r.group];
        batch.set.add(range.firstTriangle + g.firstTriangle, g.triangleCount,
                      range.firstEdge + g.firstEdge, g.edgeCount);
        if (!wedges) {
            // (no wedge set)
        } else if (!depthAware) {
            batch.wedgeSet.add(0, 0, range.firstEdge + g.firstEdge, g.edgeCount);
        } else {
            // Runs of consecutive edges whose cone meets one of the group's tiles.
            const auto positions = casters.topology(r.caster).positions();
            std::uint32_t runStart = 0, runLength = 0;
            for (std::uint32_t e = 0; e < g.edgeCount; ++e) {
                const geometry::SilhouetteEdge& edge = frame.edges[g.firstEdge + e];
                geometry::Aabb segment;
                segment.extend(positions[edge.v0]);
                segment.extend(positions[edge.v1]);
                const geometry::ShadowCone cone = geometry::shadowCone(segment, *light);
                bool reaches = false;
                for (std::size_t i = 0; i < tiles.size() && !reaches; ++i) {
                    const TileSphere& ts = spheres[tiles[i]];
                    reaches = geometry::sphereMayMeetCone(cone, ts.centre, ts.radius);
                }
                if (reaches) {
                    if (runLength == 0) runStart = e;
                    ++runLength;
                } else {
                    ++out.hiddenWedges;
                }
                if (runLength > 0 && (!reaches || e + 1 == g.edgeCount)) {
                    batch.wedgeSet.add(0, 0, range.firstEdge + g.firstEdge + runStart, runLength);
                    runLength = 0;
                }
            }
        }
        ++batch.groups;
        batch.groupPixels += std::uint64_t(r.x1 - r.x0) * std::uint64_t(r.y1 - r.y0);
        Bounds& u = bounds[b];
        u.x0 = std::min(u.x0, r.x0);
        u.y0 = std::min(u.y0, r.y0);
        u.x1 = std::max(u.x1, r.x1);
        u.y1 = std::max(u.y1, r.y1);
    }
    for (std::size_t b = 0; b < out.batches.size(); ++b) {
        GroupBatch& batch = out.batches[b];
        batch.rect = ScissorRect{bounds[b].x0, bounds[b].y0, bounds[b].x1 - bounds[b].x0,
                                 bounds[b].y1 - bounds[b].y0};
        batch.pixels = std::uint64_t(batch.rect.width) * std::uint64_t(batch.rect.height);
    }
    return out;
}

std::vector<std::uint8_t> segmentsReachingSurface(std::span<const glm::vec3> a,
                                                  std::span<const glm::vec3> b,
                                                  const geometry::Aabb& sceneBounds,
                                                  const SurfaceTiles& surface,
                                                  const geometry::RectLight& light,
                                                  const glm::mat4& viewProj, int width, int height) {
    const int tile = surface.tile;
    if (surface.tilesX != (width + tile - 1) / tile || surface.tilesY != (height + tile - 1) / tile)
        throw std::logic_error("segmentsReachingSurface: surface tiles of another grid");
    const std::vector<TileSphere> spheres = tileSpheres(surface);
    std::vector<std::uint8_t> reaches(a.size(), 0);
    for (std::size_t i = 0; i < a.size(); ++i) {
        geometry::Aabb segment;
        segment.extend(a[i]);
        segment.extend(b[i]);
        const geometry::Aabb influence =
            geometry::occluderInfluenceBounds(segment, light, sceneBounds);
        GroupRect r{0, 0, 0, 0, 0, 0};
        if (influence.empty() || !screenRect(influence, viewProj, width, height, r)) continue;
        const geometry::ShadowCone cone = geometry::shadowCone(segment, light);
        bool hit = false;
        for (int ty = r.y0 / tile; ty <= (r.y1 - 1) / tile && !hit; ++ty)
            for (int tx = r.x0 / tile; tx <= (r.x1 - 1) / tile && !hit; ++tx) {
                const TileSphere& t = spheres[static_cast<std::size_t>(ty * surface.tilesX + tx)];
                hit = !t.box.empty() && overlaps(t.box, influence) &&
                      geometry::sphereMayMeetCone(cone, t.centre, t.radius);
            }
        reaches[i] = hit ? 1 : 0;
    }
    return reaches;
}

// Below this many silhouette groups the surface tiles are not measured: the pass and the wait
// for the G-buffer it needs cost more than culling saves (demo.json, 512x512, hard: +3 ms
// on 18 with a handful of groups, nothing to cull), and the overlap scenes' few groups batch
// well by rectangles. Levels have hundreds to thousands.
constexpr std::size_t kDepthAwareMinGroups = 64;

bool depthAwareFrame(const FrameContext& ctx) {
    if (!ctx.settings.depthAwareCulling) return false;
    std::size_t groups = 0;
    for (const std::uint32_t c : ctx.casterSubset) groups += ctx.casters.frame(c).groups.size();
    return groups >= kDepthAwareMinGroups;
}

std::vector<TileSphere> tileSpheres(const SurfaceTiles& surface) {
    std::vector<TileSphere> spheres(surface.boxes.size());
    for (std::size_t i = 0; i < spheres.size(); ++i) {
        const geometry::Aabb& b = surface.boxes[i];
        if (b.empty()) continue;
        const float margin =
            1e-4f * (glm::length(b.max - b.min) + glm::length(glm::abs(b.min) + glm::abs(b.max))) +
            1e-6f;
        TileSphere& t = spheres[i];
        t.box.extend(b.min - glm::vec3(margin));
        t.box.extend(b.max + glm::vec3(margin));
        t.centre = 0.5f * (t.box.min + t.box.max);
        t.radius = 0.5f * glm::length(t.box.max - t.box.min);
    }
    return spheres;
}

SurfaceTiles measureSurface(const FrameContext& ctx, SurfaceTilePass& surface) {
    // Measured once a frame: a later path (auto's) takes the first one's.
    if (ctx.scratch && ctx.scratch->surfaceTiles &&
        ctx.scratch->surfaceTiles->tile == SurfaceTilePass::kTile)
        return *ctx.scratch->surfaceTiles;
    ScopedPass pass(&ctx.timers, "surface-tiles");
    const auto t0 = Clock::now();
    SurfaceTiles tiles = surface.measure(ctx.targets);
    ctx.addCpuTime("surface-tiles", msSince(t0)); // mostly the wait for the G-buffer
    if (ctx.scratch) ctx.scratch->surfaceTiles = std::make_shared<const SurfaceTiles>(tiles);
    return tiles;
}

namespace {

void append(DrawSet& to, const DrawSet& from) {
    to.triangleFirst.insert(to.triangleFirst.end(), from.triangleFirst.begin(),
                            from.triangleFirst.end());
    to.triangleCount.insert(to.triangleCount.end(), from.triangleCount.begin(),
                            from.triangleCount.end());
    to.edgeFirst.insert(to.edgeFirst.end(), from.edgeFirst.begin(), from.edgeFirst.end());
    to.edgeCount.insert(to.edgeCount.end(), from.edgeCount.begin(), from.edgeCount.end());
}

} // namespace

std::optional<VisibleSets> visibleSets(const FrameContext& ctx, SurfaceTilePass& surface,
                                       const geometry::RectLight& light, bool wedges) {
    if (!depthAwareFrame(ctx)) return std::nullopt;
    const SurfaceTiles tiles = measureSurface(ctx, surface);
    const auto t0 = Clock::now();
    // The batches' colouring is not needed here, only their sets (a few ms at most).
    const GroupBatches batches =
        batchGroups(ctx.casters, ctx.casterSubset, ctx.viewProj, ctx.targets.width,
                    ctx.targets.height, SurfaceTilePass::kTile, &tiles, &light, wedges);
    VisibleSets out;
    for (const GroupBatch& b : batches.batches) {
        append(out.volumes, b.set);
        append(out.wedges, b.wedgeSet);
    }
    ctx.addCpuTime("culling", msSince(t0));
    ctx.addCounter("groups_hidden", batches.hiddenGroups);
    if (wedges) ctx.addCounter("wedges_hidden", batches.hiddenWedges);
    return out;
}

} // namespace gpu
