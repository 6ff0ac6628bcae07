// wedges-blend (Forest, Barthe & Paulin 2006): a visibility buffer per silhouette group with the
// light split into R radial parts, blended into the final buffer with an overlap correction per
// part. The arithmetic is the CPU model's (geometry/models/BlendModel.h), and so are the parameters
// (gpu/Methods.h; defaults: the paper's): parts R = 1 | 4 | 8, bits = 8 | 16 (the packing of the
// stored states), overlap = paper (E = (A_f / B_f) (A_s / B_s) b) | centroid (linear densities
// through stored centroids). Per batch of groups that cannot interact on screen
// (GroupBatches.h), scissored to the batch:
// - the groups' own z-fail volumes into the stencil (the centre's state C of each group);
// - their wedges accumulate, per part, the signed coverage, the corner windings and (centroid)
//   the first moments (ADD) and the clipped edge bounds (MIN) in float targets
//   (shaders/wedge-parts.frag): sums and minima need no read-modify-write, so any fragment
//   order gives the same result;
// - where they touched (the stencil mark), shaders/blend-parts.frag resolves each part (vCoef =
//   clamp(C + coverage), rectangle = edge bounds ∪ occluded corners, centroid), stores it
//   packed and blends it into the final state, packed too, in RGBA32UI targets read and written
//   by the same pass: each pixel is written once per draw, after glTextureBarrier (DESIGN.md
//   §4); in the groups' umbra, where no wedge reached, the same pass blends the full occlusion
//   the empty sums resolve to with C = 1.
// Layout, against the slides' 4 targets of (rect, vCoef + edge max X/Y): the per-silhouette sums
// stay in float (signed running sums would gather one rounding per edge), and the rectangle is
// closed with occluded corners instead of edge maxima (BlendModel.h explains why); only the
// stored states are packed.
//
// The parts go in *sets* of at most four: R = 1 is one set of one part, R = 4 one set of four,
// R = 8 two sets of four (parts 0-3: quadrants 0, 1; parts 4-7: quadrants 2, 3), the wedge and
// blend draws of a batch done once per set (a uniform tells the wedge program which). The final
// states of different parts never meet, so this is exact, and one set fits llvmpipe's 8 colour
// attachments with the fixed-function blending of WedgePass (targets 0-3 ADD, 4-7 MIN):
//   set of 4: 0 coverage, 1 windings, 2 moment x, 3 moment y (centroid only), 4-7 bounds of part
//             0-3 (min x, min y, -max x, -max y);
//   set of 1: 0 (coverage, windings, moment x, moment y), 4 bounds;
// one float per part for all its corner windings: Σ_j 16^j w_j over its corners that are not the
// centre (3 at R = 4, 2 at R = 8, 4 at R = 1), exact while each corner's sum stays in [-8, 7]
// (planar groups: 0 or ±1). Unused targets are not attached (draw buffer NONE). The final state
// of a set: 2 targets at 8 bits (rect; vCoef | centroid << 8), 4 at 16 (rect min, rect max,
// vCoef | centroid x << 16, centroid y), one component per part (R = 1: R32UI). R = 8 draws the
// batch's wedges twice (the wedge-fragment counter counts the first set's draw only).
#include "engine/DebugViews.h"
#include "engine/Method.h"
#include "passes/FullscreenPass.h"
#include "passes/StencilVolumePass.h"
#include "passes/WedgePass.h"
#include "engine/ShaderBindings.h"
#include "passes/VolumeStates.h"
#include "engine/MethodOptions.h"
#include "methods/SilhouetteBatchMethod.h"
#include "methods/MethodUtil.h"

#include <array>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace gpu {

namespace {

constexpr GLint kPartSetLocation = 1; // shaders/wedge-parts.frag uPartSet (R = 8)
constexpr int kPartTargets = 8;
constexpr int kMaxFinalTargets = 4;
constexpr int kMaxSets = 2;

// The method's parameters and the layout they give (the comment at the top of this file).
// The method's options (engine/MethodOptions.h) and what follows from them.
struct BlendLayout : BlendOptions {

