// pcss: percentage-closer soft shadows (Fernando 2005), the shadow-map baseline:
// - frame (CPU, geometry::fitPcssFrame, redone when the light or the casters change): one
//   perspective map per side of the light that has receivers, from the light's centre along
//   ±n, fitted to the receivers (capped at a 71.6° half-angle), and the casters' near depth;
// - shadow pass (passes/PcssShadowPass): the casters into the maps, alpha-tested ones cut out;
// - lookup (pcss-lookup.frag): per G-buffer point, blocker search, penumbra width
//   w = lightSize (zReceiver - zBlocker) / zBlocker per light axis, percentage-closer filtering
//   over that rectangle; depth compared with the receiver's plane moved `bias` texels towards
//   the light; V times the light's share in front of the surface (`horizon`, as occlusion's).
//   V is written at every pixel.
// Receivers beyond the maps' cap (walls reaching the light's plane) get V = 1 and are counted
// (`pcss_pixels_outside`).
#include "engine/Method.h"
#include "engine/MethodOptions.h"
#include "engine/ShaderBindings.h"
#include "passes/FullscreenPass.h"
#include "passes/PcssShadowPass.h"

#include <geometry/shadow/PcssFrame.h>
#include <geometry/core/Sampling.h>

#include <string>
#include <vector>

namespace gpu {

namespace {

// Fixed seeds of the two sample patterns (geometry::scrambledNet): the same pattern every frame.
constexpr std::uint32_t kFilterPatternSeed = 0x5CC5u;
constexpr std::uint32_t kSearchPatternSeed = 0xB10Cu;

std::vector<std::string> lookupDefines(const PcssOptions& o) {
    std::vector<std::string> d = {"NORMAL_OFFSET " + o.bias};
    if (o.horizon) d.push_back("HORIZON");
    return d;
}

class PcssMethod final : public VisibilityMethod {
public:
    explicit PcssMethod(const MethodResources& r) : PcssMethod(r, pcssOptions(r.parameters)) {}

    PcssMethod(const MethodResources& r, const PcssOptions& o)
        : mResolution(o.resolution), mSearchSamples(o.blockerSamples),
          mFilterSamples(o.pcfSamples), mShadowPass(r.shaders),
          mLookup(r.shaders, "pcss-lookup.frag", "pcss-lookup", PipelineState{}, lookupDefines(o)) {
        // Depth zNear / z (float: precise far from the light); the border reads 0, "nothing", so
        // kernels reaching past the map find no blockers there.
        mMaps = Texture({.target = GL_TEXTURE_2D_ARRAY,
                         .width = mResolution,
                         .height = mResolution,
                         .layers = 2,
                         .format = GL_DEPTH_COMPONENT32F,
                         .wrap = GL_CLAMP_TO_BORDER,
                         .label = "pcss-shadow-maps"});
        for (int side = 0; side < 2; ++side)
            mSideFbo[side] = Framebuffer(
                {.attachments = {{GL_DEPTH_ATTACHMENT, &mMaps, 0, side}}, .label = "pcss-side"});
        const std::vector<glm::vec2> filter =
            geometry::scrambledNet(mFilterSamples, kFilterPatternSeed);
        const std::vector<glm::vec2> search =
            geometry::scrambledNet(mSearchSamples, kSearchPatternSeed);
        for (int i = 0; i < PCSS_MAX_SAMPLES; ++i)
            mPattern[i] = glm::vec4(i < mFilterSamples ? filter[i] : glm::vec2(0.0f),
                                    i < mSearchSamples ? search[i] : glm::vec2(0.0f));
    }

