// wedges-bitmask: per silhouette group, the set of the light's N samples it hides, as a bit
// mask; groups combine exactly, V = 1 - popcount(OR over groups) / N (geometry/LightMask.h).
// Per batch of groups that cannot interact on screen (GroupBatches.h), scissored to the batch:
// - the groups' own z-fail volumes into the stencil (the centre's state of each group);
// - their wedges XOR, per fragment, the samples their edge's region holds into the group mask
//   (shaders/wedge-bitmask.frag; the fixed-function logic op, so nothing is read back and the
//   order of the edges does not matter): the samples whose state differs from the centre's;
// - where they touched, the group mask (centre lit) or its complement (centre hidden) is ORed
//   into the final mask (shaders/bitmask-combine.frag, logic op OR); in the group's umbra,
//   where no wedge reached, every sample;
// - after the last batch, V from the final mask's popcount (shaders/bitmask-resolve.frag).
// Parity rather than signed counts per sample: logic ops give parity and OR for free, counts
// need a read-modify-write per fragment. Parity is exact while a group's projection from the
// receiver covers no sample twice (convex occluders, plates, most level geometry); where it
// folds (a torus seen obliquely) a sample behind two layers reads as lit (README: measured).
// Parameters (gpu/Methods.cpp): samples 32 | 64 | 128 | 256, the points of
// stratifiedSquare(N, seed) (the `reference` method's for the same N and seed) ordered by angle
// about the centre, so that a wedge fragment tests only the run of samples between its region's
// rays (found by bisection); pattern fixed | rotated (a shift per pixel: banding traded for
// noise; then every sample is tested). Targets: R32UI (32), RG32UI (64), RGBA32UI (128),
// 2 x RGBA32UI (256), for the group mask and the final mask each.
#include "../DebugViews.h"
#include "../Method.h"
#include "../passes/FullscreenPass.h"
#include "../passes/StencilVolumePass.h"
#include "../passes/WedgePass.h"
#include "../ShaderBindings.h"
#include "GroupBatches.h"
#include "MethodUtil.h"

#include <geometry/LightMask.h>

#include <array>
#include <string>
#include <string_view>
#include <vector>

namespace gpu {

namespace {

struct MaskLayout {
    int samples = 64;
    bool rotated = false;

    int targets() const { return samples > 128 ? 2 : 1; }
    GLenum format() const {
        return samples == 32 ? GL_R32UI : samples == 64 ? GL_RG32UI : GL_RGBA32UI;
    }
    std::size_t bytesPerTarget() const { return samples == 32 ? 4 : samples == 64 ? 8 : 16; }
    std::vector<std::string> defines() const {
        std::vector<std::string> d{"BITMASK_SAMPLES " + std::to_string(samples)};
        if (rotated) d.push_back("BITMASK_ROTATED 1");
        return d;
    }
};

MaskLayout maskLayout(std::span<const ParameterValue> parameters) {
    MaskLayout l;
    if (const std::string_view n = parameterValue(parameters, "samples"); !n.empty())
        l.samples = std::stoi(std::string(n));
    l.rotated = parameterValue(parameters, "pattern") == "rotated";
    return l;
}

// Logic ops on the integer targets (blending does not apply to them).
constexpr PipelineState kCombineState{.logicOp = true, .logicOpMode = GL_OR};

enum CombineMode : GLuint { kGroupMask = 0, kComplement = 1, kEverySample = 2 };

class BitmaskWedgesMethod final : public VisibilityMethod {
public:
    explicit BitmaskWedgesMethod(const MethodResources& r)
        : mLayout(maskLayout(r.parameters)), mSurface(r.shaders), mVolumes(r.shaders),
          mWedges(r.shaders, WedgePass::Output::Bitmask, mLayout.defines()),
          mCombine(r.shaders, "bitmask-combine.frag", "bitmask-combine", kCombineState,
                   mLayout.defines()),
          mClear(r.shaders, "bitmask-clear.frag", "bitmask-clear", PipelineState{}),
          mResolve(r.shaders, "bitmask-resolve.frag", "bitmask-resolve", PipelineState{},
                   mLayout.defines()),
          mSamples({.size = 0, .label = "light-samples"}) {}

    void resize(int width, int height) override {
        std::vector<FramebufferAttachment> group, final;
        for (int i = 0; i < mLayout.targets(); ++i) {
            mGroup[i] = Texture({.width = width, .height = height, .format = mLayout.format(),
                                 .label = "bitmask-group"});
            mFinal[i] = Texture({.width = width, .height = height, .format = mLayout.format(),
                                 .label = "bitmask-final"});
            group.push_back({GLenum(GL_COLOR_ATTACHMENT0 + i), &mGroup[i]});
            final.push_back({GLenum(GL_COLOR_ATTACHMENT0 + i), &mFinal[i]});
        }
        mGroupFbo = Framebuffer({.attachments = group, .label = "bitmask-group"});
        mFinalFbo = Framebuffer({.attachments = final, .label = "bitmask-final"});
        mWidth = width;
        mHeight = height;
    }

    std::size_t targetBytesPerPixel() const override {
        return 2 * std::size_t(mLayout.targets()) * mLayout.bytesPerTarget();
    }