    int sets() const { return parts == 8 ? 2 : 1; }
    int finalTargets() const { return bits == 16 ? 4 : 2; }
    // Whether per-part accumulation target i is used (attached).
    bool usesPartTarget(int i) const {
        if (parts == 1) return i == 0 || i == 4;
        if (i == 2 || i == 3) return centroid;
        return true;
    }
    // The target holding vCoef in a set's final state.
    int coefTarget() const { return bits == 16 ? 2 : 1; }
    std::vector<std::string> defines() const {
        return {"BLEND_PARTS " + std::to_string(parts), "BLEND_BITS " + std::to_string(bits),
                std::string("BLEND_CENTROID ") + (centroid ? "1" : "0")};
    }
};

BlendLayout blendLayout(std::span<const ParameterValue> parameters) {
    return {blendOptions(parameters)};
}

// The "empty" values the targets are cleared to: per-part accumulation target i (sums 0, bounds
// the empty rectangle (1, 1, 0, 0) in their min form, (1, 1, -0, -0)), and final-state target i
// (nothing occluded: the empty rectangle packed, vCoef 0).
std::array<float, 4> emptyPartValue(int target) {
    return target < 4 ? std::array<float, 4>{0, 0, 0, 0} : std::array<float, 4>{1, 1, 0, 0};
}
std::array<GLuint, 4> emptyFinalValue(const BlendLayout& layout, int target) {
    // 8 bits: (1, 1, 0, 0) = min 255 | 255 << 8, max 0; 16 bits: min x | min y << 16 = all ones.
    const GLuint emptyRectMin = layout.bits == 16 ? 0xFFFFFFFFu : 0x0000FFFFu;
    const GLuint v = target == 0 ? emptyRectMin : 0u;
    return {v, v, v, v};
}

class BlendWedgesMethod final : public SilhouetteBatchMethod {
public:
    explicit BlendWedgesMethod(const MethodResources& r)
        : BlendWedgesMethod(r, blendLayout(r.parameters)) {}

    BlendWedgesMethod(const MethodResources& r, const BlendLayout& layout)
        : SilhouetteBatchMethod(r.shaders,
                                WedgePass(r.shaders, WedgePass::Output::Parts4, layout.defines())),
          mLayout(layout),
          mBlend(r.shaders, "blend-parts.frag", "blend-parts", PipelineState{}, mLayout.defines()),
          mReset(r.shaders, "silhouette-reset.frag", "silhouette-reset", PipelineState{}),
          mResolve(r.shaders, "blend-resolve.frag", "blend-resolve", PipelineState{},
                   mLayout.defines()),
          mShaders(r.shaders) {}

    void resize(int width, int height) override {
        std::vector<FramebufferAttachment> parts;
        std::array<GLenum, kPartTargets> drawBuffers{};
        for (int i = 0; i < kPartTargets; ++i) {
            drawBuffers[i] = GL_NONE;
            mParts[i] = Texture();
            if (!mLayout.usesPartTarget(i)) continue;
            mParts[i] = Texture({.width = width, .height = height, .format = GL_RGBA32F,
                                 .label = "blend-parts"});
            parts.push_back({GLenum(GL_COLOR_ATTACHMENT0 + i), &mParts[i]});
            drawBuffers[i] = GLenum(GL_COLOR_ATTACHMENT0 + i);
        }
        mPartsFbo = Framebuffer({.attachments = parts, .label = "blend-parts"});
        mPartsFbo.setDrawBuffers(drawBuffers); // output location i -> attachment i, or none
        const GLenum finalFormat = mLayout.parts == 1 ? GL_R32UI : GL_RGBA32UI;
        for (int set = 0; set < mLayout.sets(); ++set) {
            std::vector<FramebufferAttachment> finals;
            for (int i = 0; i < mLayout.finalTargets(); ++i) {
                mFinal[set][i] = Texture({.width = width, .height = height, .format = finalFormat,
                                          .label = "blend-final"});
                finals.push_back({GLenum(GL_COLOR_ATTACHMENT0 + i), &mFinal[set][i]});
            }
            mFinalFbo[set] = Framebuffer({.attachments = finals, .label = "blend-final"});
        }
        mDebugParts = Texture(); // the group-parts view's, made again on use
    }

