// pdsm: penumbra deep shadow maps (St-Amour, Paquette & Poulin 2005). Precomputed for the
// light and the casters: k shadow maps from the light samples (the sample-maps method's maps,
// passes/SampleMapPass.h), read back a few at a time and merged on the CPU into one map from the
// light's centre whose texels hold V along their ray as a compressed piecewise-linear function
// (geometry/shadow/PenumbraDeepShadowMap.h: 16-bit depth, 8-bit value, a guaranteed bound); each
// frame, one lookup per pixel (shaders/pdsm-lookup.frag). While the light, the casters and the
// seed stay, the deep map is reused (pdsm_cached); a change builds it again: before the frame's
// lookup headless, on a CPU thread in the viewer (the frames keep the last map meanwhile).
// Objects the scene marks dynamic ("static": false) are not in the deep map: `auto` shadows them
// each frame (its wedge path, or its alpha path for alpha-tested ones) and V = V_dynamic ·
// V_pdsm (methods/MethodUtil.h VisibilityProduct), as the slides insert dynamic objects; the
// receiver's own plane is then counted by auto's path only.
#include "engine/Method.h"
#include "engine/MethodOptions.h"
#include "engine/ShaderBindings.h"
#include "methods/MethodUtil.h"
#include "passes/FullscreenPass.h"
#include "passes/SampleMapPass.h"

#include <geometry/core/Error.h>
#include <geometry/shadow/PenumbraDeepShadowMap.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <functional>
#include <future>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace gpu {

namespace {

// The sample maps are read back into CPU memory for the merge: k R^2 floats, refused past this.
constexpr std::size_t kMaxReadBackBytes = std::size_t(256) << 20;
// The sample maps' slope-scaled depth offset in texels (SampleMapPass::draw): the deep map's
// construction reads one texel per map, whose stored depth is the surface's at the texel's
// centre.
constexpr float kMapSlopeBias = 1.5f;
// Sample maps drawn (and read back) at a time.
constexpr int kMapsPerBatch = 16;

class PdsmMethod final : public VisibilityMethod {
public:
    explicit PdsmMethod(const MethodResources& r)
        : mResources{r.shaders, r.scene, {}}, mOptions(pdsmOptions(r.parameters)),
          mLookup(r.shaders, "pdsm-lookup.frag", "pdsm-lookup", PipelineState{},
                  mOptions.ownPlane ? std::vector<std::string>{"OWN_PLANE"}
                                    : std::vector<std::string>{}),
          mLookupWithoutPlane(r.shaders, "pdsm-lookup.frag", "pdsm-lookup", PipelineState{}),
          mProduct(r.shaders, "pdsm-compose"),
          mUniforms({.size = sizeof(shader::PdsmUniforms), .label = "pdsm-uniforms"}),
          mStats({.size = PDSM_STAT_COUNT * sizeof(std::uint32_t), .label = "pdsm-stats"}) {
        const std::size_t r2 = static_cast<std::size_t>(mOptions.resolution) *
                               static_cast<std::size_t>(mOptions.resolution);
        const std::size_t bytes = static_cast<std::size_t>(mOptions.samples) * r2 * 4;
        if (bytes > kMaxReadBackBytes)
            throw geometry::InputError(
                "pdsm: samples=" + std::to_string(mOptions.samples) + " at resolution=" +
                std::to_string(mOptions.resolution) + " reads back " +
                std::to_string(bytes >> 20) + " MiB of sample maps to build the deep map, over " +
                "the " + std::to_string(kMaxReadBackBytes >> 20) + " MiB limit; lower one of them");
        mMaps.emplace(r.shaders, std::min(kMapsPerBatch, mOptions.samples), mOptions.resolution,
                      "pdsm-sample-maps");
        mIndex = Texture({.width = mOptions.resolution,
                          .height = mOptions.resolution,
                          .format = GL_RG32UI,
                          .label = "pdsm-index"});
    }

    void resize(int width, int height) override {
        mWidth = width;
        mHeight = height;
        mProduct.resize(width, height);
        if (mDynamic) mDynamic->resize(width, height);
    }

    std::size_t targetBytesPerPixel() const override {
        return VisibilityProduct::kBytesPerPixel + (mDynamic ? mDynamic->targetBytesPerPixel() : 0);
    }

