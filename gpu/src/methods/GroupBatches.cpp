#include "GroupBatches.h"

#include "MethodUtil.h"

#include "../Method.h"
#include "../passes/StencilVolumePass.h"
#include "../passes/VolumeStates.h"
#include "../passes/WedgePass.h"

#include <algorithm>
#include <cmath>

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

GroupBatches batchGroups(const CasterSet& casters, std::span<const std::uint32_t> casterSubset,
                         const glm::mat4& viewProj, int width, int height, int tile) {
    GroupBatches out;
    std::vector<GroupRect> rects;
    for (const std::uint32_t c : casterSubset) {
        const auto& groups = casters.frame(c).groups;
        for (std::uint32_t g = 0; g < groups.size(); ++g) {
            GroupRect r{c, g, 0, 0, 0, 0};
            if (screenRect(groups[g].influenceBounds, viewProj, width, height, r))
                rects.push_back(r);
            else
                ++out.culledGroups;
        }
    }
    out.drawnGroups = static_cast<std::uint32_t>(rects.size());
    // Large rectangles first: they constrain the colouring most.
    std::stable_sort(rects.begin(), rects.end(), [](const GroupRect& a, const GroupRect& b) {
        return std::int64_t(a.x1 - a.x0) * (a.y1 - a.y0) > std::int64_t(b.x1 - b.x0) * (b.y1 - b.y0);
    });
    const int tilesX = (width + tile - 1) / tile, tilesY = (height + tile - 1) / tile;
    std::vector<std::vector<bool>> occupied; // per batch, per tile
    struct Bounds {
        int x0 = 1 << 30, y0 = 1 << 30, x1 = 0, y1 = 0;
    };
    std::vector<Bounds> bounds;
    for (const GroupRect& r : rects) {
        const int tx0 = r.x0 / tile, ty0 = r.y0 / tile;
        const int tx1 = (r.x1 - 1) / tile, ty1 = (r.y1 - 1) / tile;
        std::size_t b = 0;
        for (; b < occupied.size(); ++b) {
            bool free = true;
            for (int ty = ty0; ty <= ty1 && free; ++ty)
                for (int tx = tx0; tx <= tx1 && free; ++tx)
                    free = !occupied[b][static_cast<std::size_t>(ty * tilesX + tx)];
            if (free) break;
        }
        if (b == occupied.size()) {
            occupied.emplace_back(static_cast<std::size_t>(tilesX * tilesY), false);
            out.batches.emplace_back();
            bounds.emplace_back();
        }
        for (int ty = ty0; ty <= ty1; ++ty)
            for (int tx = tx0; tx <= tx1; ++tx)
                occupied[b][static_cast<std::size_t>(ty * tilesX + tx)] = true;
        GroupBatch& batch = out.batches[b];
        const CasterRange& range = casters.range(r.caster);
        const geometry::SilhouetteGroup& g = casters.frame(r.caster).groups[r.group];
        batch.set.add(range.firstTriangle + g.firstTriangle, g.triangleCount,
                      range.firstEdge + g.firstEdge, g.edgeCount);
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

namespace {

// Stencil states of the steps after the wedges (VolumeStates.h: count in bits 0-6, wedge mark in
// bit 7; the test is (ref & 0xFF) func (stencil & 0xFF)).
constexpr PipelineState stencilSelect(GLenum func, GLint ref, GLenum op) {
    PipelineState s;
    s.stencilTest = true;
    s.stencilWriteMask = 0xFF;
    s.stencilFront = {.func = func, .ref = ref, .depthPass = op};
    s.stencilBack = s.stencilFront;
    return s;
}
constexpr GLint kMark = GLint(kStencilWedgeMark);
constexpr PipelineState kTouchedLit = stencilSelect(GL_EQUAL, kMark, GL_KEEP); // == mark
constexpr PipelineState kTouchedOccluded = stencilSelect(GL_LESS, kMark, GL_KEEP); // > mark
constexpr PipelineState kTouched = stencilSelect(GL_LEQUAL, kMark, GL_KEEP);       // >= mark
constexpr PipelineState kTouchedReset = stencilSelect(GL_LEQUAL, kMark, GL_ZERO);  // >= mark
// After the reset only the untouched pixels with a non-zero count are left.
constexpr PipelineState kUmbraKeep = stencilSelect(GL_NOTEQUAL, 0, GL_KEEP);
constexpr PipelineState kUmbraZero = stencilSelect(GL_NOTEQUAL, 0, GL_ZERO);

PipelineState scissored(PipelineState s, const ScissorRect& rect) {
    s.scissor = true;
    s.scissorRect = rect;
    return s;
}

} // namespace

void runSilhouetteBatches(const FrameContext& ctx, StencilVolumePass& volumes, WedgePass& wedges,
                          const Framebuffer& target, const BatchSteps& steps) {
    const Targets& t = ctx.targets;
    auto t0 = Clock::now();
    const GroupBatches batches =
        batchGroups(ctx.casters, ctx.casterSubset, ctx.viewProj, t.width, t.height);
    ctx.addCpuTime("batching", msSince(t0));
    const std::vector<CasterRange> runs = casterRuns(ctx.casters, ctx.casterSubset);
    ctx.casters.bind();
    {
        ScopedPass pass(&ctx.timers, "wedge-setup");
        wedges.beginFrame(ctx.casters.edgeCount());
        wedges.setup(runs);
        clearStencil(t);
    }
    // Occlusion queries per batch around its combine draws (touched, umbra), read at the end:
    // reading each at once would stall the pipeline once per batch.
    std::vector<Query> touched, umbra;
    touched.reserve(batches.batches.size());
    umbra.reserve(batches.batches.size());
    std::uint64_t rectPixels = 0, groupPixels = 0;
    for (const GroupBatch& batch : batches.batches) {
        {
            ScopedPass pass(&ctx.timers, "shadow-volume");
            volumes.drawCentre(t.visibilityFbo, t, batch.set, &batch.rect);
        }
        {
            ScopedPass pass(&ctx.timers, "wedges");
            wedges.draw(target, t, batch.set, &batch.rect, /*markTouched=*/true);
        }
        {
            ScopedPass pass(&ctx.timers, "blend");
            touched.emplace_back(GL_SAMPLES_PASSED);
            glBeginQuery(GL_SAMPLES_PASSED, touched.back().id());
            steps.combine(batch, {scissored(kTouchedLit, batch.rect),
                                  scissored(kTouchedOccluded, batch.rect),
                                  scissored(kTouched, batch.rect)});
            glEndQuery(GL_SAMPLES_PASSED);
            steps.reset(batch, scissored(kTouchedReset, batch.rect));
            umbra.emplace_back(GL_SAMPLES_PASSED);
            glBeginQuery(GL_SAMPLES_PASSED, umbra.back().id());
            steps.umbra(batch, {scissored(kUmbraKeep, batch.rect),
                                scissored(kUmbraZero, batch.rect)});
            glEndQuery(GL_SAMPLES_PASSED);
        }
        rectPixels += batch.pixels;
        groupPixels += batch.groupPixels;
    }
    auto sum = [](const std::vector<Query>& queries) {
        std::uint64_t total = 0;
        for (const Query& q : queries) {
            GLuint64 samples = 0;
            glGetQueryObjectui64v(q.id(), GL_QUERY_RESULT, &samples);
            total += samples;
        }
        return total;
    };
    addWedgeCounters(ctx, wedges.counts(), runs);
    ctx.addCounter("groups_culled", batches.culledGroups);
    ctx.addCounter("groups_drawn", batches.drawnGroups);
    ctx.addCounter("batches", static_cast<double>(batches.batches.size()));
    ctx.addCounter("batch_rect_pixels", static_cast<double>(rectPixels));
    ctx.addCounter("group_rect_pixels", static_cast<double>(groupPixels));
    ctx.addCounter("pixels_blended", static_cast<double>(sum(touched)));
    ctx.addCounter("pixels_umbra", static_cast<double>(sum(umbra)));
}

} // namespace gpu
