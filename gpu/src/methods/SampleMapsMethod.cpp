// sample-maps: the average of N hard shadows from the light samples, each a shadow map in which
// alpha-tested casters cut their texels out (geometry/shadow/SampleMapFrame.h; the lookup:
// shaders/sample-maps-lookup.frag). The brute-force alpha path: it shadows leaves with leaves as
// `raytrace` does with the same number of samples, up to the maps' resolution, at the price of N
// shadow passes whenever the light or the casters change (a still light reuses the maps, counted
// as sample_maps_cached). Samples: the reference's stratified pattern for N and --seed.
//
// linear-light-sm (Heidrich, Brabec & Seidel 2000) is the same maps and lookup for other samples:
// the end points of K parallel linear lights along the light's longer axis (each from one edge of
// the rectangle to the other, at stratified offsets across the shorter axis), and between the
// maps and the lookup the skin pass (shaders/linear-light-skin.*): each end point's map's depth
// discontinuities become skin polygons drawn into the other end point's view with a visibility
// ramp, which the lookup uses as the end point's weight (LINEAR_LIGHTS).
#include "engine/Method.h"
#include "engine/MethodOptions.h"
#include "engine/ShaderBindings.h"
#include "methods/MethodUtil.h"
#include "passes/FullscreenPass.h"
#include "passes/SampleMapPass.h"

#include <geometry/core/Error.h>
#include <geometry/shadow/SampleMapFrame.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace gpu {

namespace {

// Maps larger than this in all are refused with the figure (N x R^2 x 4 bytes; the early
// out's N-buffer comes on top).
constexpr std::size_t kMaxMapBytes = std::size_t(256) << 20;

// A depth jump of more than this ratio between neighbouring texels of a map is an occluder's
// edge (linear-light-skin.vert).
constexpr float kSkinDiscontinuity = 1.02f;

// The skins' blending: the darkest of overlapping skins (each pass writes its ramp where it lies
// in front of the target map's surface).
constexpr PipelineState kSkinState{
    .blend = true, .blendSrc = GL_ONE, .blendDst = GL_ONE, .blendEquation = GL_MIN};

SampleMapsOptions linearOptions(const LinearLightSmOptions& o) {
    return {.samples = 2 * o.lights,
            .resolution = o.resolution,
            .normalOffset = o.normalOffset,
            .ownPlane = o.ownPlane,
            .earlyOut = false};
}

class SampleMapsMethod final : public VisibilityMethod {
public:
    explicit SampleMapsMethod(const MethodResources& r)
        : SampleMapsMethod(r, sampleMapsOptions(r.parameters), 0) {}

