// The pcss method's shadow maps and lookup (PcssShadow.h).
#include "methods/PcssShadow.h"

#include "engine/ShaderBindings.h"
#include "methods/GroupBatches.h"
#include "methods/MethodUtil.h"

#include <geometry/core/Error.h>
#include <geometry/core/Sampling.h>
#include <geometry/reference/RayTracer.h>
#include <geometry/shadow/DeepShadowMap.h>

#include <cmath>
#include <string>
#include <vector>

namespace gpu {

namespace {

// Fixed seeds of the two sample patterns (geometry::scrambledNet): the same pattern every frame.
constexpr std::uint32_t kFilterPatternSeed = 0x5CC5u;
constexpr std::uint32_t kSearchPatternSeed = 0xB10Cu;

std::vector<std::string> lookupDefines(const PcssOptions& o, PcssShadow::Pixels pixels,
                                       bool deep = false) {
    std::vector<std::string> d = {"NORMAL_OFFSET " + o.bias};
    if (deep) d.push_back("DEEP_SHADOW_MAP");
    if (o.horizon) d.push_back("HORIZON");
    if (pixels == PcssShadow::Pixels::OutsideOcclusion) d.push_back("OUTSIDE_OCCLUSION");
    return d;
}

} // namespace

// deep-sm's part: its options, the casters' tracer, the map and its textures.
struct PcssShadow::Deep {
    DeepSmOptions options;
    std::unique_ptr<geometry::RayTracer> tracer;
    std::vector<std::size_t> tracerObjects; // the objects it holds
    geometry::DeepShadowMap map;
    Texture index; // a layer per face: first group, count | nearest code << 16 (RG32UI)
    BufferTexture data;
    double tracerMs = 0.0, buildMs = 0.0, uploadMs = 0.0;
};

PcssShadow::~PcssShadow() = default;

PcssShadow::PcssShadow(const MethodResources& r, const PcssOptions& o, Pixels pixels)
    : PcssShadow(r, o, pixels, false) {}

PcssShadow::PcssShadow(const MethodResources& r, const PcssOptions& o, Pixels pixels, bool deep)
    : mPixels(pixels), mResolution(o.resolution), mSearchSamples(o.blockerSamples),
      mFilterSamples(o.pcfSamples), mShadowPass(r.shaders),
      mLookup(r.shaders, "pcss-lookup.frag", "pcss-lookup", PipelineState{}, lookupDefines(o, pixels, deep)),
      mLookupTiles(r.shaders, "pcss-lookup.frag", "pcss-lookup-tiles", PipelineState{},
                   lookupDefines(o, pixels, deep), "tile-rects.vert"),
      mUniforms({.size = sizeof(shader::PcssUniforms), .label = "pcss-uniforms"}),
      mStats({.size = 4 * sizeof(std::uint32_t), .label = "pcss-stats"}),
      mRects({.size = 0, .label = "pcss-screen-rects"}) {
    if (o.horizon && pixels == Pixels::All) {
        std::vector<std::string> defines = lookupDefines(o, pixels, deep);
        defines.push_back("HORIZON_ONLY");
        mHorizonTiles.emplace(r.shaders, "pcss-lookup.frag", "pcss-horizon-tiles",
                              PipelineState{}, defines, "tile-rects.vert");
    }
    // Depth zNear / z (float: precise far from the light); the border reads 0, "nothing", so
    // kernels reaching past the map find no blockers there. (deep-sm's maps are its own.)
    if (!deep) {
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
    }
    const std::vector<glm::vec2> filter =
        geometry::scrambledNet(mFilterSamples, kFilterPatternSeed);
    const std::vector<glm::vec2> search =
        geometry::scrambledNet(mSearchSamples, kSearchPatternSeed);
    for (int i = 0; i < PCSS_MAX_SAMPLES; ++i)
        mPattern[i] = glm::vec4(i < mFilterSamples ? filter[i] : glm::vec2(0.0f),
                                i < mSearchSamples ? search[i] : glm::vec2(0.0f));
}

PcssShadow::PcssShadow(const MethodResources& r, const DeepSmOptions& deep)
    : PcssShadow(r, deep.lookup, Pixels::All, true) {
    mDeep = std::make_unique<Deep>();
    mDeep->options = deep;
    mDeep->index = Texture({.target = GL_TEXTURE_2D_ARRAY,
                            .width = mResolution,
                            .height = mResolution,
                            .layers = geometry::kPcssFaces,
                            .format = GL_RG32UI,
                            .label = "deep-sm-index"});
    const std::uint32_t none[3] = {0, 0, 0};
    mDeep->data.upload(none, 0, GL_RGB32UI, sizeof(none), "deep-sm-data");
}

void PcssShadow::execute(const FrameContext& ctx, bool multiply) {
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
        if (mDeep) {
            const geometry::DeepShadowFace& d = mDeep->map.faces[static_cast<std::size_t>(face)];
            u.faceDeep[face] = glm::vec4(d.zc, d.sFar, d.built ? 1.0f : 0.0f, 0.0f);
        }
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
    mReach = reachBoxes(ctx.light);
    for (std::size_t k = 0; k < mReach.size(); ++k) {
        u.reach[2 * k] = glm::vec4(mReach[k].min, 0.0f);
        u.reach[2 * k + 1] = glm::vec4(mReach[k].max, 0.0f);
    }
    u.params2 = glm::vec4(static_cast<float>(mReach.size()), 0.0f, 0.0f, 0.0f);
    mUniforms.upload(&u, sizeof(u));
    glBindBufferBase(GL_UNIFORM_BUFFER, BINDING_PCSS_UBO, mUniforms.id());

    // The maps depend on the light and the casters only: while neither changes (a still
    // light; the scene is fixed for the renderer's life) the last frame's are this frame's.
    const bool cached = mMapsDrawn;
    if (!cached && mDeep) {
        buildDeep(ctx); // the faces' deep maps (CPU), and this frame's uniforms again
        for (int face = 0; face < geometry::kPcssFaces; ++face) {
            const geometry::DeepShadowFace& d = mDeep->map.faces[static_cast<std::size_t>(face)];
            u.faceDeep[face] = glm::vec4(d.zc, d.sFar, d.built ? 1.0f : 0.0f, 0.0f);
        }
        mUniforms.upload(&u, sizeof(u));
        mMapsDrawn = true;
    } else if (!cached) {
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
        ScopedPass pass(&ctx.timers, mDeep                     ? "deep-sm-lookup"
                                     : mPixels == Pixels::All ? "pcss-lookup"
                                                              : "occlusion-outside");
        glBindTextureUnit(TEXUNIT_POSITION, ctx.targets.position.id());
        glBindTextureUnit(TEXUNIT_NORMAL, ctx.targets.normal.id());
        if (mDeep) {
            glBindTextureUnit(TEXUNIT_DEEP_SM_INDEX, mDeep->index.id());
            glBindTextureUnit(TEXUNIT_PDSM_DATA, mDeep->data.id());
        } else {
            glBindTextureUnit(TEXUNIT_PCSS, mMaps.id());
        }
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BINDING_PCSS_STATS, mStats.id());
        if (!drawLookupOverTiles(ctx, multiply)) // else over the whole screen
            mLookup.execute(ctx.targets.visibilityFbo, ctx.targets.width, ctx.targets.height,
                            multiply ? kMultiplyState : PipelineState{}, {});
    }
    // Pixels in no face, pixels shaded (OUTSIDE_OCCLUSION), pixels whose blockers lay outside
    // their pyramid to the light (lit), pixels a caster's box could reach.
    std::uint32_t stats[4] = {0, 0, 0, 0};
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT); // the lookup's atomics
    glGetNamedBufferSubData(mStats.id(), 0, sizeof(stats), stats);

    if (mDeep) {
        deepCounters(ctx, cached, stats[0]);
        return;
    }
    if (mPixels == Pixels::OutsideOcclusion) {
        ctx.addCounter("occlusion_pixels_outside", stats[1]);
        ctx.addCounter("occlusion_outside_blockers_unconfirmed", stats[2]);
        ctx.addCounter("occlusion_outside_pixels_searched", stats[3]);
        ctx.addCounter("occlusion_outside_maps", maps);
        ctx.addCounter("occlusion_outside_maps_cached", cached ? 1.0 : 0.0);
        return;
    }
    ctx.addCounter("pcss_resolution", mResolution);
    ctx.addCounter("pcss_sides", maps);
    ctx.addCounter("pcss_side_maps", sideMaps);
    ctx.addCounter("pcss_maps_cached", cached ? 1.0 : 0.0);
    ctx.addCounter("pcss_pixels_outside", stats[0]);
    ctx.addCounter("pcss_blockers_unconfirmed", stats[2]);
    ctx.addCounter("pcss_pixels_searched", stats[3]);
    ctx.addCounter("pcss_frustum_clamped",
                   static_cast<double>(f.faces[0].clamped || f.faces[1].clamped));
    ctx.addCounter("pcss_caster_near",
                   f.faces[0].present ? f.faces[0].casterNear : f.faces[1].casterNear);
    ctx.addCounter("pcss_casters", static_cast<double>(mObjects.size()));
}

