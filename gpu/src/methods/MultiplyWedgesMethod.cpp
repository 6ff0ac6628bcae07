// wedges-multiply: a visibility buffer per silhouette group, combined as V = Π V_s (the
// independent-occluder combination; Forest et al. 2006 compare against it). Per batch of groups
// whose screen rectangles do not overlap (GroupBatches.h), scissored to the batch:
// - the groups' own z-fail volumes into the stencil, V_s = 1 where the count is zero;
// - their wedges subtract their edges' coverage from V_s (exact for one group: the additive
//   method's arithmetic, with no other group in the sum);
// - the final V (cleared to 1) is multiplied by clamp(V_s).
// The wedges of every group are built once per frame (one compute dispatch), not per batch.
#include "../Method.h"
#include "../passes/FullscreenPass.h"
#include "../passes/StencilVolumePass.h"
#include "../passes/WedgePass.h"
#include "../ShaderBindings.h"
#include "GroupBatches.h"
#include "MethodUtil.h"

namespace gpu {

namespace {

constexpr PipelineState kMultiplyState{
    .blend = true,
    .blendSrc = GL_DST_COLOR, // final * V_s
    .blendDst = GL_ZERO,
};

class MultiplyWedgesMethod final : public VisibilityMethod {
public:
    explicit MultiplyWedgesMethod(const MethodResources& r)
        : mVolumes(r.shaders), mAccumulate(r.shaders), mWedges(r.shaders),
          mMultiply(r.shaders, "blend-multiply.frag", "blend-multiply", kMultiplyState) {}

    void resize(int width, int height) override {
        mSilhouette = Texture({.width = width, .height = height, .format = GL_R32F,
                               .label = "silhouette-visibility"});
        mSilhouetteFbo = Framebuffer({.attachments = {{GL_COLOR_ATTACHMENT0, &mSilhouette}},
                                      .label = "silhouette-visibility"});
    }

    void execute(const FrameContext& ctx) override {
        const Targets& t = ctx.targets;
        // The silhouette target shares the frame's depth-stencil (volumes and the wedges'
        // depth test need it): attached here, since the frame's targets are recreated on resize.
        glNamedFramebufferTexture(mSilhouetteFbo.id(), GL_DEPTH_STENCIL_ATTACHMENT,
                                  t.depthStencil.id(), 0);
        const float one = 1.0f;
        glClearTexImage(t.visibility.id(), 0, GL_RED, GL_FLOAT, &one);

        const int zeroStencil = 0;
        const float zero = 0.0f;
        runSilhouetteBatches(
            ctx, mVolumes, mWedges, mSilhouetteFbo,
            {.clear =
                 [&] {
                     glClearNamedFramebufferiv(mSilhouetteFbo.id(), GL_STENCIL, 0, &zeroStencil);
                     glClearNamedFramebufferfv(mSilhouetteFbo.id(), GL_COLOR, 0, &zero);
                 },
             .afterVolumes =
                 [&](const GroupBatch& batch) {
                     ScopedPass pass(&ctx.timers, "accumulate");
                     mAccumulate.execute(mSilhouetteFbo, t.width, t.height, &batch.rect);
                 },
             .combine =
                 [&](const GroupBatch& batch) {
                     glBindTextureUnit(TEXUNIT_SILHOUETTE, mSilhouette.id());
                     mMultiply.execute(t.visibilityFbo, t.width, t.height, &batch.rect);
                 }});
    }

private:
    StencilVolumePass mVolumes;
    AccumulatePass mAccumulate;
    WedgePass mWedges;
    FullscreenPass mMultiply;
    Texture mSilhouette;
    Framebuffer mSilhouetteFbo;
};

} // namespace

std::unique_ptr<VisibilityMethod> createMultiplyWedgesMethod(const MethodResources& r) {
    return std::make_unique<MultiplyWedgesMethod>(r);
}

} // namespace gpu