    void execute(const FrameContext& ctx) override {
        updateFrame(ctx);
        const geometry::PcssFrame& f = mFrame;
        shader::PcssUniforms u{};
        for (int side = 0; side < 2; ++side) {
            const geometry::PcssSide& s = f.sides[side];
            u.shadowProj[side] = s.present ? f.projection(side) : glm::mat4(1.0f);
            u.extent[side] = glm::vec4(s.lo, 1.0f / (s.hi - s.lo));
        }
        u.basisU = glm::vec4(f.eu, f.halfSize.x);
        u.basisV = glm::vec4(f.ev, f.halfSize.y);
        u.normal = glm::vec4(f.normal, f.zNear);
        u.sides = glm::vec4(f.sides[0].present ? 1.0f : 0.0f, f.sides[1].present ? 1.0f : 0.0f,
                            f.sides[0].casterNear, f.sides[1].casterNear);
        u.params =
            glm::vec4(static_cast<float>(mSearchSamples), static_cast<float>(mFilterSamples),
                      static_cast<float>(mResolution), 1.0f / static_cast<float>(mResolution));
        for (int i = 0; i < PCSS_MAX_SAMPLES; ++i)
            u.pattern[i] = mPattern[i];
        mUniforms.upload(&u, sizeof(u));
        glBindBufferBase(GL_UNIFORM_BUFFER, BINDING_PCSS_UBO, mUniforms.id());

        {
            ScopedPass pass(&ctx.timers, "pcss-shadow");
            for (int side = 0; side < 2; ++side)
                if (drawn(side))
                    mShadowPass.execute(mSideFbo[side], side, mResolution, ctx.sceneGeometry,
                                        mObjects);
        }
        const std::uint32_t zero = 0;
        glClearNamedBufferData(mStats.id(), GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, &zero);
        {
            ScopedPass pass(&ctx.timers, "pcss-lookup");
            glBindTextureUnit(TEXUNIT_POSITION, ctx.targets.position.id());
            glBindTextureUnit(TEXUNIT_NORMAL, ctx.targets.normal.id());
            glBindTextureUnit(TEXUNIT_PCSS, mMaps.id());
            glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BINDING_PCSS_STATS, mStats.id());
            mLookup.execute(ctx.targets.visibilityFbo, ctx.targets.width, ctx.targets.height);
        }
        std::uint32_t outside = 0;
        glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT); // the lookup's atomics
        glGetNamedBufferSubData(mStats.id(), 0, sizeof(outside), &outside);

        ctx.addCounter("pcss_resolution", mResolution);
        ctx.addCounter("pcss_sides", static_cast<double>(drawn(0)) + static_cast<double>(drawn(1)));
        ctx.addCounter("pcss_pixels_outside", outside);
        ctx.addCounter("pcss_frustum_clamped",
                       static_cast<double>(f.sides[0].clamped || f.sides[1].clamped));
        ctx.addCounter("pcss_caster_near",
                       f.sides[0].present ? f.sides[0].casterNear : f.sides[1].casterNear);
        ctx.addCounter("pcss_casters", static_cast<double>(mObjects.size()));
    }

private:
    // A side's map is drawn when receivers lie on it and casters reach into its frustum (the
    // lookup reads no map where casterNear is 0).
    bool drawn(int side) const {
        return mFrame.sides[side].present && mFrame.sides[side].casterNear > 0.0f;
    }

    void updateFrame(const FrameContext& ctx) {
        const geometry::RectLight& light = ctx.light;
        std::vector<std::uint32_t> subset(ctx.casterSubset.begin(), ctx.casterSubset.end());
        if (mFitted && light == mLight && subset == mSubset)
            return;
        const auto t0 = Clock::now();
        mObjects.clear();
        for (const std::uint32_t c : subset)
            mObjects.push_back(ctx.casters.sceneObject(c));
        mFrame = geometry::fitPcssFrame(ctx.scene, light, mObjects);
        mLight = light;
        mSubset = std::move(subset);
        mFitted = true;
        ctx.addCpuTime("pcss-fit", msSince(t0));
    }

    int mResolution, mSearchSamples, mFilterSamples;
    PcssShadowPass mShadowPass;
    FullscreenPass mLookup;
    Texture mMaps;
    Framebuffer mSideFbo[2];
    glm::vec4 mPattern[PCSS_MAX_SAMPLES];
    Buffer mUniforms{{.size = sizeof(shader::PcssUniforms), .label = "pcss-uniforms"}};
    Buffer mStats{{.size = sizeof(std::uint32_t), .label = "pcss-stats"}};

    bool mFitted = false;
    geometry::RectLight mLight;
    std::vector<std::uint32_t> mSubset;
    std::vector<std::size_t> mObjects;
    geometry::PcssFrame mFrame;
};

} // namespace

std::unique_ptr<VisibilityMethod> createPcssMethod(const MethodResources& r) {
    return std::make_unique<PcssMethod>(r);
}

} // namespace gpu