    void execute(const FrameContext& ctx) override {
        const Targets& t = ctx.targets;
        uploadPattern(ctx.settings.seed);
        glNamedFramebufferTexture(mGroupFbo.id(), GL_DEPTH_STENCIL_ATTACHMENT,
                                  t.depthStencil.id(), 0);
        glNamedFramebufferTexture(mFinalFbo.id(), GL_DEPTH_STENCIL_ATTACHMENT,
                                  t.depthStencil.id(), 0);
        applyState(PipelineState{}); // colour writes on, no scissor: whole-frame clears
        const std::array<GLuint, 4> empty{0, 0, 0, 0};
        for (int i = 0; i < mLayout.targets(); ++i) {
            glClearNamedFramebufferuiv(mGroupFbo.id(), GL_COLOR, i, empty.data());
            glClearNamedFramebufferuiv(mFinalFbo.id(), GL_COLOR, i, empty.data());
        }
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BINDING_LIGHT_SAMPLES, mSamples.id());
        runSilhouetteBatches(
            ctx, mSurface, mVolumes, mWedges, mGroupFbo,
            {.combine =
                 [&](const GroupBatch&, const TouchedStates& states) {
                     combine(t, states.lit, kGroupMask);
                     combine(t, states.occluded, kComplement);
                 },
             .reset =
                 [&](const GroupBatch&, const PipelineState& stencil) {
                     mClear.execute(mGroupFbo, t.width, t.height, stencil, [] {});
                 },
             .umbra = [&](const GroupBatch&,
                          const UmbraStates& states) { combine(t, states.zero, kEverySample); }});
        {
            ScopedPass pass(&ctx.timers, "resolve");
            for (int i = 0; i < mLayout.targets(); ++i)
                glBindTextureUnit(TEXUNIT_FINAL0 + i, mFinal[i].id());
            mResolve.execute(t.visibilityFbo, t.width, t.height);
        }
        ctx.addCounter("light_samples", mLayout.samples);
    }

    bool drawDebug(DebugView view, const FrameContext& ctx, DebugViews& debug) override {
        return view == DebugView::WedgeWireframe && drawWedgeWireframe(ctx, mWedges, debug);
    }

    LightMasks lightMasks() const override {
        LightMasks m;
        m.samples = mLayout.samples;
        m.width = mWidth;
        m.height = mHeight;
        const int words = mLayout.samples / 32;
        m.words.assign(std::size_t(mWidth) * mHeight * words, 0u);
        std::vector<GLuint> texels;
        for (int i = 0; i < mLayout.targets(); ++i) {
            const int perTexel = std::min(4, words - 4 * i); // 1, 2 or 4 components
            texels.assign(std::size_t(mWidth) * mHeight * perTexel, 0u);
            const GLenum format = perTexel == 1 ? GL_RED_INTEGER
                                  : perTexel == 2 ? GL_RG_INTEGER
                                                  : GL_RGBA_INTEGER;
            glGetTextureImage(mFinal[i].id(), 0, format, GL_UNSIGNED_INT,
                              GLsizei(texels.size() * sizeof(GLuint)), texels.data());
            for (std::size_t px = 0; px < std::size_t(mWidth) * mHeight; ++px)
                for (int c = 0; c < perTexel; ++c)
                    m.words[px * words + 4 * i + c] = texels[px * perTexel + c];
        }
        return m;
    }

private:
    void uploadPattern(std::uint32_t seed) {
        if (mSamples.size() > 0 && seed == mSeed) return;
        // (s, t, angle about the centre, 0) per sample, in the pattern's angle order
        // (shaders/wedge-bitmask.frag finds the run between two rays by bisection).
        std::vector<glm::vec4> table;
        for (const glm::vec2 y : geometry::lightMaskPattern(mLayout.samples, seed))
            table.emplace_back(y, geometry::maskSampleAngle(y), 0.0f);
        mSamples = Buffer({.size = table.size() * sizeof(glm::vec4), .data = table.data(),
                           .flags = 0, .label = "light-samples"});
        mSeed = seed;
    }

    // The group masks into the final mask where `stencil` selects (bitmask-combine.frag).
    void combine(const Targets& t, const PipelineState& stencil, CombineMode mode) {
        for (int i = 0; i < mLayout.targets(); ++i)
            glBindTextureUnit(TEXUNIT_PARTS0 + i, mGroup[i].id());
        mCombine.execute(mFinalFbo, t.width, t.height, withStencil(kCombineState, stencil),
                         [&] { glUniform1ui(0, mode); });
    }

    MaskLayout mLayout;
    SurfaceTilePass mSurface;
    StencilVolumePass mVolumes;
    WedgePass mWedges;
    FullscreenPass mCombine, mClear, mResolve;
    Buffer mSamples;
    std::uint32_t mSeed = 0;
    std::array<Texture, 2> mGroup, mFinal;
    Framebuffer mGroupFbo, mFinalFbo;
    int mWidth = 0, mHeight = 0;
};

} // namespace

std::unique_ptr<VisibilityMethod> createBitmaskWedgesMethod(const MethodResources& r) {
    return std::make_unique<BitmaskWedgesMethod>(r);
}

} // namespace gpu
