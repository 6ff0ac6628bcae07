// wedges-multiply: a visibility buffer per silhouette group, combined as V = Π V_s (the
// independent-occluder combination; Forest et al. 2006 compare against it). Per batch of groups
// whose screen rectangles do not overlap (SilhouetteBatchMethod.h), scissored to
// the batch:
// - the groups' own z-fail volumes into the stencil (the centre's state);
// - their wedges subtract their edges' coverage from the silhouette target (0 elsewhere);
// - where they touched, the final V (cleared to 1) is multiplied by V_s = clamp(lit - Σ
//   coverage) (exact for one group: the additive method's arithmetic, with no other group in
//   the sum), and where only the volume reached (the group's umbra), by 0.
// The wedges of every group are built once per frame (one compute dispatch), not per batch.
#include "engine/DebugViews.h"
#include "engine/Method.h"
#include "passes/FullscreenPass.h"
#include "passes/StencilVolumePass.h"
#include "passes/WedgePass.h"
#include "engine/ShaderBindings.h"
#include "methods/SilhouetteBatchMethod.h"
#include "methods/MethodUtil.h"

namespace gpu {

namespace {

class MultiplyWedgesMethod final : public SilhouetteBatchMethod {
public:
    explicit MultiplyWedgesMethod(const MethodResources& r)
        : SilhouetteBatchMethod(r.shaders, WedgePass(r.shaders)),
          mMultiply(r.shaders, "blend-multiply.frag", "blend-multiply", kMultiplyState),
          mReset(r.shaders, "silhouette-reset.frag", "silhouette-reset", PipelineState{}) {}

    void resize(int width, int height) override {
        mSilhouette = Texture({.width = width, .height = height, .format = GL_R32F,
                               .label = "silhouette-visibility"});
        mSilhouetteFbo = Framebuffer({.attachments = {{GL_COLOR_ATTACHMENT0, &mSilhouette}},
                                      .label = "silhouette-visibility"});
    }

    std::size_t targetBytesPerPixel() const override { return 4; } // mSilhouette, R32F

    void execute(const FrameContext& ctx) override {
        const Targets& t = ctx.targets;
        // The silhouette target shares the frame's depth-stencil (volumes and the wedges'
        // depth test need it): attached here, since the frame's targets are recreated on resize.
        glNamedFramebufferTexture(mSilhouetteFbo.id(), GL_DEPTH_STENCIL_ATTACHMENT,
                                  t.depthStencil.id(), 0);
        const float one = 1.0f;
        glClearTexImage(t.visibility.id(), 0, GL_RED, GL_FLOAT, &one);

        const float zero = 0.0f;
        glClearTexImage(mSilhouette.id(), 0, GL_RED, GL_FLOAT, &zero);
        runBatches(ctx, mSilhouetteFbo);
    }

    bool drawDebug(DebugView view, const FrameContext& ctx, DebugViews& debug) override {
        return view == DebugView::WedgeWireframe && drawWedgeWireframe(ctx, mWedges, debug);
    }

private:
    void combine(const FrameContext& ctx, const GroupBatch&, const TouchedStates& states) override {
        multiply(ctx.targets, states.lit, 1.0f);
        multiply(ctx.targets, states.occluded, 0.0f);
    }

    void reset(const FrameContext& ctx, const GroupBatch&, const PipelineState& stencil) override {
        mReset.execute(mSilhouetteFbo, ctx.targets.width, ctx.targets.height, stencil, [&] {
            const float empty[4] = {0, 0, 0, 0};
            glUniform4fv(0, 1, empty);
        });
    }

    void umbra(const FrameContext& ctx, const GroupBatch&, const UmbraStates& states) override {
        multiply(ctx.targets, states.zero, 0.0f);
    }

    // V *= clamp(lit - Σ coverage) where `stencil` selects.
    void multiply(const Targets& t, const PipelineState& stencil, float lit) {
        glBindTextureUnit(TEXUNIT_SILHOUETTE, mSilhouette.id());
        mMultiply.execute(t.visibilityFbo, t.width, t.height, withStencil(kMultiplyState, stencil),
                          [&] { glUniform1f(0, lit); });
    }

    FullscreenPass mMultiply, mReset;
    Texture mSilhouette;
    Framebuffer mSilhouetteFbo;
};

} // namespace

std::unique_ptr<VisibilityMethod> createMultiplyWedgesMethod(const MethodResources& r) {
    return std::make_unique<MultiplyWedgesMethod>(r);
}

} // namespace gpu
