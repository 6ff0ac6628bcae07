// The pcss method's shadow maps and lookup (PcssShadow.h).
#include "methods/PcssShadow.h"

#include "engine/ShaderBindings.h"

#include <geometry/core/Sampling.h>

#include <cmath>
#include <string>
#include <vector>

namespace gpu {

namespace {

// Fixed seeds of the two sample patterns (geometry::scrambledNet): the same pattern every frame.
constexpr std::uint32_t kFilterPatternSeed = 0x5CC5u;
constexpr std::uint32_t kSearchPatternSeed = 0xB10Cu;

std::vector<std::string> lookupDefines(const PcssOptions& o, PcssShadow::Pixels pixels) {
    std::vector<std::string> d = {"NORMAL_OFFSET " + o.bias};
    if (o.horizon) d.push_back("HORIZON");
    if (pixels == PcssShadow::Pixels::OutsideOcclusion) d.push_back("OUTSIDE_OCCLUSION");
    return d;
}

} // namespace

PcssShadow::PcssShadow(const MethodResources& r, const PcssOptions& o, Pixels pixels)
    : mPixels(pixels), mResolution(o.resolution), mSearchSamples(o.blockerSamples),
      mFilterSamples(o.pcfSamples), mShadowPass(r.shaders),
      mLookup(r.shaders, "pcss-lookup.frag", "pcss-lookup", PipelineState{}, lookupDefines(o, pixels)),
      mUniforms({.size = sizeof(shader::PcssUniforms), .label = "pcss-uniforms"}),
      mStats({.size = 2 * sizeof(std::uint32_t), .label = "pcss-stats"}) {
    // Depth zNear / z (float: precise far from the light); the border reads 0, "nothing", so
    // kernels reaching past the map find no blockers there.
    mMaps = Texture({.target = GL_TEXTURE_2D_ARRAY,
                     .width = mResolution,
                     .height = mResolution,
                     .layers = geometry::kPcssFaces,
                     .format = GL_DEPTH_COMPONENT32F,
                     .wrap = GL_CLAMP_TO_BORDER,
                     .label = "pcss-shadow-maps"});
    for (int face = 0; face < geometry::kPcssFaces; ++face)
        mFaceFbo[face] = Framebuffer(
            {.attachments = {{GL_DEPTH_ATTACHMENT, &mMaps, 0, face}}, .label = "pcss-face"});
    const std::vector<glm::vec2> filter =
        geometry::scrambledNet(mFilterSamples, kFilterPatternSeed);
    const std::vector<glm::vec2> search =
        geometry::scrambledNet(mSearchSamples, kSearchPatternSeed);
    for (int i = 0; i < PCSS_MAX_SAMPLES; ++i)
        mPattern[i] = glm::vec4(i < mFilterSamples ? filter[i] : glm::vec2(0.0f),
                                i < mSearchSamples ? search[i] : glm::vec2(0.0f));
}

void PcssShadow::execute(const FrameContext& ctx) {
    updateFrame(ctx);
    const geometry::PcssFrame& f = mFrame;
    shader::PcssUniforms u{};
    for (int face = 0; face < geometry::kPcssFaces; ++face) {
        const geometry::PcssFace& s = f.faces[face];
        u.shadowProj[face] = f.projection(face);
        // w: 1 if receivers lie in the face, + 2 if its map is drawn.
        u.faceB1[face] = glm::vec4(s.b1, (s.present ? 1.0f : 0.0f) + (s.drawn ? 2.0f : 0.0f));
        u.faceB2[face] = glm::vec4(s.b2, s.casterNear);
        const glm::vec3 lu = f.lightU(face), lv = f.lightV(face);
        u.faceAxis[face] = glm::vec4(s.axis, std::abs(lu.z) + std::abs(lv.z));
        u.extent[face] = glm::vec4(s.lo, 1.0f / (s.hi - s.lo));
        u.lightU[face] = glm::vec4(lu, 0.0f);
        u.lightV[face] = glm::vec4(lv, 0.0f);
    }
    u.basisU = glm::vec4(f.eu, f.maxTan);
    int maps = 0, sideMaps = 0;
    for (int face = 0; face < geometry::kPcssFaces; ++face) {
        maps += drawn(face) ? 1 : 0;
        sideMaps += face >= 2 && drawn(face) ? 1 : 0;
    }
    u.basisV = glm::vec4(f.ev, static_cast<float>(maps));
    u.normal = glm::vec4(f.normal, f.zNear);
    u.params =
        glm::vec4(static_cast<float>(mSearchSamples), static_cast<float>(mFilterSamples),
                  static_cast<float>(mResolution), 1.0f / static_cast<float>(mResolution));
    for (int i = 0; i < PCSS_MAX_SAMPLES; ++i)
        u.pattern[i] = mPattern[i];
    {
        // A point of the segment from P to a light point c + d lies within |d| of the segment
        // from P to c, per axis within the light's half extent.
        const glm::vec3 half = glm::abs(ctx.light.u) + glm::abs(ctx.light.v);
        for (std::size_t k = 0; k < mCasterBoxes.size(); ++k) {
            u.reach[2 * k] = glm::vec4(mCasterBoxes[k].min - half, 0.0f);
            u.reach[2 * k + 1] = glm::vec4(mCasterBoxes[k].max + half, 0.0f);
        }
        u.params2 = glm::vec4(static_cast<float>(mCasterBoxes.size()), 0.0f, 0.0f, 0.0f);
    }
    mUniforms.upload(&u, sizeof(u));
    glBindBufferBase(GL_UNIFORM_BUFFER, BINDING_PCSS_UBO, mUniforms.id());

    // The maps depend on the light and the casters only: while neither changes (a still
    // light; the scene is fixed for the renderer's life) the last frame's are this frame's.
    const bool cached = mMapsDrawn;
    if (!cached) {
        ScopedPass pass(&ctx.timers, "pcss-shadow");
        for (int face = 0; face < geometry::kPcssFaces; ++face)
            if (drawn(face))
                mShadowPass.execute(mFaceFbo[face], face, mResolution, ctx.sceneGeometry,
                                    mObjects);
        mMapsDrawn = true;
    }
    const std::uint32_t zero = 0;
    glClearNamedBufferData(mStats.id(), GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, &zero);
    {
        ScopedPass pass(&ctx.timers, mPixels == Pixels::All ? "pcss-lookup" : "occlusion-outside");
        glBindTextureUnit(TEXUNIT_POSITION, ctx.targets.position.id());
        glBindTextureUnit(TEXUNIT_NORMAL, ctx.targets.normal.id());
        glBindTextureUnit(TEXUNIT_PCSS, mMaps.id());
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BINDING_PCSS_STATS, mStats.id());
        mLookup.execute(ctx.targets.visibilityFbo, ctx.targets.width, ctx.targets.height);
    }
    std::uint32_t stats[2] = {0, 0}; // pixels in no face, pixels shaded (OUTSIDE_OCCLUSION)
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT); // the lookup's atomics
    glGetNamedBufferSubData(mStats.id(), 0, sizeof(stats), stats);

    if (mPixels == Pixels::OutsideOcclusion) {
        ctx.addCounter("occlusion_pixels_outside", stats[1]);
        ctx.addCounter("occlusion_outside_maps", maps);
        ctx.addCounter("occlusion_outside_maps_cached", cached ? 1.0 : 0.0);
        return;
    }
    ctx.addCounter("pcss_resolution", mResolution);
    ctx.addCounter("pcss_sides", maps);
    ctx.addCounter("pcss_side_maps", sideMaps);
    ctx.addCounter("pcss_maps_cached", cached ? 1.0 : 0.0);
    ctx.addCounter("pcss_pixels_outside", stats[0]);
    ctx.addCounter("pcss_frustum_clamped",
                   static_cast<double>(f.faces[0].clamped || f.faces[1].clamped));
    ctx.addCounter("pcss_caster_near",
                   f.faces[0].present ? f.faces[0].casterNear : f.faces[1].casterNear);
    ctx.addCounter("pcss_casters", static_cast<double>(mObjects.size()));
}

void PcssShadow::updateFrame(const FrameContext& ctx) {
    const geometry::RectLight& light = ctx.light;
    std::vector<std::uint32_t> subset(ctx.casterSubset.begin(), ctx.casterSubset.end());
    if (mFitted && light == mLight && subset == mSubset)
        return;
    const auto t0 = Clock::now();
    mObjects.clear();
    for (const std::uint32_t c : subset)
        mObjects.push_back(ctx.casters.sceneObject(c));
    mCasterBoxes = geometry::casterClusters(ctx.scene, mObjects, PCSS_REACH_BOXES);
    mFrame = geometry::fitPcssFrame(ctx.scene, light, mObjects);
    mMapsDrawn = false;
    mLight = light;
    mSubset = std::move(subset);
    mFitted = true;
    ctx.addCpuTime("pcss-fit", msSince(t0));
}

} // namespace gpu