    std::size_t targetBytesPerPixel() const override {
        std::size_t bytes = 16; // mDebugParts (RGBA32F), when the group-parts view is shown
        for (int i = 0; i < kPartTargets; ++i)
            bytes += mLayout.usesPartTarget(i) ? 16 : 0; // RGBA32F
        const std::size_t finalBytes = mLayout.parts == 1 ? 4 : 16; // R32UI or RGBA32UI
        return bytes + std::size_t(mLayout.sets() * mLayout.finalTargets()) * finalBytes;
    }

    void execute(const FrameContext& ctx) override {
        const Targets& t = ctx.targets;
        // The framebuffers share the frame's depth-stencil (recreated on resize).
        glNamedFramebufferTexture(mPartsFbo.id(), GL_DEPTH_STENCIL_ATTACHMENT,
                                  t.depthStencil.id(), 0);
        for (int set = 0; set < mLayout.sets(); ++set)
            glNamedFramebufferTexture(mFinalFbo[set].id(), GL_DEPTH_STENCIL_ATTACHMENT,
                                      t.depthStencil.id(), 0);
        applyState(PipelineState{}); // colour writes on, no scissor: whole-frame clears
        clearFinalState();

        clearPartTargets();
        runBatches(ctx, mPartsFbo);
        {
            ScopedPass pass(&ctx.timers, "resolve");
            glTextureBarrier();
            for (int set = 0; set < mLayout.sets(); ++set)
                glBindTextureUnit(TEXUNIT_FINAL0 + set, mFinal[set][mLayout.coefTarget()].id());
            mResolve.execute(t.visibilityFbo, t.width, t.height);
        }
    }

    bool drawDebug(DebugView view, const FrameContext& ctx, DebugViews& debug) override {
        if (view == DebugView::WedgeWireframe) return drawWedgeWireframe(ctx, mWedges, debug);
        if (view != DebugView::GroupParts) return false;
        drawGroupParts(ctx, debug);
        return true;
    }

private:
    void combine(const FrameContext& ctx, const GroupBatch& batch,
                 const TouchedStates& states) override {
        blendPartSets(ctx.targets, batch, states);
    }

    void reset(const FrameContext& ctx, const GroupBatch&, const PipelineState& stencil) override {
        resetPartTargets(ctx.targets, stencil);
    }

    void umbra(const FrameContext& ctx, const GroupBatch&, const UmbraStates& states) override {
        for (int set = 0; set < mLayout.sets(); ++set)
            blend(ctx.targets, set == mLayout.sets() - 1 ? states.zero : states.keep, set, true);
    }

