#include "engine/DebugViews.h"

#include "engine/ShaderBindings.h"
#include "methods/MethodUtil.h"
#include "methods/ReferenceSampler.h"
#include "passes/StencilVolumePass.h"
#include "passes/VolumeStates.h"
#include "passes/WedgePass.h"

#include <geometry/scene/AlphaMask.h>
#include <geometry/core/Error.h>
#include <geometry/core/Sampling.h>

#include <algorithm>
#include <cstdio>

namespace gpu {

namespace {

constexpr float kDepthBias = 2e-3f; // relative distance (debug-edges.vert, wedge.vert)
constexpr glm::vec3 kEdgeColour{1.0f, 0.9f, 0.1f};
constexpr glm::vec3 kWedgeColour{0.2f, 1.0f, 0.9f};
// Lines behind the surface: dimmer for the wedge hulls, which run on to infinity below the
// receivers and would hide the picture.
constexpr float kHiddenEdgeAlpha = 0.3f;
constexpr float kHiddenHullAlpha = 0.12f;
constexpr glm::vec3 kBackground{0.10f, 0.14f, 0.35f}; // lib/Debug.glsl kDebugNoSurface
constexpr int kSumTile = 16;                            // debug-error-sum.comp

// Lines over the image: blended (hidden ones dim). No depth clamp, unlike the wedge pass: with
// it llvmpipe does not clip lines at w = 0, and hull edges towards directions behind the camera
// wrap around the screen (the wedge pass's triangles are discarded there by the hull test). With
// near and far clipping, points at infinity (depth 0) are on the far plane and kept.
constexpr PipelineState kLineState{
    .depthTest = true,
    .depthFunc = GL_GEQUAL, // reversed Z: at or in front of the surface
    .blend = true,
    .blendSrc = GL_SRC_ALPHA,
    .blendDst = GL_ONE_MINUS_SRC_ALPHA,
};

// Count class k of the low (count) bits of the stencil: EQUAL k, or for the last class every
// count above 2 (ref 2 LESS count).
PipelineState stencilClass(int k) {
    PipelineState s;
    s.stencilTest = true;
    s.stencilWriteMask = 0;
    s.stencilFront = {.func = GLenum(k < 3 ? GL_EQUAL : GL_LESS),
                      .ref = k < 3 ? k : 2,
                      .readMask = kStencilCountMask};
    s.stencilBack = s.stencilFront;
    return s;
}

const char* viewName(DebugView view) { return debugViewInfo(view).name.data(); }

} // namespace

DebugViews::DebugViews(const ShaderLoader& shaders) : mShaders(shaders) {}

DebugViews::~DebugViews() = default;

void DebugViews::resize(const Targets& t) {
    mOverlay = Framebuffer({.attachments = {{GL_COLOR_ATTACHMENT0, &t.image},
                                            {GL_DEPTH_STENCIL_ATTACHMENT, &t.depthStencil}},
                            .label = "debug-overlay"});
    // The reference restarts at the new size (its key holds the size); created on first use.
    mReference = Texture();
    mReferenceFbo = Framebuffer();
    mErrorKey.reset();
}

void DebugViews::draw(const FrameContext& ctx, VisibilityMethod& method,
                      std::string_view methodName) {
    const DebugView view = ctx.settings.debugView;
    note.clear();
    const std::string name = viewName(view);
    switch (view) {
    case DebugView::Shaded:
        return;
    case DebugView::Visibility:
        drawVisibility(ctx);
        note = "visibility: V of '" + std::string(methodName) +
               "' as grey (white lit, black umbra), no surface dark blue";
        break;
    case DebugView::SilhouetteEdges:
        drawSilhouettes(ctx);
        note = "silhouettes: " + std::to_string(ctx.casters.edgeCount()) +
               " directed edges from the light centre in " +
               std::to_string(ctx.casters.groupCount()) +
               " groups (yellow; dim where hidden)";
        break;
    case DebugView::StencilCount:
        drawStencil(ctx);
        note = "stencil: z-fail count from the light centre: grey 0 (lit), blue 1, green 2, "
               "red 3+";
        break;
    case DebugView::ErrorHeatMap:
        drawError(ctx);
        break;
    case DebugView::WedgeWireframe:
    case DebugView::GroupParts:
        if (!method.drawDebug(view, ctx, *this) && note.empty())
            note = name + ": method '" + std::string(methodName) +
                   (view == DebugView::WedgeWireframe
                        ? "' draws no wedges"
                        : "' has no per-silhouette part buffers (wedges-blend, or auto with "
                          "wedges=blend, has)") +
                   "; showing the shaded image";
        break;
    }
    // The baseline the shade pass leaves (fill mode, no tests), for whoever draws next (the
    // viewer's UI).
    applyState(PipelineState{});
}

void DebugViews::drawVisibility(const FrameContext& ctx) {
    if (!mVisibility)
        mVisibility.emplace(mShaders, "debug-visibility.frag", "debug-visibility",
                            PipelineState{});
    const Targets& t = ctx.targets;
    glBindTextureUnit(TEXUNIT_POSITION, t.position.id());
    glBindTextureUnit(TEXUNIT_VISIBILITY, t.visibility.id());
    mVisibility->execute(t.imageFbo, t.width, t.height);
}

void DebugViews::drawLines(const std::function<void(const PipelineState&)>& draw,
                           GLuint program, const glm::vec3& colour, bool polygons) {
    for (int visible = 0; visible < 2; ++visible) {
        PipelineState s = kLineState;
        s.depthFunc = visible ? GL_GEQUAL : GL_LESS;
        if (polygons) s.polygonMode = GL_LINE;
        glProgramUniform4f(program, 2, colour.r, colour.g, colour.b,
                           visible ? 1.0f : polygons ? kHiddenHullAlpha : kHiddenEdgeAlpha);
        draw(s);
    }
}

void DebugViews::drawSilhouettes(const FrameContext& ctx) {
    if (!mEdges)
        mEdges = mShaders.load({.stages = {{GL_VERTEX_SHADER, "debug-edges.vert"},
                                           {GL_FRAGMENT_SHADER, "debug-colour.frag"}},
                                .label = "debug-edges"});
    const Targets& t = ctx.targets;
    ctx.casters.bind();
    glProgramUniform1f(mEdges.id(), 1, kDepthBias);
    const GLsizei vertices = static_cast<GLsizei>(2 * ctx.casters.edgeCount());
    if (vertices == 0) return;
    drawLines(
        [&](const PipelineState& s) {
            applyState(s);
            glBindFramebuffer(GL_FRAMEBUFFER, mOverlay.id());
            glViewport(0, 0, t.width, t.height);
            glUseProgram(mEdges.id());
            glBindVertexArray(mEmptyVao.id());
            glDrawArrays(GL_LINES, 0, vertices);
        },
        mEdges.id(), kEdgeColour, false);
}

void DebugViews::drawWedgeLines(WedgePass& wedges, const Targets& t, const DrawSet& set) {
    if (!mWedgeLines)
        mWedgeLines = mShaders.load({.stages = {{GL_VERTEX_SHADER, "wedge.vert"},
                                                {GL_FRAGMENT_SHADER, "debug-colour.frag"}},
                                     .defines = {"WEDGE_DEPTH_BIAS " + std::to_string(kDepthBias)},
                                     .label = "debug-wedges"});
    drawLines([&](const PipelineState& s) { wedges.drawHulls(mOverlay, t, set, mWedgeLines.id(), s); },
              mWedgeLines.id(), kWedgeColour, true);
}

void DebugViews::clearImage(const Targets& t) {
    const float c[4] = {kBackground.r, kBackground.g, kBackground.b, 1.0f};
    glClearTexImage(t.image.id(), 0, GL_RGBA, GL_FLOAT, c);
}

void DebugViews::drawPartTiles(const Targets& t, const Texture& partVisibility, int grid,
                               int firstTile, int parts) {
    if (!mMosaic) mMosaic.emplace(mShaders, "debug-mosaic.frag", "debug-mosaic", PipelineState{});
    glBindTextureUnit(TEXUNIT_POSITION, t.position.id());
    glBindTextureUnit(TEXUNIT_DEBUG0, partVisibility.id());
    mMosaic->execute(t.imageFbo, t.width, t.height, PipelineState{}, [&] {
        glUniform1i(0, grid);
        glUniform1i(1, firstTile);
        glUniform1i(2, parts);
    });
}

void DebugViews::drawStencil(const FrameContext& ctx) {
    if (!mVolumes) mVolumes = std::make_unique<StencilVolumePass>(mShaders);
    if (!mStencilCount)
        mStencilCount.emplace(mShaders, "debug-stencil.frag", "debug-stencil", PipelineState{});
    const Targets& t = ctx.targets;
    // The `hard` method's volumes (every caster), whatever the method drew.
    clearStencil(t);
    ctx.casters.bind();
    for (const CasterRange& range : casterRuns(ctx.casters, ctx.casterSubset))
        mVolumes->drawCentre(t, range);
    glBindTextureUnit(TEXUNIT_POSITION, t.position.id());
    glBindTextureUnit(TEXUNIT_NORMAL, t.normal.id());
    for (int k = 0; k < 4; ++k)
        mStencilCount->execute(mOverlay, t.width, t.height, stencilClass(k),
                               [k] { glUniform1i(0, k); });
}

float DebugViews::referenceScale() const {
    return mSamplesDone > 0 ? static_cast<float>(mPattern.size()) / static_cast<float>(mSamplesDone)
                            : 0.0f;
}

void DebugViews::drawError(const FrameContext& ctx) {
    const RenderSettings& s = ctx.settings;
    const Targets& t = ctx.targets;
    if (!mSampler) mSampler = std::make_unique<ReferenceSampler>(mShaders);
    if (!mHeat) mHeat.emplace(mShaders, "debug-error.frag", "debug-error", PipelineState{});
    if (!mErrorSum)
        mErrorSum = mShaders.load(
            {.stages = {{GL_COMPUTE_SHADER, "debug-error-sum.comp"}}, .label = "debug-error-sum"});
    if (!mReference.id()) {
        mReference = Texture({.width = t.width, .height = t.height, .format = GL_R32F,
                              .label = "debug-reference"});
        mReferenceFbo = Framebuffer({.attachments = {{GL_COLOR_ATTACHMENT0, &mReference},
                                                     {GL_DEPTH_STENCIL_ATTACHMENT,
                                                      &t.depthStencil}},
                                     .label = "debug-reference"});
        const std::size_t tiles = static_cast<std::size_t>((t.width + kSumTile - 1) / kSumTile) *
                                  static_cast<std::size_t>((t.height + kSumTile - 1) / kSumTile);
        mSums = Buffer({.size = tiles * sizeof(glm::vec2), .flags = 0, .label = "debug-sums"});
        mErrorKey.reset();
    }

    const ErrorKey key{ctx.viewProj, ctx.light.center, ctx.light.u, ctx.light.v, t.width,
                       t.height,     s.samples,        s.seed};
    if (!mErrorKey || !(*mErrorKey == key)) {
        mErrorKey = key;
        mPattern = geometry::stratifiedSquare(s.samples, s.seed);
        mSamplesDone = 0;
        const float zero = 0.0f;
        glClearTexImage(mReference.id(), 0, GL_RED, GL_FLOAT, &zero);
    }
    const int total = static_cast<int>(mPattern.size());
    const int add = std::min(s.referenceSamplesPerFrame, total - mSamplesDone);
    if (add > 0) {
        // The `reference` method's passes and weights, a few samples per frame: once complete
        // the sum is its V bit for bit (same points, same order, same float additions).
        ctx.setAccumulationWeight(1.0f / static_cast<float>(total));
        for (int i = mSamplesDone; i < mSamplesDone + add; ++i) // ctx: every caster
            mSampler->add(ctx, ctx.light.point(mPattern[i].x, mPattern[i].y), mReferenceFbo);
        ctx.setAccumulationWeight(1.0f);
        mSamplesDone += add;
    }
    ctx.stats.referenceSamplesDone = mSamplesDone;

    const float refScale = referenceScale();
    glBindTextureUnit(TEXUNIT_POSITION, t.position.id());
    glBindTextureUnit(TEXUNIT_VISIBILITY, t.visibility.id());
    glBindTextureUnit(TEXUNIT_DEBUG0, mReference.id());
    mHeat->execute(t.imageFbo, t.width, t.height, PipelineState{}, [&] {
        glUniform1f(0, refScale);
        glUniform1f(1, s.errorScale);
    });

    // Mean |dV| over the surface pixels: per-tile sums on the GPU, the few tiles added here.
    const GLuint groupsX = static_cast<GLuint>((t.width + kSumTile - 1) / kSumTile);
    const GLuint groupsY = static_cast<GLuint>((t.height + kSumTile - 1) / kSumTile);
    glUseProgram(mErrorSum.id());
    glUniform1f(0, refScale);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BINDING_DEBUG_SUMS, mSums.id());
    glDispatchCompute(groupsX, groupsY, 1);
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    std::vector<glm::vec2> sums(static_cast<std::size_t>(groupsX) * groupsY);
    glGetNamedBufferSubData(mSums.id(), 0, static_cast<GLsizeiptr>(sums.size() * sizeof(glm::vec2)),
                            sums.data());
    double error = 0.0, pixels = 0.0;
    for (const glm::vec2& v : sums) {
        error += v.x;
        pixels += v.y;
    }
    char line[200];
    std::snprintf(line, sizeof line,
                  "error: |V - V_ref| (black 0, pale yellow >= %g); reference %d/%d samples%s, "
                  "mean |dV| %.4f",
                  static_cast<double>(s.errorScale), mSamplesDone, total,
                  mSamplesDone == total ? " (complete)" : "",
                  pixels > 0.0 ? error / pixels : 0.0);
    note = line;
    for (const std::uint32_t c : ctx.casterSubset)
        if (geometry::hasAlphaMask(ctx.scene.objects[ctx.casters.sceneObject(c)].mesh)) {
            note += "; the reference treats alpha-masked casters as opaque";
            break;
        }
}

} // namespace gpu