std::vector<geometry::Aabb> PcssShadow::reachBoxes(const geometry::RectLight& light) const {
    // A point of the segment from P to a light point c + d lies within |d| of the segment from
    // P to c, per axis within the light's half extent.
    const glm::vec3 half = glm::abs(light.u) + glm::abs(light.v);
    std::vector<geometry::Aabb> grown;
    for (const geometry::Aabb& box : mCasterBoxes) {
        geometry::Aabb g;
        g.extend(box.min - half);
        g.extend(box.max + half);
        grown.push_back(g);
    }
    return grown;
}

bool PcssShadow::drawLookupOverTiles(const FrameContext& ctx, bool multiply) {
    const SurfaceTiles* tiles = ctx.scratch ? ctx.scratch->surfaceTiles.get() : nullptr;
    const int width = ctx.targets.width, height = ctx.targets.height;
    if (!tiles || mPixels != Pixels::All || tiles->tile <= 0 ||
        tiles->tilesX * tiles->tile < width || tiles->tilesY * tiles->tile < height ||
        tiles->boxes.size() != static_cast<std::size_t>(tiles->tilesX) * tiles->tilesY)
        return false;
    // The lookup's own reach test (a pixel whose segment to the light's centre misses every
    // reach box grown by the light's half extents is lit), for a whole tile: no segment from
    // its surface box to the centre meets one (geometry::sweepMeetsBox). A tile that fails it
    // holds no pixel that passes, so V is what the lookup over the screen gives. Runs of tiles
    // of one kind along a row are drawn as one rectangle.
    const std::vector<TileSphere> spheres = tileSpheres(*tiles); // boxes with a rounding margin
    std::vector<glm::vec4> reached, other;
    std::size_t reachedTiles = 0, surfaceTiles = 0;
    auto ndc = [](int pixel, int size) {
        return 2.0f * static_cast<float>(pixel) / static_cast<float>(size) - 1.0f;
    };
    auto addRun = [&](std::vector<glm::vec4>& to, int tx0, int tx1, int ty) {
        const int x0 = tx0 * tiles->tile, x1 = std::min(width, tx1 * tiles->tile);
        const int y0 = ty * tiles->tile, y1 = std::min(height, (ty + 1) * tiles->tile);
        if (x1 > x0 && y1 > y0)
            to.push_back({ndc(x0, width), ndc(y0, height), ndc(x1, width), ndc(y1, height)});
    };
    for (int ty = 0; ty < tiles->tilesY; ++ty) {
        int runStart = 0, runKind = 0; // 0: no surface, 1: reached, 2: surface not reached
        for (int tx = 0; tx <= tiles->tilesX; ++tx) {
            int kind = 0;
            if (tx < tiles->tilesX) {
                const TileSphere& t = spheres[static_cast<std::size_t>(ty) * tiles->tilesX + tx];
                if (!t.box.empty()) {
                    ++surfaceTiles;
                    kind = 2;
                    for (const geometry::Aabb& g : mReach) // this frame's, as the shader's
                        if (geometry::sweepMeetsBox(t.box, ctx.light.center, g)) {
                            kind = 1;
                            ++reachedTiles;
                            break;
                        }
                }
            }
            if (tx == tiles->tilesX || kind != runKind) {
                if (runKind == 1) addRun(reached, runStart, tx, ty);
                if (runKind == 2) addRun(other, runStart, tx, ty);
                runStart = tx;
                runKind = kind;
            }
        }
    }
    ctx.addCounter(mDeep ? "deep_sm_lookup_tiles" : "pcss_lookup_tiles",
                   static_cast<double>(reachedTiles));
    ctx.addCounter(mDeep ? "deep_sm_surface_tiles" : "pcss_surface_tiles",
                   static_cast<double>(surfaceTiles));
    // Pixels no rectangle covers keep V (multiply), or are lit (written).
    if (!multiply) {
        const float one = 1.0f;
        glClearTexImage(ctx.targets.visibility.id(), 0, GL_RED, GL_FLOAT, &one);
    }
    const bool horizon = mHorizonTiles.has_value() && !other.empty();
    const std::size_t count = reached.size() + (horizon ? other.size() : 0);
    if (count == 0) return true;
    std::vector<glm::vec4> all = reached;
    if (horizon) all.insert(all.end(), other.begin(), other.end());
    mRects.uploadResize(all.data(), all.size() * sizeof(glm::vec4));
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BINDING_SCREEN_RECTS, mRects.id());
    const PipelineState state = multiply ? kMultiplyState : PipelineState{};
    if (!reached.empty())
        mLookupTiles.execute(ctx.targets.visibilityFbo, width, height, state,
                             [] { glUniform1i(UNIFORM_FIRST_RECT, 0); },
                             static_cast<GLsizei>(6 * reached.size()));
    if (horizon) {
        // The others' rectangles follow the reached ones in the buffer.
        const GLint first = static_cast<GLint>(reached.size());
        mHorizonTiles->execute(ctx.targets.visibilityFbo, width, height, state,
                               [first] { glUniform1i(UNIFORM_FIRST_RECT, first); },
                               static_cast<GLsizei>(6 * other.size()));
    }
    return true;
}