    // The GroupParts debug view: group ctx.settings.debugGroup (wrapped) of the casters served,
    // alone: its own volume (the centre state C) and wedges (the per-part sums), then per part
    // the visibility 1 - clamp(C + coverage) that blend-parts.frag resolves, before any
    // blending, as the tiles of a mosaic (R = 1: the whole image, 4: 2x2, 8: 3x3).
    void drawGroupParts(const FrameContext& ctx, DebugViews& debug) {
        const Targets& t = ctx.targets;
        std::size_t total = 0;
        for (const std::uint32_t c : ctx.casterSubset) total += ctx.casters.frame(c).groups.size();
        if (total == 0) {
            debug.note = "group-parts: no silhouette groups this frame; showing the shaded image";
            return;
        }
        const long n = static_cast<long>(total);
        const long shown = ((ctx.settings.debugGroup % n) + n) % n;
        long k = shown;
        std::uint32_t caster = 0;
        for (const std::uint32_t c : ctx.casterSubset) {
            const long groups = static_cast<long>(ctx.casters.frame(c).groups.size());
            if (k < groups) {
                caster = c;
                break;
            }
            k -= groups;
        }
        const CasterRange& range = ctx.casters.range(caster);
        const geometry::SilhouetteGroup& group =
            ctx.casters.frame(caster).groups[static_cast<std::size_t>(k)];
        DrawSet set;
        set.add(range.firstTriangle + group.firstTriangle, group.triangleCount,
                range.firstEdge + group.firstEdge, group.edgeCount);

        if (!mDebugParts.id()) {
            mDebugParts = Texture({.width = t.width, .height = t.height, .format = GL_RGBA32F,
                                   .label = "debug-group-parts"});
            mDebugFbo = Framebuffer({.attachments = {{GL_COLOR_ATTACHMENT0, &mDebugParts}},
                                     .label = "debug-group-parts"});
            mDebugResolve.emplace(mShaders, "debug-group-parts.frag", "debug-group-parts",
                                  PipelineState{}, mLayout.defines());
        }
        glNamedFramebufferTexture(mDebugFbo.id(), GL_DEPTH_STENCIL_ATTACHMENT,
                                  t.depthStencil.id(), 0);
        clearStencil(t);
        ctx.casters.bind();
        mVolumes.drawCentre(t.visibilityFbo, t, set);
        const int grid = mLayout.parts == 1 ? 1 : mLayout.parts == 4 ? 2 : 3;
        const int perSet = mLayout.parts == 1 ? 1 : 4;
        debug.clearImage(t);
        for (int s = 0; s < mLayout.sets(); ++s) {
            applyState(PipelineState{}); // whole-frame clears
            clearPartTargets();
            if (mLayout.sets() > 1) glProgramUniform1i(mWedges.drawProgram(), kPartSetLocation, s);
            mWedges.draw(mPartsFbo, t, set, nullptr, /*markTouched=*/false,
                         /*countFragments=*/false);
            glBindTextureUnit(TEXUNIT_PARTS0, mParts[0].id());
            for (const bool occluded : {false, true}) {
                PipelineState state;
                state.stencilTest = true;
                state.stencilWriteMask = 0;
                state.stencilFront = {.func = GLenum(occluded ? GL_NOTEQUAL : GL_EQUAL),
                                      .ref = 0,
                                      .readMask = kStencilCountMask};
                state.stencilBack = state.stencilFront;
                mDebugResolve->execute(mDebugFbo, t.width, t.height, state,
                                       [&] { glUniform1f(0, occluded ? 1.0f : 0.0f); });
            }
            debug.drawPartTiles(t, mDebugParts, grid, perSet * s, perSet);
        }
        if (mLayout.sets() > 1) glProgramUniform1i(mWedges.drawProgram(), kPartSetLocation, 0);
        const std::string& object = ctx.scene.objects[ctx.casters.sceneObject(caster)].name;
        debug.note = "group-parts: group " + std::to_string(shown) + " of " +
                     std::to_string(total) + " (object '" + object + "', " +
                     std::to_string(group.edgeCount) + " edges" +
                     (boxOutsideFrustum(group.influenceBounds, ctx.viewProj)
                          ? ", outside the view: its wedges are culled"
                          : "") +
                     "): per-part visibility 1 - clamp(C + coverage) before blending, " +
                     (grid == 1 ? std::string("the whole light")
                                : std::to_string(mLayout.parts) + " parts as " +
                                      std::to_string(grid) + "x" + std::to_string(grid) +
                                      " tiles, part 0 top left");
    }

