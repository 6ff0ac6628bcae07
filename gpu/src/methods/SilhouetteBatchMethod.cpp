#include "methods/SilhouetteBatchMethod.h"

#include "engine/ShaderBindings.h"
#include "engine/Targets.h"
#include "methods/MethodUtil.h"
#include "passes/VolumeStates.h"

#include <utility>
#include <vector>

namespace gpu {

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


SilhouetteBatchMethod::SilhouetteBatchMethod(const ShaderLoader& shaders, WedgePass wedges)
    : mSurface(shaders), mVolumes(shaders), mWedges(std::move(wedges)) {}

void SilhouetteBatchMethod::runBatches(const FrameContext& ctx, const Framebuffer& target) {
    SurfaceTilePass& surface = mSurface;
    StencilVolumePass& volumes = mVolumes;
    WedgePass& wedges = mWedges;
    const Targets& t = ctx.targets;
    const bool depthAware = depthAwareFrame(ctx);
    const SurfaceTiles tiles = depthAware ? measureSurface(ctx, surface) : SurfaceTiles{};
    auto t0 = Clock::now();
    const GroupBatches batches =
        batchGroups(ctx.casters, ctx.casterSubset, ctx.viewProj, t.width, t.height,
                    SurfaceTilePass::kTile, depthAware ? &tiles : nullptr, &ctx.light);
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
    std::vector<Query> touchedQueries, umbraQueries;
    touchedQueries.reserve(batches.batches.size());
    umbraQueries.reserve(batches.batches.size());
    std::uint64_t rectPixels = 0, groupPixels = 0;
    for (const GroupBatch& batch : batches.batches) {
        {
            ScopedPass pass(&ctx.timers, "shadow-volume");
            volumes.drawCentre(t.visibilityFbo, t, batch.set, &batch.rect);
        }
        {
            ScopedPass pass(&ctx.timers, "wedges");
            wedges.draw(target, t, batch.wedgeSet, &batch.rect, /*markTouched=*/true);
        }
        {
            ScopedPass pass(&ctx.timers, "blend");
            touchedQueries.emplace_back(GL_SAMPLES_PASSED);
            glBeginQuery(GL_SAMPLES_PASSED, touchedQueries.back().id());
            combine(ctx, batch, {scissored(kTouchedLit, batch.rect),
                                  scissored(kTouchedOccluded, batch.rect),
                                  scissored(kTouched, batch.rect)});
            glEndQuery(GL_SAMPLES_PASSED);
            reset(ctx, batch, scissored(kTouchedReset, batch.rect));
            umbraQueries.emplace_back(GL_SAMPLES_PASSED);
            glBeginQuery(GL_SAMPLES_PASSED, umbraQueries.back().id());
            umbra(ctx, batch, {scissored(kUmbraKeep, batch.rect),
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
    ctx.addCounter("groups_hidden", batches.hiddenGroups);
    ctx.addCounter("wedges_hidden", batches.hiddenWedges);
    {
        double drawn = 0;
        for (const GroupBatch& b : batches.batches)
            for (GLsizei n : b.wedgeSet.edgeCount) drawn += n;
        ctx.addCounter("wedges_drawn", drawn);
    }
    ctx.addCounter("groups_drawn", batches.drawnGroups);
    ctx.addCounter("batches", static_cast<double>(batches.batches.size()));
    ctx.addCounter("batch_rect_pixels", static_cast<double>(rectPixels));
    ctx.addCounter("group_rect_pixels", static_cast<double>(groupPixels));
    ctx.addCounter("pixels_blended", static_cast<double>(sum(touchedQueries)));
    ctx.addCounter("pixels_umbra", static_cast<double>(sum(umbraQueries)));
}

} // namespace gpu
