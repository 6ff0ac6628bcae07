// wedges-blend (Forest, Barthe & Paulin 2006): a visibility buffer per silhouette group with the
// light split into four radial parts (quadrants around its centre), blended into the final
// buffer with the overlap correction E = (A_f / B_f) (A_s / B_s) b per part. The arithmetic is
// the CPU model's (geometry/BlendModel.h: R = 4, Overlap::Paper, 8-bit storage). Per batch of
// groups that cannot interact on screen (GroupBatches.h), scissored to the batch:
// - the groups' own z-fail volumes into the stencil (the centre's state C of each group);
// - their wedges accumulate, per quadrant, the signed coverage and corner windings (ADD) and the
//   clipped edge bounds (MIN) in 8 float targets (shaders/wedge-parts.frag): sums and minima need
//   no read-modify-write, so any fragment order gives the same result;
// - where they touched (the stencil mark), shaders/blend-parts.frag resolves each quadrant
//   (vCoef = clamp(C + coverage), rectangle = edge bounds ∪ occluded corners), stores it at 8
//   bits and blends it into the final state (in the groups' umbra, where no wedge reached, the
//   same pass blends the full occlusion the empty sums resolve to with C = 1),
//   packed 8-bit four to a 32-bit scalar (rectangles: min x | min y | max x | max y rounded
//   outwards; vCoef), in two RGBA32UI targets read and written by the same pass: each pixel is
//   written once per draw, after glTextureBarrier (DESIGN.md §4).
// Layout, against the slides' 4 targets of (rect, vCoef + edge max X/Y): the per-silhouette sums
// stay in float (signed running sums would gather one 8-bit rounding per edge), and the rectangle
// is closed with occluded corners instead of edge maxima (BlendModel.h explains why); only the
// final state is packed.
#include "../Method.h"
#include "../passes/FullscreenPass.h"
#include "../passes/StencilVolumePass.h"
#include "../passes/WedgePass.h"
#include "../ShaderBindings.h"
#include "GroupBatches.h"
#include "MethodUtil.h"

#include <geometry/Error.h>

#include <array>

namespace gpu {

namespace {

constexpr std::uint32_t kEmptyRect8 = 0x0000FFFFu; // (1, 1, 0, 0): min 255, max 0

class BlendWedgesMethod final : public VisibilityMethod {
public:
    explicit BlendWedgesMethod(const MethodResources& r)
        : mVolumes(r.shaders), mWedges(r.shaders, WedgePass::Output::Parts4),
          mBlend(r.shaders, "blend-parts.frag", "blend-parts", PipelineState{}),
          mReset(r.shaders, "silhouette-reset.frag", "silhouette-reset", PipelineState{}),
          mResolve(r.shaders, "blend-resolve.frag", "blend-resolve", PipelineState{}) {
        if (parameterValue(r.parameters, "parts") != "4" ||
            parameterValue(r.parameters, "bits") != "8" ||
            parameterValue(r.parameters, "overlap") != "paper")
            throw geometry::InputError("wedges-blend: only parts=4, bits=8, overlap=paper run on "
                                       "the GPU yet");
    }

    void resize(int width, int height) override {
        std::vector<FramebufferAttachment> parts;
        for (int i = 0; i < 8; ++i) {
            mParts[i] = Texture({.width = width, .height = height, .format = GL_RGBA32F,
                                 .label = "blend-parts"});
            parts.push_back({GLenum(GL_COLOR_ATTACHMENT0 + i), &mParts[i]});
        }
        mPartsFbo = Framebuffer({.attachments = parts, .label = "blend-parts"});
        for (int i = 0; i < 2; ++i)
            mFinal[i] = Texture({.width = width, .height = height, .format = GL_RGBA32UI,
                                 .label = "blend-final"});
        mFinalFbo = Framebuffer({.attachments = {{GL_COLOR_ATTACHMENT0, &mFinal[0]},
                                                 {GL_COLOR_ATTACHMENT1, &mFinal[1]}},
                                 .label = "blend-final"});
    }

    void execute(const FrameContext& ctx) override {
        const Targets& t = ctx.targets;
        // Both framebuffers share the frame's depth-stencil (recreated on resize).
        glNamedFramebufferTexture(mPartsFbo.id(), GL_DEPTH_STENCIL_ATTACHMENT,
                                  t.depthStencil.id(), 0);
        glNamedFramebufferTexture(mFinalFbo.id(), GL_DEPTH_STENCIL_ATTACHMENT,
                                  t.depthStencil.id(), 0);
        const GLuint emptyRect[4] = {kEmptyRect8, kEmptyRect8, kEmptyRect8, kEmptyRect8};
        const GLuint zero4[4] = {0, 0, 0, 0};
        applyState(PipelineState{}); // colour writes on, no scissor: whole-frame clears
        glClearNamedFramebufferuiv(mFinalFbo.id(), GL_COLOR, 0, emptyRect);
        glClearNamedFramebufferuiv(mFinalFbo.id(), GL_COLOR, 1, zero4);

        const float sums[4] = {0, 0, 0, 0}, bounds[4] = {1, 1, 0, 0};
        for (int i = 0; i < 8; ++i)
            glClearNamedFramebufferfv(mPartsFbo.id(), GL_COLOR, i, i < 4 ? sums : bounds);
        runSilhouetteBatches(
            ctx, mVolumes, mWedges, mPartsFbo,
            {.combine =
                 [&](const GroupBatch&, const PipelineState& stencil, bool centreOccluded) {
                     blend(t, stencil, centreOccluded);
                 },
             .reset =
                 [&](const GroupBatch&, const PipelineState& stencil) {
                     mReset.execute(mPartsFbo, t.width, t.height, stencil, [&] {
                         float empty[8][4];
                         for (int i = 0; i < 8; ++i)
                             for (int c = 0; c < 4; ++c) empty[i][c] = i < 4 ? sums[c] : bounds[c];
                         glUniform4fv(0, 8, &empty[0][0]);
                     });
                 }});
        {
            ScopedPass pass(&ctx.timers, "resolve");
            glTextureBarrier();
            glBindTextureUnit(TEXUNIT_FINAL1, mFinal[1].id());
            mResolve.execute(t.visibilityFbo, t.width, t.height);
        }
    }

private:
    // Each quadrant of the batch's silhouette state into the final state (blend-parts.frag),
    // where `stencil` selects.
    void blend(const Targets& t, const PipelineState& stencil, bool centreOccluded) {
        for (int i = 0; i < 8; ++i) glBindTextureUnit(TEXUNIT_PARTS0 + i, mParts[i].id());
        glBindTextureUnit(TEXUNIT_FINAL0, mFinal[0].id());
        glBindTextureUnit(TEXUNIT_FINAL1, mFinal[1].id());
        // The final state is read and written by this pass: every pixel once per draw, after
        // the barrier that makes the previous writes visible.
        glTextureBarrier();
        mBlend.execute(mFinalFbo, t.width, t.height, withStencil(PipelineState{}, stencil),
                       [&] { glUniform1f(0, centreOccluded ? 1.0f : 0.0f); });
    }

    StencilVolumePass mVolumes;
    WedgePass mWedges;
    FullscreenPass mBlend, mReset, mResolve;
    std::array<Texture, 8> mParts;
    Framebuffer mPartsFbo;
    std::array<Texture, 2> mFinal;
    Framebuffer mFinalFbo;
};

} // namespace

std::unique_ptr<VisibilityMethod> createBlendWedgesMethod(const MethodResources& r) {
    return std::make_unique<BlendWedgesMethod>(r);
}

} // namespace gpu