void PcssShadow::updateFrame(const FrameContext& ctx) {
    const geometry::RectLight& light = ctx.light;
    std::vector<std::uint32_t> subset(ctx.casterSubset.begin(), ctx.casterSubset.end());
    if (mFitted && light == mLight && subset == mSubset)
        return;
    const bool newCasters = !mFitted || subset != mSubset;
    mObjects.clear();
    for (const std::uint32_t c : subset)
        mObjects.push_back(ctx.casters.sceneObject(c));
    // The boxes hold the casters' occluding points, whatever the light: made again only for
    // other casters (an alpha-tested object's texels are read for them).
    if (newCasters) {
        const auto b0 = Clock::now();
        // deep-sm's texels hold transmittance: every point of opacity above 0 hides light.
        mCasterBoxes = geometry::casterClusters(
            ctx.scene, mObjects, PCSS_REACH_BOXES,
            mDeep ? geometry::AlphaRule::Transmittance : geometry::AlphaRule::Cutoff);
        ctx.addCpuTime("pcss-reach-boxes", msSince(b0));
    }
    const auto t0 = Clock::now();
    mFrame = geometry::fitPcssFrame(ctx.scene, light, mObjects);
    mMapsDrawn = false;
    mLight = light;
    mSubset = std::move(subset);
    mFitted = true;
    ctx.addCpuTime("pcss-fit", msSince(t0));
}