    // linear-light-sm: `lights` linear lights (0: sample-maps).
    SampleMapsMethod(const MethodResources& r, const SampleMapsOptions& options, int lights)
        : mOptions(options), mLights(lights),
          mPrefix(lights ? "linear_light_sm" : "sample_maps"),
          mLookup(r.shaders, "sample-maps-lookup.frag",
                  lights ? "linear-light-sm-lookup" : "sample-maps-lookup", PipelineState{},
                  lookupDefines(mOptions, lights)),
          mUniforms({.size = sizeof(shader::SampleMapUniforms), .label = "sample-map-uniforms"}),
          mStats({.size = SAMPLE_MAP_STAT_COUNT * sizeof(std::uint32_t),
                  .label = "sample-map-stats"}) {
        if (mOptions.earlyOut)
            while ((1 << (mNBufferLevels - 1)) < mOptions.resolution) ++mNBufferLevels;
        // The maps (the early out's N-buffer adds log2(R) + 1 layers of R^2 floats: 44 MiB at
        // resolution=1024, not counted against the limit).
        const std::size_t layers = static_cast<std::size_t>(mOptions.samples);
        const std::size_t r2 = static_cast<std::size_t>(mOptions.resolution) *
                               static_cast<std::size_t>(mOptions.resolution);
        if (layers * r2 * 4 > kMaxMapBytes)
            throw geometry::InputError(
                "sample-maps: samples=" + std::to_string(mOptions.samples) + " at resolution=" +
                std::to_string(mOptions.resolution) + " needs " +
                std::to_string(layers * r2 * 4 >> 20) + " MiB of shadow maps, over the " +
                std::to_string(kMaxMapBytes >> 20) + " MiB limit; lower one of them");
        mMaps.emplace(r.shaders, mOptions.samples, mOptions.resolution, "sample-maps");
        if (mOptions.earlyOut) {
            mNBuffer = Texture({.target = GL_TEXTURE_2D_ARRAY,
                                .width = mOptions.resolution,
                                .height = mOptions.resolution,
                                .layers = mNBufferLevels,
                                .format = GL_R32F,
                                .label = "sample-map-nbuffer"});
            mNBufferProgram =
                r.shaders.load({.stages = {{GL_COMPUTE_SHADER, "sample-maps-nbuffer.comp"}},
                                .label = "sample-maps-nbuffer"});
        }
        if (mLights) {
            mSkins = Texture({.target = GL_TEXTURE_2D_ARRAY,
                              .width = mOptions.resolution,
                              .height = mOptions.resolution,
                              .layers = mOptions.samples,
                              .format = GL_R32F,
                              .label = "linear-light-skins"});
            for (int i = 0; i < mOptions.samples; ++i)
                mSkinFbos.emplace_back(FramebufferDesc{
                    .attachments = {{GL_COLOR_ATTACHMENT0, &mSkins, 0, i}},
                    .label = "linear-light-skin"});
            mSkinProgram = r.shaders.load({.stages = {{GL_VERTEX_SHADER, "linear-light-skin.vert"},
                                                      {GL_FRAGMENT_SHADER, "linear-light-skin.frag"}},
                                           .label = "linear-light-skin"});
            mSkinVao = VertexArray("linear-light-skin");
        }
    }

    void execute(const FrameContext& ctx) override { run(ctx, false); }
    bool executeMultiplied(const FrameContext& ctx) override {
        run(ctx, true); // the lookup writes every pixel once
        return true;
    }

private:
    // `multiply`: the lookup multiplies V into the target's instead of writing it.
    void run(const FrameContext& ctx, bool multiply) {
        update(ctx);
        const geometry::SampleMapFrame& f = mFrame;
        shader::SampleMapUniforms u{};
        u.eu = glm::vec4(f.eu, 0.0f);
        u.ev = glm::vec4(f.ev, 0.0f);
        u.n = glm::vec4(f.n, 0.0f);
        u.params = glm::vec4(f.empty ? 0.0f : static_cast<float>(mOptions.samples),
                             static_cast<float>(mOptions.resolution), mOptions.normalOffset, f.zNear);
        u.reach = glm::vec4(f.centreLo, f.centreHi);
        u.reachSpread = glm::vec4(f.half, f.zFar > 0.0f ? 1.0f / f.zFar : 0.0f,
                                  f.reachAll ? 1.0f : 0.0f);
        const bool earlyOut = mOptions.earlyOut && !f.empty && !f.reachAll && mEmptyTestUsable;
        u.emptyTest = glm::vec4(static_cast<float>(mNearest),
                                earlyOut ? static_cast<float>(mNBufferLevels) : 0.0f, mOffsetShare,
                                mFootprintMargin);
        for (int q = 0; q < 4; ++q) u.emptyQuadrant[q] = mQuadrantOffsets[q];
        mUniforms.upload(&u, sizeof(u));
        glBindBufferBase(GL_UNIFORM_BUFFER, BINDING_SAMPLE_MAPS_UBO, mUniforms.id());

        const bool cached = mMapsDrawn;
        if (!cached && !f.empty) {
            ScopedPass pass(&ctx.timers, mLights ? "linear-light-sm-shadow" : "sample-maps-shadow");
            mMaps->draw(f, 0, f.views.size(), mObjects, ctx.sceneGeometry);
            if (earlyOut) buildNBuffer();
        }
        if (!cached && mLights) {
            ScopedPass pass(&ctx.timers, "linear-light-sm-skins");
            drawSkins();
        }
        mMapsDrawn = true;
        const std::uint32_t zero = 0;
        if (mOptions.earlyOut)
            glClearNamedBufferData(mStats.id(), GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, &zero);
        {
            ScopedPass pass(&ctx.timers, mLights ? "linear-light-sm-lookup" : "sample-maps-lookup");
            glBindTextureUnit(TEXUNIT_POSITION, ctx.targets.position.id());
            glBindTextureUnit(TEXUNIT_NORMAL, ctx.targets.normal.id());
            glBindTextureUnit(TEXUNIT_SAMPLE_MAPS, mMaps->maps().id());
            if (mOptions.earlyOut) {
                glBindTextureUnit(TEXUNIT_SAMPLE_MAP_NBUFFER, mNBuffer.id());
                glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BINDING_SAMPLE_MAP_STATS, mStats.id());
            }
            glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BINDING_SAMPLE_MAP_VIEWS, mViews.id());
            if (mLights) glBindTextureUnit(TEXUNIT_LINEAR_SKINS, mSkins.id());
            mLookup.execute(ctx.targets.visibilityFbo, ctx.targets.width, ctx.targets.height,
                            multiply ? kMultiplyState : PipelineState{}, {});
        }
        std::uint32_t stats[SAMPLE_MAP_STAT_COUNT] = {};
        if (mOptions.earlyOut) {
            glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT); // the lookup's atomics
            glGetNamedBufferSubData(mStats.id(), 0, sizeof(stats), stats);
        }
        const auto counter = [&](const char* name, double value) {
            ctx.addCounter(mPrefix + name, value);
        };
        if (mLights) {
            counter("_lights", mLights);
        } else {
            // Pixels in reach that read no map, and pixels that skipped some quadrants' maps.
            counter("_early_out_pixels", stats[SAMPLE_MAP_STAT_EMPTY]);
            counter("_quadrant_skip_pixels", stats[SAMPLE_MAP_STAT_QUADRANTS]);
        }
        counter(mLights ? "_maps" : "", f.empty ? 0.0 : static_cast<double>(f.views.size()));
        counter("_resolution", mOptions.resolution);
        counter("_cached", cached ? 1.0 : 0.0);
        // Casters reaching behind a light sample or past the maps' 71.6-degree cap: they are
        // missing from some maps (points they hide from those samples are drawn lit).
        counter("_clipped", f.clipped ? 1.0 : 0.0);
        counter("_casters", static_cast<double>(mObjects.size()));
    }

