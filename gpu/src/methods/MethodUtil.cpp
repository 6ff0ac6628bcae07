#include "methods/MethodUtil.h"

#include "engine/DebugViews.h"
#include "engine/ShaderBindings.h"

#include "passes/FullscreenPass.h"
#include "passes/StencilVolumePass.h"
#include "passes/VolumeStates.h"
#include "passes/WedgePass.h"

namespace gpu {

VisibilityProduct::VisibilityProduct(const ShaderLoader& shaders, const char* label)
    : mMultiply(shaders, "blend-multiply.frag", label, kMultiplyState) {}

void VisibilityProduct::resize(int width, int height) {
    mSaved = Texture({.width = width, .height = height, .format = GL_R32F,
                      .label = "composed-visibility"});
}

void VisibilityProduct::beforeFactor(const FrameContext& ctx) {
    ScopedPass pass(&ctx.timers, "compose");
    const Targets& t = ctx.targets;
    glCopyImageSubData(t.visibility.id(), GL_TEXTURE_2D, 0, 0, 0, 0, mSaved.id(), GL_TEXTURE_2D,
                       0, 0, 0, 0, t.width, t.height, 1);
    const float zero = 0.0f;
    glClearTexImage(t.visibility.id(), 0, GL_RED, GL_FLOAT, &zero);
}

void VisibilityProduct::afterFactor(const FrameContext& ctx) {
    ScopedPass pass(&ctx.timers, "compose");
    const Targets& t = ctx.targets;
    glBindTextureUnit(TEXUNIT_SILHOUETTE, mSaved.id());
    mMultiply.execute(t.visibilityFbo, t.width, t.height, kMultiplyState,
                      [] { glUniform1f(0, 0.0f); }); // blend-multiply: clamp(0 + V)
}

void clearStencil(const Targets& t) {
    applyState(PipelineState{}); // all stencil bits writable, no scissor
    const int zero = 0;
    glClearNamedFramebufferiv(t.visibilityFbo.id(), GL_STENCIL, 0, &zero);
}

std::vector<CasterRange> casterRuns(const CasterSet& casters,
                                    std::span<const std::uint32_t> subset) {
    std::vector<CasterRange> runs;
    std::uint32_t previous = 0;
    for (std::size_t k = 0; k < subset.size(); ++k) {
        const CasterRange& r = casters.range(subset[k]);
        if (k > 0 && subset[k] == previous + 1) {
            CasterRange& last = runs.back();
            last.triangleCount += r.triangleCount;
            last.edgeCount += r.edgeCount;
            last.groupCount += r.groupCount;
        } else {
            runs.push_back(r);
        }
        previous = subset[k];
    }
    return runs;
}

void drawHardVisibility(const FrameContext& ctx, std::span<const CasterRange> runs,
                        StencilVolumePass& volumes, const AccumulatePass& accumulate,
                        const DrawSet* visible) {
    const Targets& t = ctx.targets;
    {
        ScopedPass pass(&ctx.timers, "shadow-volume");
        clearStencil(t);
        ctx.casters.bind();
        if (visible) {
            volumes.drawCentre(t.visibilityFbo, t, *visible);
        } else {
            for (const CasterRange& range : runs) volumes.drawCentre(t, range);
        }
    }
    ScopedPass pass(&ctx.timers, "accumulate");
    accumulate.execute(t.visibilityFbo, t.width, t.height);
}

bool boxOutsideFrustum(const geometry::Aabb& box, const glm::mat4& m) {
    auto row = [&](int j) { return glm::vec4(m[0][j], m[1][j], m[2][j], m[3][j]); };
    const glm::vec4 planes[5] = {row(3) + row(0), row(3) - row(0), row(3) + row(1),
                                 row(3) - row(1), row(3) - row(2)};
    for (const glm::vec4& p : planes) {
        // The corner farthest along the plane's normal: if even it is outside, all are.
        const glm::vec3 corner =
            glm::mix(box.min, box.max, glm::step(glm::vec3(0.0f), glm::vec3(p)));
        if (glm::dot(glm::vec3(p), corner) + p.w < 0.0f) return true;
    }
    return false;
}

std::uint32_t countCulledGroups(const FrameContext& ctx) {
    std::uint32_t culled = 0;
    for (const std::uint32_t c : ctx.casterSubset)
        for (const geometry::SilhouetteGroup& g : ctx.casters.frame(c).groups)
            culled += boxOutsideFrustum(g.influenceBounds, ctx.viewProj);
    return culled;
}

bool drawWedgeWireframe(const FrameContext& ctx, WedgePass& wedges, DebugViews& debug) {
    DrawSet set;
    std::uint32_t edges = 0;
    for (const CasterRange& r : casterRuns(ctx.casters, ctx.casterSubset)) {
        set.add(r);
        edges += r.edgeCount;
    }
    ctx.casters.bind();
    debug.drawWedgeLines(wedges, ctx.targets, set);
    debug.note = "wedges: " + std::to_string(edges) +
                 " wedge hulls as drawn (cyan; dim where behind a surface; full-screen wedges as "
                 "a triangle over their group's screen rectangle)";
    return true;
}

void addWedgeCounters(const FrameContext& ctx, const WedgeCounts& c,
                      std::span<const CasterRange> runs) {
    std::uint32_t edges = 0;
    for (const CasterRange& r : runs) edges += r.edgeCount;
    ctx.addCounter("wedges", edges);
    ctx.addCounter("wedges_bounded", c.bounded);
    ctx.addCounter("wedges_fullscreen", c.fullscreen);
    ctx.addCounter("wedges_degenerate", c.degenerate);
    ctx.addCounter("wedges_culled", c.culled);
    ctx.addCounter("wedges_camera_inside", c.eyeInside);
    ctx.addCounter("wedge_fragments", static_cast<double>(c.fragments));
}

} // namespace gpu