void PcssShadow::buildDeep(const FrameContext& ctx) {
    Deep& d = *mDeep;
    if (!d.tracer || d.tracerObjects != mObjects) {
        const auto t0 = Clock::now();
        d.tracer.reset();
        d.tracer = std::make_unique<geometry::RayTracer>(ctx.scene, mObjects);
        d.tracerObjects = mObjects;
        d.tracerMs = msSince(t0);
        ctx.addCpuTime("deep-sm-tracer", d.tracerMs);
    }
    geometry::Aabb receivers;
    for (const geometry::SceneObject& o : ctx.scene.objects) receivers.extend(o.mesh.bounds());
    geometry::DeepShadowSettings settings{.resolution = mResolution,
                                          .supersample = d.options.supersample,
                                          .tolerance = d.options.tolerance};
    if (ctx.settings.waitForGpu) settings.progress = ctx.settings.progress;
    const geometry::RayTracer& tracer = *d.tracer;
    const geometry::SurfaceQuery query = [&tracer](const glm::vec3& origin, const glm::vec3& dir,
                                                   float tfar,
                                                   std::vector<geometry::SurfaceHit>& out) {
        tracer.surfacesAlong(origin, dir, 0.0f, tfar, out);
    };
    d.map = geometry::buildDeepShadowMap(mFrame, receivers, query, settings);
    d.buildMs = d.map.stats.buildMs;
    ctx.addCpuTime("deep-sm-build", d.buildMs);

    const auto t0 = Clock::now();
    GLint maxTexels = 0;
    glGetIntegerv(GL_MAX_TEXTURE_BUFFER_SIZE, &maxTexels);
    if (d.map.data.size() / 3 > static_cast<std::size_t>(maxTexels))
        throw geometry::InputError(
            "deep-sm: the deep maps hold " + std::to_string(d.map.stats.points) +
            " points, more than one buffer texture of GL_MAX_TEXTURE_BUFFER_SIZE = " +
            std::to_string(maxTexels) + " texels of four holds; raise tolerance or lower " +
            "resolution or supersample");
    glTextureSubImage3D(d.index.id(), 0, 0, 0, 0, mResolution, mResolution, geometry::kPcssFaces,
                        GL_RG_INTEGER, GL_UNSIGNED_INT, d.map.index.data());
    d.data.upload(d.map.data.data(), d.map.data.size() * sizeof(std::uint32_t), GL_RGB32UI,
                  3 * sizeof(std::uint32_t), "deep-sm-data");
    d.uploadMs = msSince(t0);
}