private:
    static std::vector<std::string> lookupDefines(const SampleMapsOptions& o, int lights) {
        std::vector<std::string> d;
        if (o.ownPlane) d.emplace_back("OWN_PLANE");
        if (o.earlyOut) d.emplace_back("EARLY_OUT");
        if (lights) d.emplace_back("LINEAR_LIGHTS");
        return d;
    }

    // linear-light-sm: the end points (s, t) of the linear lights along the light's longer
    // axis, 2k and 2k + 1 for light k at the stratified offset (2k + 1) / K - 1 across.
    std::vector<glm::vec2> endPoints(const geometry::RectLight& light) const {
        const bool alongU = glm::length(light.u) >= glm::length(light.v);
        std::vector<glm::vec2> points;
        for (int k = 0; k < mLights; ++k) {
            const float across = (2.0f * k + 1.0f) / static_cast<float>(mLights) - 1.0f;
            for (const float along : {-1.0f, 1.0f})
                points.push_back(alongU ? glm::vec2(along, across) : glm::vec2(across, along));
        }
        return points;
    }

    // The skins of each linear light's two maps, each drawn into the other's layer.
    void drawSkins() const {
        const float none = 2.0f;
        glClearTexImage(mSkins.id(), 0, GL_RED, GL_FLOAT, &none);
        if (mFrame.empty) return;
        applyState(kSkinState);
        glUseProgram(mSkinProgram.id());
        glBindVertexArray(mSkinVao.id());
        glBindTextureUnit(TEXUNIT_SAMPLE_MAPS, mMaps->maps().id());
        const int R = mOptions.resolution;
        glViewport(0, 0, R, R);
        const glm::vec3 axes[3] = {mFrame.eu, mFrame.ev, mFrame.n};
        glUniform3fv(UNIFORM_SKIN_AXES, 3, &axes[0][0]);
        glUniform4f(UNIFORM_SKIN_PARAMS, mFrame.zNear, mFrame.zFar, static_cast<float>(R),
                    kSkinDiscontinuity);
        for (int k = 0; k < mLights; ++k)
            for (const auto& [source, target] : {std::pair{2 * k, 2 * k + 1}, {2 * k + 1, 2 * k}}) {
                const geometry::SampleMapView& v = mFrame.views[static_cast<std::size_t>(source)];
                const glm::mat4 view = mFrame.projection(static_cast<std::size_t>(target));
                glBindFramebuffer(GL_FRAMEBUFFER,
                                  mSkinFbos[static_cast<std::size_t>(target)].id());
                glUniformMatrix4fv(UNIFORM_SKIN_TARGET_VIEW, 1, GL_FALSE, &view[0][0]);
                glUniform2i(UNIFORM_SKIN_LAYERS, source, target);
                glUniform3fv(UNIFORM_SKIN_ORIGIN, 1, &v.origin[0]);
                glUniform4f(UNIFORM_SKIN_EXTENT, v.lo.x, v.lo.y, v.hi.x, v.hi.y);
                glDrawArrays(GL_TRIANGLES, 0, 6 * 2 * R * (R - 1));
            }
        glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT);
    }

    // Map mNearest's max N-buffer (shaders/sample-maps-nbuffer.comp), from the maps just drawn.
    void buildNBuffer() const {
        glUseProgram(mNBufferProgram.id());
        glBindTextureUnit(TEXUNIT_SAMPLE_MAPS, mMaps->maps().id());
        glBindImageTexture(IMAGE_SAMPLE_MAP_NBUFFER, mNBuffer.id(), 0, GL_TRUE, 0, GL_READ_WRITE,
                           GL_R32F);
        const GLuint groups = static_cast<GLuint>((mOptions.resolution + 7) / 8);
        for (int level = 0; level < mNBufferLevels; ++level) {
            glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT); // level l reads l - 1
            glUniform1i(UNIFORM_PREFILTER_STEP, level);
            glDispatchCompute(groups, groups, 1);
        }
        glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT); // the lookup fetches the levels
    }

    // The early out's figures (sample-maps-lookup.frag, EARLY_OUT): the map whose sample lies
    // nearest the centre, the range of lateral offsets from it of each quadrant's samples, and the
    // receiver offset's and texel footprints' bounds from the widest map.
    void fitEmptyTest() {
        mNearest = 0;
        float best = std::numeric_limits<float>::infinity();
        float widest = 0.0f;
        for (std::size_t i = 0; i < mFrame.views.size(); ++i) {
            const geometry::SampleMapView& v = mFrame.views[i];
            const float d = glm::dot(v.st, v.st);
            if (d < best) {
                best = d;
                mNearest = static_cast<int>(i);
            }
            widest = std::max({widest, v.hi.x - v.lo.x, v.hi.y - v.lo.y});
        }
        // Per quadrant (the shader's sampleQuadrant), the range of its samples' lateral offsets
        // from sample k; a quadrant without samples holds 0.
        constexpr float inf = std::numeric_limits<float>::infinity();
        std::array<glm::vec2, 4> lo, hi;
        lo.fill(glm::vec2(inf));
        hi.fill(glm::vec2(-inf));
        if (!mFrame.views.empty()) {
            const glm::vec3 ck = mFrame.views[static_cast<std::size_t>(mNearest)].origin;
            for (const geometry::SampleMapView& v : mFrame.views) {
                const glm::vec3 d = v.origin - ck;
                const glm::vec2 o(glm::dot(d, mFrame.eu), glm::dot(d, mFrame.ev));
                const int q = (v.st.x >= 0.0f ? 1 : 0) + (v.st.y >= 0.0f ? 2 : 0);
                lo[q] = glm::min(lo[q], o);
                hi[q] = glm::max(hi[q], o);
            }
        }
        for (int q = 0; q < 4; ++q)
            mQuadrantOffsets[q] = lo[q].x <= hi[q].x ? glm::vec4(lo[q], hi[q]) : glm::vec4(0.0f);
        const float texel = widest / static_cast<float>(mOptions.resolution);
        // The lookup moves the receiver by at most (0.25 + bias) texels of its map at its depth.
        mOffsetShare = (0.25f + mOptions.normalOffset) * texel;
        // Per axis, the 2 x 2 texels a sample reads lie within one texel of its ray, and a caster
        // there covers a texel centre of map k within about one texel: 2.5 texels in all.
        mFootprintMargin = 2.5f * texel;
        mEmptyTestUsable = std::isfinite(mOffsetShare) && mOffsetShare < 0.25f;
    }

    // Refits the frame (and marks the maps stale) when the light or the casters change.
    void update(const FrameContext& ctx) {
        std::vector<std::uint32_t> subset(ctx.casterSubset.begin(), ctx.casterSubset.end());
        const std::uint32_t seed = ctx.settings.seed;
        if (mFitted && ctx.light == mLight && subset == mSubset && seed == mSeed) return;
        const auto t0 = Clock::now();
        SampleMapSetup setup =
            mLights ? fitSampleMaps(ctx.scene, ctx.casters, subset, ctx.light, endPoints(ctx.light))
                    : fitSampleMaps(ctx.scene, ctx.casters, subset, ctx.light, mOptions.samples,
                                    seed);
        mObjects = std::move(setup.objects);
        mFrame = std::move(setup.frame);
        std::vector<glm::vec4> views;
        for (const geometry::SampleMapView& v : mFrame.views) {
            const glm::vec3 d = v.origin - ctx.light.center;
            views.emplace_back(v.st, glm::dot(d, mFrame.eu), glm::dot(d, mFrame.ev));
            views.emplace_back(v.lo, 1.0f / (v.hi - v.lo));
        }
        if (views.empty()) views.emplace_back(0.0f); // a buffer is bound either way
        fitEmptyTest();
        mViews = Buffer({.size = views.size() * sizeof(glm::vec4), .label = "sample-map-views"});
        mViews.upload(std::span<const glm::vec4>(views));
        mMapsDrawn = false;
        mLight = ctx.light;
        mSubset = std::move(subset);
        mSeed = seed;
        mFitted = true;
        ctx.addCpuTime(mLights ? "linear-light-sm-fit" : "sample-maps-fit", msSince(t0));
    }

    SampleMapsOptions mOptions;
    int mLights = 0;     // linear-light-sm: the linear lights (0: sample-maps)
    std::string mPrefix; // of the counters
    FullscreenPass mLookup;
    // linear-light-sm: per end point's map, the skins' ramp (R32F array, cleared to 2: none).
    Texture mSkins;
    std::vector<Framebuffer> mSkinFbos;
    Program mSkinProgram;
    VertexArray mSkinVao;
    Buffer mUniforms, mStats, mViews;
    std::optional<SampleMapPass> mMaps;
    // early_out=on: map mNearest's max N-buffer, one layer per level.
    Texture mNBuffer;
    Program mNBufferProgram;
    int mNBufferLevels = 1;
    int mNearest = 0;
    std::array<glm::vec4, 4> mQuadrantOffsets{}; // per quadrant: least (xy), largest (zw)
    float mOffsetShare = 0.0f, mFootprintMargin = 0.0f;
    bool mEmptyTestUsable = false;
    geometry::SampleMapFrame mFrame;
    bool mFitted = false, mMapsDrawn = false;
    geometry::RectLight mLight;
    std::vector<std::uint32_t> mSubset;
    std::vector<std::size_t> mObjects;
    std::uint32_t mSeed = 0;
};

} // namespace

std::unique_ptr<VisibilityMethod> createSampleMapsMethod(const MethodResources& r) {
    return std::make_unique<SampleMapsMethod>(r);
}

std::unique_ptr<VisibilityMethod> createLinearLightSmMethod(const MethodResources& r) {
    const LinearLightSmOptions o = linearLightSmOptions(r.parameters);
    return std::make_unique<SampleMapsMethod>(r, linearOptions(o), o.lights);
}

} // namespace gpu