    void execute(const FrameContext& ctx) override {
        // The static casters go into the deep map, the dynamic ones to auto's paths.
        std::vector<std::uint32_t> staticCasters, dynamicCasters;
        for (const std::uint32_t c : ctx.casterSubset)
            (ctx.scene.objects[ctx.casters.sceneObject(c)].isStatic ? staticCasters
                                                                     : dynamicCasters)
                .push_back(c);
        ctx.addCounter("pdsm_dynamic_objects", static_cast<double>(dynamicCasters.size()));
        FrameContext own = ctx;
        own.casterSubset = staticCasters;
        if (dynamicCasters.empty()) {
            executeDeep(own, mLookup);
            return;
        }
        if (!mDynamic) {
            const MethodInfo& info = findMethod("auto");
            mDynamic = info.create(
                MethodResources{mResources.shaders, mResources.scene, resolveParameters(info, {})});
            mDynamic->resize(mWidth, mHeight);
        }
        FrameContext dynamic = ctx;
        dynamic.casterSubset = dynamicCasters;
        mDynamic->execute(dynamic); // counts the receiver's own plane
        mProduct.beforeFactor(ctx);
        executeDeep(own, mLookupWithoutPlane);
        mProduct.afterFactor(ctx);
    }

private:
    // The deep map of ctx.casterSubset (built or reused) and its lookup into V.
    void executeDeep(const FrameContext& ctx, const FullscreenPass& lookup) {
        // A background build that finished replaces the map (the viewer: see below).
        if (mPending && mPending->result.wait_for(std::chrono::seconds(0)) ==
                            std::future_status::ready)
            adopt(std::move(*mPending));
        const bool cached = !stale(ctx);
        if (!cached) {
            // The first map, and every map of a headless frame, is built before the lookup;
            // in the viewer (waitForGpu = false) a moved light's map is merged on a CPU thread
            // while the frames keep the last one (pdsm_building, its rows done in percent).
            if (!mBuilt || ctx.settings.waitForGpu) {
                if (mPending) adopt(std::move(*mPending)); // waits for it
                Pending next = start(ctx);
                next.result.wait();
                adopt(std::move(next));
            } else if (!mPending) {
                mPending.emplace(start(ctx));
            }
        }
        const geometry::PdsmGrid& g = mMap.grid;
        shader::PdsmUniforms u{};
        u.eu = glm::vec4(g.eu, g.empty ? 0.0f : 1.0f);
        u.ev = glm::vec4(g.ev, g.clipped ? 1.0f : 0.0f);
        u.n = glm::vec4(g.n, g.zNear);
        u.extent = g.empty ? glm::vec4(0.0f) : glm::vec4(g.lo, 1.0f / (g.hi - g.lo));
        const glm::vec2 side = g.hi - g.lo;
        u.params = glm::vec4(static_cast<float>(g.resolution), g.sFar, mOptions.normalOffset,
                             std::max(side.x, side.y) / static_cast<float>(g.resolution));
        u.centre = glm::vec4(g.centre, 1.0f);
        mUniforms.upload(&u, sizeof(u));
        // The lookup counts receivers outside the map only where it is clipped (elsewhere none
        // can be hidden there): only then is the counter cleared and read back, a wait on the
        // GPU in the viewer's frames.
        const std::uint32_t zero = 0;
        if (g.clipped)
            glClearNamedBufferData(mStats.id(), GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, &zero);
        {
            ScopedPass pass(&ctx.timers, "pdsm-lookup");
            glBindBufferBase(GL_UNIFORM_BUFFER, BINDING_PDSM_UBO, mUniforms.id());
            glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BINDING_PDSM_STATS, mStats.id());
            glBindTextureUnit(TEXUNIT_POSITION, ctx.targets.position.id());
            glBindTextureUnit(TEXUNIT_NORMAL, ctx.targets.normal.id());
            glBindTextureUnit(TEXUNIT_PDSM_INDEX, mIndex.id());
            glBindTextureUnit(TEXUNIT_PDSM_DATA, mDataTexels.id());
            lookup.execute(ctx.targets.visibilityFbo, ctx.targets.width, ctx.targets.height);
        }
        std::uint32_t stats[PDSM_STAT_COUNT] = {};
        if (g.clipped) {
            glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT); // the lookup's atomics
            glGetNamedBufferSubData(mStats.id(), 0, sizeof(stats), stats);
        }
        const geometry::PdsmStats& s = mMap.stats;
        ctx.addCounter("pdsm_cached", cached ? 1.0 : 0.0);
        ctx.addCounter("pdsm_building", mPending ? 1.0 : 0.0);
        ctx.addCounter("pdsm_building_percent",
                       mPending ? 100.0 * mPending->rows->load() / mOptions.resolution : 0.0);
        ctx.addCounter("pdsm_samples", g.empty ? 0.0 : static_cast<double>(mOptions.samples));
        ctx.addCounter("pdsm_resolution", mOptions.resolution);
        ctx.addCounter("pdsm_tolerance", mOptions.tolerance);
        ctx.addCounter("pdsm_points", static_cast<double>(s.points));
        ctx.addCounter("pdsm_texels_stored", s.texelsStored);
        ctx.addCounter("pdsm_longest_function", s.longest);
        ctx.addCounter("pdsm_mean_function",
                       s.texelsStored ? static_cast<double>(s.points) / s.texelsStored : 0.0);
        ctx.addCounter("pdsm_steps", static_cast<double>(s.steps));
        ctx.addCounter("pdsm_max_deviation", s.maxDeviation);
        ctx.addCounter("pdsm_bytes", static_cast<double>(mMap.bytes()));
        ctx.addCounter("pdsm_maps_ms", mMapsMs);
        ctx.addCounter("pdsm_build_ms", s.buildMs);
        ctx.addCounter("pdsm_precompute_ms", mMapsMs + s.buildMs + mUploadMs);
        ctx.addCounter("pdsm_clipped", g.clipped ? 1.0 : 0.0);
        ctx.addCounter("pdsm_pixels_outside", stats[PDSM_STAT_OUTSIDE]);
        ctx.addCounter("pdsm_casters", static_cast<double>(mSetup.objects.size()));
    }

    // A deep map being merged on a CPU thread, with what it was built for.
    struct Pending {
        std::future<geometry::Pdsm> result;
        std::shared_ptr<std::atomic<int>> rows; // rows merged so far
        geometry::RectLight light;
        std::uint32_t seed = 0;
        std::vector<std::uint32_t> subset;
        SampleMapSetup setup;
        double mapsMs = 0.0;
    };

    bool stale(const FrameContext& ctx) const {
        return !mBuilt || !(ctx.light == mLight) || ctx.settings.seed != mSeed ||
               !std::equal(ctx.casterSubset.begin(), ctx.casterSubset.end(), mSubset.begin(),
                           mSubset.end());
    }

    // Draws the sample maps of this frame's light and casters, reads them back, and starts
    // merging them into the deep map on a CPU thread.
    Pending start(const FrameContext& ctx) {
        const auto t0 = Clock::now();
        Pending p;
        p.light = ctx.light;
        p.seed = ctx.settings.seed;
        p.subset.assign(ctx.casterSubset.begin(), ctx.casterSubset.end());
        p.setup = fitSampleMaps(ctx.scene, ctx.casters, p.subset, ctx.light, mOptions.samples,
                                p.seed);
        geometry::jitterSampleMapGrids(p.setup.frame, mOptions.resolution);
        const geometry::SampleMapFrame& f = p.setup.frame;
        geometry::Aabb scene;
        for (const geometry::SceneObject& o : ctx.scene.objects) scene.extend(o.mesh.bounds());
        const geometry::PdsmGrid grid =
            geometry::fitPdsmGrid(f, ctx.light.center, scene, mOptions.resolution);
        const int R = mOptions.resolution;
        const std::size_t layer = static_cast<std::size_t>(R) * static_cast<std::size_t>(R);
        auto texels = std::make_shared<std::vector<float>>();
        if (!f.empty) {
            ScopedPass pass(&ctx.timers, "pdsm-sample-maps");
            texels->resize(layer * f.views.size());
            for (std::size_t first = 0; first < f.views.size();
                 first += static_cast<std::size_t>(mMaps->layers())) {
                const std::size_t count = std::min(static_cast<std::size_t>(mMaps->layers()),
                                                   f.views.size() - first);
                mMaps->draw(f, first, count, p.setup.objects, ctx.sceneGeometry, kMapSlopeBias);
                glGetTextureSubImage(mMaps->maps().id(), 0, 0, 0, 0, R, R,
                                     static_cast<GLsizei>(count), GL_DEPTH_COMPONENT, GL_FLOAT,
                                     static_cast<GLsizei>(count * layer * sizeof(float)),
                                     texels->data() + first * layer);
            }
        }
        p.mapsMs = msSince(t0);
        ctx.addCpuTime("pdsm-sample-maps", p.mapsMs);
        p.rows = std::make_shared<std::atomic<int>>(0);
        geometry::PdsmBuildSettings settings{.tolerance = mOptions.tolerance};
        const std::function<void(int, int)> report =
            ctx.settings.waitForGpu ? ctx.settings.progress : std::function<void(int, int)>{};
        settings.progress = [rows = p.rows, report](int done, int total) {
            rows->store(done);
            if (report) report(done, total);
        };
        // The frame (and the maps' copy) live in the task; nothing of this frame is referenced.
        p.result = std::async(std::launch::async,
                              [frame = f, grid, texels, settings, R]() {
                                  return geometry::buildPdsm(frame, grid, {R, *texels}, settings);
                              });
        return p;
    }

    // Takes a finished build's map (waiting for it) and uploads it.
    void adopt(Pending&& p) {
        try {
            mMap = p.result.get();
        } catch (...) {
            mPending.reset(); // (p may be it) a failed build is not tried again as it is
            throw;
        }
        mLight = p.light;
        mSeed = p.seed;
        mSubset = std::move(p.subset);
        mSetup = std::move(p.setup);
        mMapsMs = p.mapsMs;
        const auto t0 = Clock::now();
        upload();
        mUploadMs = msSince(t0);
        mBuilt = true;
        mPending.reset();
    }

    void upload() {
        const int R = mOptions.resolution;
        glTextureSubImage2D(mIndex.id(), 0, 0, 0, R, R, GL_RG_INTEGER, GL_UNSIGNED_INT,
                            mMap.index.data());
        // A buffer texture holds GL_MAX_TEXTURE_BUFFER_SIZE texels of four points each.
        GLint maxTexels = 0;
        glGetIntegerv(GL_MAX_TEXTURE_BUFFER_SIZE, &maxTexels);
        const std::size_t groups = mMap.data.size() / 3;
        if (groups > static_cast<std::size_t>(maxTexels))
            throw geometry::InputError(
                "pdsm: the deep map holds " + std::to_string(mMap.stats.points) +
                " points, more than one buffer texture of GL_MAX_TEXTURE_BUFFER_SIZE = " +
                std::to_string(maxTexels) + " texels of four holds; raise tolerance or lower " +
                "resolution");
        std::vector<std::uint32_t> words = mMap.data;
        if (words.empty()) words.assign(3, 0u); // a texture is bound either way
        mData = Buffer({.size = words.size() * sizeof(std::uint32_t),
                        .data = words.data(),
                        .flags = 0,
                        .label = "pdsm-data"});
        if (!mDataTexels) {
            GLuint id = 0;
            glCreateTextures(GL_TEXTURE_BUFFER, 1, &id);
            mDataTexels = Handle<TextureDeleter>(id);
        }
        glTextureBuffer(mDataTexels.id(), GL_RGB32UI, mData.id());
    }

    struct TextureDeleter {
        void operator()(GLuint id) const { glDeleteTextures(1, &id); }
    };

    MethodResources mResources; // shaders and scene, for the dynamic objects' method
    PdsmOptions mOptions;
    FullscreenPass mLookup, mLookupWithoutPlane;
    VisibilityProduct mProduct;
    std::unique_ptr<VisibilityMethod> mDynamic; // auto, on the dynamic objects
    int mWidth = 0, mHeight = 0;
    Buffer mUniforms, mStats, mData;
    Texture mIndex;
    Handle<TextureDeleter> mDataTexels;
    std::optional<SampleMapPass> mMaps;
    geometry::Pdsm mMap;
    SampleMapSetup mSetup;
    std::optional<Pending> mPending;
    double mMapsMs = 0.0, mUploadMs = 0.0;
    bool mBuilt = false;
    geometry::RectLight mLight;
    std::uint32_t mSeed = 0;
    std::vector<std::uint32_t> mSubset;
};

} // namespace

std::unique_ptr<VisibilityMethod> createPdsmMethod(const MethodResources& r) {
    return std::make_unique<PdsmMethod>(r);
}

} // namespace gpu