    void clearFinalState() {
        for (int set = 0; set < mLayout.sets(); ++set)
            for (int i = 0; i < mLayout.finalTargets(); ++i)
                glClearNamedFramebufferuiv(mFinalFbo[set].id(), GL_COLOR, i,
                                           emptyFinalValue(mLayout, i).data());
    }

    // The colour targets of the per-part accumulation, whole frame (once per frame: after that
    // every batch resets the pixels it touched, resetPartTargets).
    void clearPartTargets() {
        for (int i = 0; i < kPartTargets; ++i)
            if (mLayout.usesPartTarget(i))
                glClearNamedFramebufferfv(mPartsFbo.id(), GL_COLOR, i, emptyPartValue(i).data());
    }

    // The accumulation targets back to their empty values where `stencil` selects.
    void resetPartTargets(const Targets& t, const PipelineState& stencil) {
        mReset.execute(mPartsFbo, t.width, t.height, stencil, [&] {
            std::array<float, 4 * kPartTargets> empty{};
            for (int i = 0; i < kPartTargets; ++i)
                for (int c = 0; c < 4; ++c) empty[4 * i + c] = emptyPartValue(i)[c];
            glUniform4fv(0, kPartTargets, empty.data());
        });
    }

    // The batch's per-set sequence where its wedges touched (the layout at the top of this
    // file). Set 0's wedges were drawn by the batch loop; each further set resets the
    // accumulation targets there, draws the batch's wedges again for its own parts (the
    // stencil of the volumes and the marks stay) and blends them into its own final state.
    void blendPartSets(const Targets& t, const GroupBatch& batch, const TouchedStates& states) {
        for (int set = 0; set < mLayout.sets(); ++set) {
            if (set > 0) {
                resetPartTargets(t, states.touched);
                glProgramUniform1i(mWedges.drawProgram(), kPartSetLocation, set);
                mWedges.draw(mPartsFbo, t, batch.wedgeSet, &batch.rect, /*markTouched=*/false,
                             /*countFragments=*/false); // counted with set 0
            }
            blend(t, states.lit, set, false);
            blend(t, states.occluded, set, true);
        }
        if (mLayout.sets() > 1) glProgramUniform1i(mWedges.drawProgram(), kPartSetLocation, 0);
    }

    // Each part of the set of the batch's silhouette state into the set's final state
    // (blend-parts.frag), where `stencil` selects, with the group's centre state C given.
    void blend(const Targets& t, const PipelineState& stencil, int set, bool centreOccluded) {
        for (int i = 0; i < kPartTargets; ++i)
            if (mLayout.usesPartTarget(i)) glBindTextureUnit(TEXUNIT_PARTS0 + i, mParts[i].id());
        for (int i = 0; i < mLayout.finalTargets(); ++i)
            glBindTextureUnit(TEXUNIT_FINAL0 + i, mFinal[set][i].id());
        // The final state is read and written by this pass: every pixel once per draw, after
        // the barrier that makes the previous writes visible.
        glTextureBarrier();
        mBlend.execute(mFinalFbo[set], t.width, t.height, withStencil(PipelineState{}, stencil),
                       [&] { glUniform1f(0, centreOccluded ? 1.0f : 0.0f); });
    }

    BlendLayout mLayout;
    FullscreenPass mBlend, mReset, mResolve;
    std::array<Texture, kPartTargets> mParts;
    Framebuffer mPartsFbo;
    std::array<std::array<Texture, kMaxFinalTargets>, kMaxSets> mFinal;
    std::array<Framebuffer, kMaxSets> mFinalFbo;
    const ShaderLoader& mShaders;
    // The GroupParts debug view's (built on first use).
    std::optional<FullscreenPass> mDebugResolve;
    Texture mDebugParts; // per-part visibility of one set
    Framebuffer mDebugFbo;
};

} // namespace

std::unique_ptr<VisibilityMethod> createBlendWedgesMethod(const MethodResources& r) {
    return std::make_unique<BlendWedgesMethod>(r);
}

} // namespace gpu