void PcssShadow::deepCounters(const FrameContext& ctx, bool cached,
                              std::uint32_t outside) const {
    const Deep& d = *mDeep;
    const geometry::DeepShadowStats& s = d.map.stats;
    int faces = 0;
    for (const geometry::DeepShadowFace& f : d.map.faces) faces += f.built ? 1 : 0;
    ctx.addCounter("deep_sm_resolution", mResolution);
    ctx.addCounter("deep_sm_supersample", d.options.supersample);
    ctx.addCounter("deep_sm_tolerance", d.options.tolerance);
    ctx.addCounter("deep_sm_faces", faces);
    ctx.addCounter("deep_sm_cached", cached ? 1.0 : 0.0);
    ctx.addCounter("deep_sm_rays", static_cast<double>(s.rays));
    ctx.addCounter("deep_sm_crossings_per_ray",
                   s.rays ? static_cast<double>(s.crossings) / static_cast<double>(s.rays) : 0.0);
    ctx.addCounter("deep_sm_points", static_cast<double>(s.points));
    ctx.addCounter("deep_sm_texels_stored", s.texelsStored);
    ctx.addCounter("deep_sm_longest_function", s.longest);
    ctx.addCounter("deep_sm_mean_function",
                   s.texelsStored ? static_cast<double>(s.points) / s.texelsStored : 0.0);
    ctx.addCounter("deep_sm_max_deviation", s.maxDeviation);
    ctx.addCounter("deep_sm_bytes", static_cast<double>(d.map.bytes()));
    ctx.addCounter("deep_sm_tracer_ms", d.tracerMs);
    ctx.addCounter("deep_sm_build_ms", d.buildMs);
    ctx.addCounter("deep_sm_precompute_ms", d.tracerMs + d.buildMs + d.uploadMs);
    ctx.addCounter("deep_sm_pixels_outside", outside);
    ctx.addCounter("deep_sm_casters", static_cast<double>(mObjects.size()));
}

} // namespace gpu
