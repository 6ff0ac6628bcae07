// pdsm: penumbra deep shadow maps (St-Amour, Paquette & Poulin 2005). Precomputed for the
// light and the casters: k shadow maps from the light samples (the sample-maps method's maps,
// passes/SampleMapPass.h), read back a few at a time and merged on the CPU into one map from the
// light's centre whose texels hold V along their ray as a compressed piecewise-linear function
// (geometry/shadow/PenumbraDeepShadowMap.h: 16-bit depth, 8-bit value, a guaranteed bound); each
// frame, one lookup per pixel (shaders/pdsm-lookup.frag). Where one map along the light's
// normal cannot hold every receiver that may be hidden (a lamp in a room), a map per face of
// the cube around the light (fitPdsmCube), each built as the one: its k maps drawn, read back
// and merged in turn, so that one face's maps are in memory at a time. While the light, the casters and the
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
#include <shared/Pdsm.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <functional>
#include <future>
#include <memory>
#include <optional>
#include <stdexcept>
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
// The lookup's RECEIVER_PLANE_SPAN (pdsm-lookup.frag): how far from a receiver's depth, in
// texels, it reads a neighbouring texel; the build keeps the functions over that span.
constexpr float kReceiverPlaneSpan = 16.0f;
std::string spanDefine() {
    return "RECEIVER_PLANE_SPAN " + std::to_string(kReceiverPlaneSpan);
}

// The lookup's programs: for the one map (ONE_MAP: its one face's frame) and for the cube (a
// face per pixel), each with the count of receivers outside the maps where they are clipped
// (COUNT_OUTSIDE: an atomic every SIMD group pays) and without it.
struct PdsmLookup {
    PdsmLookup(const ShaderLoader& shaders, const std::vector<std::string>& defines)
        : oneMap(pass(shaders, defines, {"ONE_MAP"})),
          cube(pass(shaders, defines, {})),
          oneMapCounting(pass(shaders, defines, {"ONE_MAP", "COUNT_OUTSIDE"})),
          cubeCounting(pass(shaders, defines, {"COUNT_OUTSIDE"})) {}
    const FullscreenPass& pick(bool isCube, bool counting) const {
        return counting ? (isCube ? cubeCounting : oneMapCounting) : (isCube ? cube : oneMap);
    }

private:
    static FullscreenPass pass(const ShaderLoader& shaders, std::vector<std::string> defines,
                               std::initializer_list<const char*> more) {
        for (const char* d : more) defines.push_back(d);
        return FullscreenPass(shaders, "pdsm-lookup.frag", "pdsm-lookup", PipelineState{},
                              std::move(defines), "pdsm-lookup.vert");
    }

    FullscreenPass oneMap, cube, oneMapCounting, cubeCounting;
};
// Sample maps drawn (and read back) at a time.
constexpr int kMapsPerBatch = 16;

class PdsmMethod final : public VisibilityMethod {
public:
    explicit PdsmMethod(const MethodResources& r)
        : mResources{r.shaders, r.scene, {}}, mOptions(pdsmOptions(r.parameters)),
          mLookup(r.shaders, mOptions.ownPlane
                                 ? std::vector<std::string>{"OWN_PLANE", spanDefine()}
                                 : std::vector<std::string>{spanDefine()}),
          mLookupWithoutPlane(r.shaders, {spanDefine()}),
          mProduct(r.shaders, "pdsm-compose"),
          mUniforms({.size = sizeof(shader::PdsmUniforms), .label = "pdsm-uniforms"}),
          mStats({.size = PDSM_STAT_COUNT * sizeof(std::uint32_t), .label = "pdsm-stats"}),
          mData({.label = "pdsm-data"}) {
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
    // The deep maps of ctx.casterSubset (built or reused) and their lookup into V.
    void executeDeep(const FrameContext& ctx, const PdsmLookup& lookup) {
        mCurrentLookup = &lookup; // the probe's, in start()
        mMapsDrawn = 0;
        const bool cached = ensureMaps(ctx);
        std::uint32_t outside = runLookup(ctx, lookup);
        // One map that leaves receivers of this view outside it where they may be hidden (its
        // frame clipped: a lamp in a room, casters at the light's plane): the cube from now on,
        // built at once and the lookup run again headless, in the background in the viewer.
        if (!mCube && outside > 0 && !mWantCube) {
            mWantCube = true;
            if (ctx.settings.waitForGpu || !mBuilt) {
                const double first = precomputeMs();
                ensureMaps(ctx);
                mFirstMapMs = first; // part of what this frame waited for
                outside = runLookup(ctx, lookup);
            } else if (!mPending) {
                mPending.emplace(start(ctx));
            }
        }
        addCounters(ctx, cached, outside);
    }

    // Builds the maps where they are stale (see below); true when the last ones were reused.
    bool ensureMaps(const FrameContext& ctx) {
        // A background build that finished replaces the maps (the viewer: see below); one whose
        // face is merged draws the next face's sample maps and merges them in turn.
        if (mPending && advanceOrDrop(ctx, *mPending, false)) adopt(std::move(*mPending));
        const bool cached = !stale(ctx);
        if (!cached) {
            // The first maps, and every map of a headless frame, are built before the lookup;
            // in the viewer (waitForGpu = false) a moved light's maps are merged on a CPU thread
            // while the frames keep the last ones (pdsm_building, its rows done in percent).
            if (!mBuilt || ctx.settings.waitForGpu) {
                if (mPending) { // waits for it
                    advanceOrDrop(ctx, *mPending, true);
                    adopt(std::move(*mPending));
                }
                Pending next = start(ctx);
                advance(ctx, next, true);
                adopt(std::move(next));
            } else if (!mPending) {
                mPending.emplace(start(ctx));
            }
        }
        return cached;
    }

    // The built maps' precompute: their sample maps, merges and upload.
    double precomputeMs() const {
        double build = 0.0;
        for (const geometry::Pdsm& m : mFaces) build += m.stats.buildMs;
        return mMapsMs + build + mUploadMs;
    }

    // The lookup into V; the receivers it finds outside the maps where they may be hidden.
    // `probe`: instead, the one map's extent `probe` alone, before its functions are built (the
    // lookup counts the receivers outside it and reads nothing; V is written again after).
    std::uint32_t runLookup(const FrameContext& ctx, const PdsmLookup& lookup,
                            const geometry::PdsmGrid* probe = nullptr) {
        std::vector<const geometry::PdsmGrid*> grids;
        std::vector<int> ids;
        if (probe) {
            grids.push_back(probe);
            ids.push_back(0);
        } else {
            for (std::size_t f = 0; f < mFaces.size(); ++f) {
                grids.push_back(&mFaces[f].grid);
                ids.push_back(mFaceIds[f]);
            }
        }
        const bool clipped = std::any_of(grids.begin(), grids.end(),
                                         [](const geometry::PdsmGrid* g) { return g->clipped; });
        shader::PdsmUniforms u{};
        const bool anyCasters = std::any_of(grids.begin(), grids.end(),
                                            [](const geometry::PdsmGrid* g) { return !g->empty; });
        const bool cube = !probe && mCube;
        u.centre = glm::vec4(probe ? probe->centre : mLight.center, anyCasters ? 1.0f : 0.0f);
        u.cube = glm::vec4(cube ? 1.0f : 0.0f, mCubeFrame.maxTan, mOptions.normalOffset,
                           static_cast<float>(mOptions.resolution));
        u.basisU = glm::vec4(mCubeFrame.eu, clipped ? 1.0f : 0.0f);
        u.basisV = glm::vec4(mCubeFrame.ev, probe ? 1.0f : 0.0f);
        u.normal = glm::vec4(mCubeFrame.normal, mCubeFrame.zNear);
        for (int k = 0; k < geometry::kPcssFaces; ++k) u.faceB1[k].w = -1.0f;
        for (std::size_t f = 0; f < grids.size(); ++f) {
            const geometry::PdsmGrid& g = *grids[f];
            if (g.empty) continue;
            const int k = ids[f];
            const glm::vec2 side = g.hi - g.lo;
            u.faceB1[k] = glm::vec4(g.eu, static_cast<float>(f));
            u.faceB2[k] = glm::vec4(g.ev, g.zNear);
            u.faceAxis[k] = glm::vec4(g.n, g.sFar);
            u.faceExtent[k] = glm::vec4(g.lo, 1.0f / side);
            const glm::vec2 size(static_cast<float>(g.resolution),
                                 static_cast<float>(g.rowCount()));
            u.faceTexel[k] = glm::vec4(std::max(side.x / size.x, side.y / size.y), size,
                                       g.nearClipped ? 1.0f : 0.0f);
        }
        mUniforms.upload(&u, sizeof(u));
        // The lookup counts receivers outside the map only where it is clipped (elsewhere none
        // can be hidden there): only then is the counter cleared and read back, a wait on the
        // GPU in the viewer's frames.
        const std::uint32_t zero = 0;
        if (clipped)
            glClearNamedBufferData(mStats.id(), GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, &zero);
        {
            ScopedPass pass(&ctx.timers, "pdsm-lookup");
            glBindBufferBase(GL_UNIFORM_BUFFER, BINDING_PDSM_UBO, mUniforms.id());
            glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BINDING_PDSM_STATS, mStats.id());
            glBindTextureUnit(TEXUNIT_POSITION, ctx.targets.position.id());
            glBindTextureUnit(TEXUNIT_NORMAL, ctx.targets.normal.id());
            glBindTextureUnit(TEXUNIT_PDSM_INDEX, mIndex.id());
            glBindTextureUnit(TEXUNIT_PDSM_DATA, mDataTexels.id());
            lookup.pick(cube, clipped).execute(ctx.targets.visibilityFbo, ctx.targets.width,
                                      ctx.targets.height);
        }
        std::uint32_t stats[PDSM_STAT_COUNT] = {};
        if (clipped) {
            glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT); // the lookup's atomics
            glGetNamedBufferSubData(mStats.id(), 0, sizeof(stats), stats);
        }
        return stats[PDSM_STAT_OUTSIDE];
    }

    void addCounters(const FrameContext& ctx, bool cached, std::uint32_t outside) {
        const bool clipped = std::any_of(mFaces.begin(), mFaces.end(),
                                         [](const geometry::Pdsm& m) { return m.grid.clipped; });
        const bool anyCasters = std::any_of(mFaces.begin(), mFaces.end(),
                                            [](const geometry::Pdsm& m) { return !m.grid.empty; });
        geometry::PdsmStats s;
        std::size_t bytes = 0;
        for (const geometry::Pdsm& m : mFaces) {
            s.points += m.stats.points;
            s.steps += m.stats.steps;
            s.texelsStored += m.stats.texelsStored;
            s.texelsRead += m.stats.texelsRead;
            s.codesKept += m.stats.codesKept;
            s.longest = std::max(s.longest, m.stats.longest);
            s.maxDeviation = std::max(s.maxDeviation, m.stats.maxDeviation);
            s.maxExcess = std::max(s.maxExcess, m.stats.maxExcess);
            s.buildMs += m.stats.buildMs;
            bytes += m.bytes();
        }
        ctx.addCounter("pdsm_cached", cached ? 1.0 : 0.0);
        ctx.addCounter("pdsm_building", mPending ? 1.0 : 0.0);
        // Sample maps drawn and read back in this frame: every face's at once headless, a batch
        // (kMapsPerBatch) a frame in the viewer while the last maps are drawn.
        ctx.addCounter("pdsm_maps_drawn", static_cast<double>(mMapsDrawn));
        ctx.addCounter("pdsm_building_percent", mPending ? buildingPercent(*mPending) : 0.0);
        ctx.addCounter("pdsm_samples", anyCasters ? static_cast<double>(mOptions.samples) : 0.0);
        ctx.addCounter("pdsm_faces", static_cast<double>(mFaces.size()));
        ctx.addCounter("pdsm_cube", mCube ? 1.0 : 0.0);
        // 1: the one map's extent, probed before it was built, left receivers of the view out:
        // the cube was built without it (pdsm_first_map_ms 0).
        ctx.addCounter("pdsm_cube_probed", mProbedCube ? 1.0 : 0.0);
        ctx.addCounter("pdsm_resolution", mOptions.resolution);
        ctx.addCounter("pdsm_tolerance", mOptions.tolerance);
        ctx.addCounter("pdsm_noise", mOptions.noise);
        ctx.addCounter("pdsm_points", static_cast<double>(s.points));
        ctx.addCounter("pdsm_texels_stored", s.texelsStored);
        // cull=on: the functions kept only where a receiver may read them (0 where not
        // applied); the texels some receiver reads, and the share of their depths kept.
        ctx.addCounter("pdsm_cull", mCulled ? 1.0 : 0.0);
        ctx.addCounter("pdsm_texels_read", s.texelsRead);
        ctx.addCounter("pdsm_depth_kept",
                       s.texelsRead ? static_cast<double>(s.codesKept) /
                                          (65536.0 * static_cast<double>(s.texelsRead))
                                    : 0.0);
        ctx.addCounter("pdsm_longest_function", s.longest);
        ctx.addCounter("pdsm_mean_function",
                       s.texelsStored ? static_cast<double>(s.points) / s.texelsStored : 0.0);
        ctx.addCounter("pdsm_steps", static_cast<double>(s.steps));
        ctx.addCounter("pdsm_max_deviation", s.maxDeviation);
        // At most 0: every stored function keeps its bound (tolerance and noise).
        ctx.addCounter("pdsm_max_excess", s.texelsStored ? s.maxExcess : 0.0f);
        ctx.addCounter("pdsm_bytes", static_cast<double>(bytes));
        // The GPU's copy as allocated: the index layers (R x R, 8 bytes a texel) and the data
        // buffer, kept at the largest maps' since the method was created.
        const double R = mOptions.resolution;
        ctx.addCounter("pdsm_buffer_bytes",
                       static_cast<double>(mData.size()) + R * R * 8.0 * mIndexLayers);
        ctx.addCounter("pdsm_maps_ms", mMapsMs);
        ctx.addCounter("pdsm_build_ms", s.buildMs);
        ctx.addCounter("pdsm_first_map_ms", mFirstMapMs);
        ctx.addCounter("pdsm_precompute_ms", precomputeMs() + mFirstMapMs);
        ctx.addCounter("pdsm_clipped", clipped ? 1.0 : 0.0);
        ctx.addCounter("pdsm_pixels_outside", outside);
        ctx.addCounter("pdsm_casters", static_cast<double>(mSetup.objects.size()));
    }

    // Deep maps being built, with what they are built for: the faces' sample maps are drawn
    // and read back one face at a time (on the GL thread), each face's merged on a CPU thread.
    struct Pending {
        std::shared_ptr<std::atomic<int>> rows; // rows merged so far, over every face
        int totalRows = 0;                      // the faces' rows
        geometry::RectLight light;
        std::uint32_t seed = 0;
        std::vector<std::uint32_t> subset;
        SampleMapSetup setup;
        // The receivers' triangles where the functions are kept only at the depths they may be
        // read (cull=on; null: every depth).
        std::shared_ptr<const std::vector<glm::vec3>> receivers;
        bool cube = false;
        bool frameClipped = false; // the one map's frame was clipped
        geometry::PcssFrame cubeFrame;
        std::vector<geometry::PdsmFace> faces;
        std::size_t next = 0; // the next face whose maps to draw
        // Of that face: its sample maps drawn and read back so far (the viewer draws a batch a
        // frame), and where they are read back to.
        std::size_t drawn = 0;
        std::shared_ptr<std::vector<float>> texels;
        std::future<geometry::Pdsm> current;
        std::vector<geometry::Pdsm> built;
        double mapsMs = 0.0;
        std::function<void(int, int)> report; // the headless progress
    };

    // How far a build has come: its sample maps read back and its rows merged, each a unit
    // (the viewer draws the maps a batch a frame, then merges the face's rows on a CPU thread:
    // counted by rows alone, the bar stood at 0 while a face's maps were drawn).
    static double buildingPercent(const Pending& p) {
        std::size_t maps = 0, mapsDone = p.drawn; // the faces before p.next are all read back
        for (std::size_t k = 0; k < p.faces.size(); ++k) {
            const geometry::SampleMapFrame& f = p.faces[k].frame;
            const std::size_t n = f.empty ? 0 : f.views.size();
            maps += n;
            if (k < p.next) mapsDone += n;
        }
        const double done = static_cast<double>(mapsDone) + p.rows->load();
        const double total = static_cast<double>(maps) + p.totalRows;
        return 100.0 * done / std::max(total, 1.0);
    }

    bool stale(const FrameContext& ctx) const {
        return !mBuilt || !(ctx.light == mLight) || ctx.settings.seed != mSeed ||
               (mWantCube && !mCube && mFrameClipped) ||
               !std::equal(ctx.casterSubset.begin(), ctx.casterSubset.end(), mSubset.begin(),
                           mSubset.end());
    }

    // Every object's triangles in world space, the receivers cull keeps the depths of: gathered
    // once (the scene's objects do not move within a run; a light moved every frame rebuilds
    // the maps every frame). Null where an object is dynamic: it may be anywhere when the map
    // is read, so every depth is kept.
    std::shared_ptr<const std::vector<glm::vec3>> receivers(const geometry::Scene& scene) {
        if (mReceiversGathered) return mReceivers;
        mReceiversGathered = true;
        const bool anyDynamic =
            std::any_of(scene.objects.begin(), scene.objects.end(),
                        [](const geometry::SceneObject& o) { return !o.isStatic; });
        if (anyDynamic) return mReceivers;
        auto triangles = std::make_shared<std::vector<glm::vec3>>();
        for (const geometry::SceneObject& o : scene.objects)
            for (const glm::uvec3& t : o.mesh.triangles)
                for (int k = 0; k < 3; ++k) triangles->push_back(o.mesh.positions[t[k]]);
        mReceivers = std::move(triangles);
        return mReceivers;
    }

    // Fits the maps of this frame's light and casters: one map along the light's normal where
    // it holds every receiver that may be hidden, else a map per face of the cube; and starts
    // the first face.
    Pending start(const FrameContext& ctx) {
        const auto t0 = Clock::now();
        Pending p;
        p.light = ctx.light;
        p.seed = ctx.settings.seed;
        p.subset.assign(ctx.casterSubset.begin(), ctx.casterSubset.end());
        p.setup = fitSampleMaps(ctx.scene, ctx.casters, p.subset, ctx.light, mOptions.samples,
                                p.seed);
        if (mOptions.cull) p.receivers = receivers(ctx.scene);
        geometry::jitterSampleMapGrids(p.setup.frame, mOptions.resolution);
        geometry::Aabb scene;
        for (const geometry::SceneObject& o : ctx.scene.objects) scene.extend(o.mesh.bounds());
        const geometry::SampleMapFrame& f = p.setup.frame;
        const geometry::PdsmGrid grid =
            geometry::fitPdsmGrid(f, ctx.light.center, scene, mOptions.resolution);
        // One map along the light's normal where the casters lie in front of every sample
        // within the maps' cap (the frame is not clipped): every receiver that may be hidden then
        // lies where some sample's map holds the casters, about the map's extent (what lies
        // past its cap is counted, pdsm_pixels_outside: none on the data/ scenes). Else (a lamp
        // in a room, casters at the light's plane) the cube.
        p.frameClipped = !f.empty && f.clipped;
        // Where the one map would be clipped, the lookup first counts this view's receivers
        // outside its extent (no functions needed): if there are any, the cube at once, without
        // building the one map only to find them (a level's spawn view spent 16 of its 68 s so).
        if (p.frameClipped && !mWantCube && runLookup(ctx, *mCurrentLookup, &grid) > 0) {
            mWantCube = true;
            mProbedCube = true;
        }
        if (!p.frameClipped || !mWantCube) {
            p.faces.push_back({0, f, grid});
        } else {
            p.cube = true;
            p.cubeFrame = geometry::fitPcssFrame(ctx.scene, ctx.light, p.setup.objects);
            std::vector<glm::vec2> samples;
            for (const geometry::SampleMapView& v : f.views) samples.push_back(v.st);
            p.faces = geometry::fitPdsmCube(p.cubeFrame, ctx.light, samples, ctx.scene,
                                            p.setup.objects, p.setup.bounds, scene,
                                            mOptions.resolution);
            for (geometry::PdsmFace& face : p.faces)
                geometry::jitterSampleMapGrids(face.frame, mOptions.resolution);
        }
        p.rows = std::make_shared<std::atomic<int>>(0);
        for (const geometry::PdsmFace& face : p.faces) p.totalRows += face.grid.rowCount();
        p.report = ctx.settings.waitForGpu ? ctx.settings.progress : std::function<void(int, int)>{};
        p.mapsMs = msSince(t0); // the fit (the cube's walks every caster triangle per face)
        drawNext(ctx, p, ctx.settings.waitForGpu || !mBuilt);
        return p;
    }

    // Draws the next face's sample maps and reads them back: all of them (`all`: headless, or
    // the first maps), else one batch of kMapsPerBatch (the viewer, while it draws the last
    // maps: a level's face took about 1 s for its 256 maps of 512², one frame held that long
    // per face); once the face's maps are all read back, starts merging them into its deep map
    // on a CPU thread.
    void drawNext(const FrameContext& ctx, Pending& p, bool all) {
        if (p.next >= p.faces.size()) return;
        const auto t0 = Clock::now();
        const geometry::PdsmFace& face = p.faces[p.next];
        const geometry::SampleMapFrame& f = face.frame;
        const int R = mOptions.resolution;
        const std::size_t layer = static_cast<std::size_t>(R) * static_cast<std::size_t>(R);
        if (p.drawn == 0) {
            // One read-back buffer, kept from face to face and build to build (a light moved
            // every frame would otherwise allocate and free k R^2 floats per face per frame); a
            // new one only while a merge or another build still holds it.
            if (!mReadBack || mReadBack.use_count() > 1)
                mReadBack = std::make_shared<std::vector<float>>();
            p.texels = mReadBack;
            if (!f.empty) p.texels->resize(layer * f.views.size());
        }
        if (!f.empty) {
            ScopedPass pass(&ctx.timers, "pdsm-sample-maps");
            while (p.drawn < f.views.size()) {
                const std::size_t count = std::min(static_cast<std::size_t>(mMaps->layers()),
                                                   f.views.size() - p.drawn);
                mMaps->draw(f, p.drawn, count, p.setup.objects, ctx.sceneGeometry,
                            kMapSlopeBias);
                glGetTextureSubImage(mMaps->maps().id(), 0, 0, 0, 0, R, R,
                                     static_cast<GLsizei>(count), GL_DEPTH_COMPONENT, GL_FLOAT,
                                     static_cast<GLsizei>(count * layer * sizeof(float)),
                                     p.texels->data() + p.drawn * layer);
                p.drawn += count;
                mMapsDrawn += count;
                if (!all) break;
            }
        }
        const double ms = msSince(t0);
        p.mapsMs += ms;
        ctx.addCpuTime("pdsm-sample-maps", ms);
        if (!f.empty && p.drawn < f.views.size()) return; // the rest in the next frames
        std::shared_ptr<std::vector<float>> texels = std::move(p.texels);
        p.drawn = 0;
        geometry::PdsmBuildSettings settings{.tolerance = mOptions.tolerance,
                                             .noise = mOptions.noise,
                                             .receivers = p.receivers,
                                             .readSpanTexels = kReceiverPlaneSpan,
                                             .readOffsetTexels =
                                                 mOptions.normalOffset * PDSM_OFFSET_MAX_TAN};
        if (mOptions.ownPlane) // only receivers facing some of the light read the map
            for (const float s : {-1.0f, 1.0f})
                for (const float t : {-1.0f, 1.0f})
                    settings.lightCorners.push_back(p.light.point(s, t));
        int before = 0;
        for (std::size_t k = 0; k < p.next; ++k) before += p.faces[k].grid.rowCount();
        const int total = p.totalRows;
        settings.progress = [rows = p.rows, report = p.report, before, total](int done, int) {
            rows->store(before + done);
            if (report) report(before + done, total);
        };
        // The frame (and the maps' copy) live in the task; nothing of this frame is referenced.
        p.current = std::async(std::launch::async,
                               [frame = f, grid = face.grid, texels, settings, R]() {
                                   return geometry::buildPdsm(frame, grid, {R, *texels},
                                                              settings);
                               });
        ++p.next;
    }

    // Takes each face's finished merge and starts the next face's; true when every face is
    // merged. `wait`: waits for the merges (headless), else returns at one still running.
    bool advance(const FrameContext& ctx, Pending& p, bool wait) {
        for (;;) {
            if (p.current.valid()) {
                if (!wait && p.current.wait_for(std::chrono::seconds(0)) !=
                                 std::future_status::ready)
                    return false;
                p.built.push_back(p.current.get());
            }
            if (p.next >= p.faces.size()) return true;
            const std::size_t face = p.next;
            drawNext(ctx, p, wait);
            if (p.next == face) return false; // its maps go on in the next frames
        }
    }

    // advance() on mPending: a failed build is dropped, not tried again as it is.
    bool advanceOrDrop(const FrameContext& ctx, Pending& p, bool wait) {
        try {
            return advance(ctx, p, wait);
        } catch (...) {
            mPending.reset();
            throw;
        }
    }

    // Takes a finished build's maps and uploads them.
    void adopt(Pending&& p) {
        mFaces = std::move(p.built);
        mFaceIds.clear();
        for (const geometry::PdsmFace& f : p.faces) mFaceIds.push_back(f.face);
        mCube = p.cube;
        mCulled = p.receivers != nullptr;
        mFrameClipped = p.frameClipped;
        mCubeFrame = p.cubeFrame;
        // The cube's lookup derives a face's axes from the light's as pcss's faces have them
        // (pdsm-lookup.frag's pdsmFace, these statements): a face built with others would be
        // misread. Checked once per build.
        if (mCube)
            for (std::size_t f = 0; f < mFaces.size(); ++f) {
                const int k = p.faces[f].face;
                const geometry::PdsmGrid& g = mFaces[f].grid;
                glm::vec3 axis = k < 2 ? mCubeFrame.normal : k < 4 ? mCubeFrame.eu : mCubeFrame.ev;
                if (k & 1) axis = -axis;
                const glm::vec3 b1 = k == 2 || k == 3 ? mCubeFrame.ev : mCubeFrame.eu;
                const glm::vec3 b2 = k < 2 ? mCubeFrame.ev : mCubeFrame.normal;
                if (!g.empty && (g.eu != b1 || g.ev != b2 || g.n != axis))
                    throw std::logic_error("pdsm: the cube's face " + std::to_string(k) +
                                           " was built with axes other than pcss's");
            }
        mLight = p.light;
        mSeed = p.seed;
        mSubset = std::move(p.subset);
        mSetup = std::move(p.setup);
        mMapsMs = p.mapsMs;
        mFirstMapMs = 0.0;
        const auto t0 = Clock::now();
        upload();
        mUploadMs = msSince(t0);
        mBuilt = true;
        mPending.reset();
    }

    void upload() {
        const int R = mOptions.resolution;
        const int layers = std::max(static_cast<int>(mFaces.size()), 1);
        if (mIndexLayers != layers) {
            mIndex = Texture({.target = GL_TEXTURE_2D_ARRAY,
                              .width = R,
                              .height = R,
                              .layers = layers,
                              .format = GL_RG32UI,
                              .label = "pdsm-index"});
            mIndexLayers = layers;
        }
        // The faces' points one after the other; each face's index shifted by the groups
        // before it.
        std::size_t words = 0, points = 0;
        for (const geometry::Pdsm& m : mFaces) {
            words += m.data.size();
            points += m.stats.points;
        }
        // A buffer texture holds GL_MAX_TEXTURE_BUFFER_SIZE texels of four points each.
        GLint maxTexels = 0;
        glGetIntegerv(GL_MAX_TEXTURE_BUFFER_SIZE, &maxTexels);
        if (words / 3 > static_cast<std::size_t>(maxTexels))
            throw geometry::InputError(
                "pdsm: the deep maps hold " + std::to_string(points) +
                " points, more than one buffer texture of GL_MAX_TEXTURE_BUFFER_SIZE = " +
                std::to_string(maxTexels) + " texels of four holds; raise tolerance or lower " +
                "resolution");
        // The data buffer is kept, grown to what the maps need where they need more (the
        // largest maps built so far), each face's points uploaded at its offset: a light moved
        // every frame rebuilds the maps every frame.
        const std::size_t usedWords = std::max<std::size_t>(words, 3);
        mData.reserve(usedWords * sizeof(std::uint32_t), false);
        std::size_t offset = 0; // in words
        std::vector<std::uint32_t> index;
        for (std::size_t f = 0; f < mFaces.size(); ++f) {
            const geometry::Pdsm& m = mFaces[f];
            const auto base = static_cast<std::uint32_t>(offset / 3);
            index = m.index;
            for (std::size_t i = 0; i < index.size(); i += 2) index[i] += base;
            // A side face's band fills the layer's first rows; the row above it repeats its
            // last, which the bilinear gathers at its edge read (as CLAMP_TO_EDGE does at the
            // layer's).
            const int rows = m.grid.rowCount();
            const int filled = std::min(rows + 1, R);
            if (filled > rows)
                index.insert(index.end(), index.end() - 2 * static_cast<std::ptrdiff_t>(R),
                             index.end());
            glTextureSubImage3D(mIndex.id(), 0, 0, 0, static_cast<GLint>(f), R, filled, 1,
                                GL_RG_INTEGER, GL_UNSIGNED_INT, index.data());
            mData.upload(m.data.data(), m.data.size() * sizeof(std::uint32_t),
                         offset * sizeof(std::uint32_t));
            offset += m.data.size();
        }
        if (offset == 0) { // a texture is bound either way
            const std::uint32_t zeros[3] = {};
            mData.upload(zeros, sizeof(zeros));
        }
        if (!mDataTexels) {
            GLuint id = 0;
            glCreateTextures(GL_TEXTURE_BUFFER, 1, &id);
            mDataTexels = Handle<TextureDeleter>(id);
        }
        // Re-pointed every upload: the buffer's name changes where it grew.
        glTextureBufferRange(mDataTexels.id(), GL_RGB32UI, mData.id(), 0,
                             static_cast<GLsizeiptr>(usedWords * sizeof(std::uint32_t)));
    }

    struct TextureDeleter {
        void operator()(GLuint id) const { glDeleteTextures(1, &id); }
    };

    MethodResources mResources; // shaders and scene, for the dynamic objects' method
    PdsmOptions mOptions;
    PdsmLookup mLookup, mLookupWithoutPlane;
    const PdsmLookup* mCurrentLookup = nullptr; // this frame's (one of the two)
    VisibilityProduct mProduct;
    std::unique_ptr<VisibilityMethod> mDynamic; // auto, on the dynamic objects
    int mWidth = 0, mHeight = 0;
    Buffer mUniforms, mStats, mData;
    Texture mIndex;
    Handle<TextureDeleter> mDataTexels;
    std::optional<SampleMapPass> mMaps;
    std::shared_ptr<std::vector<float>> mReadBack; // the sample maps read back (drawNext)
    std::size_t mMapsDrawn = 0;                     // in this frame
    std::vector<geometry::Pdsm> mFaces; // the built maps, a layer of mIndex each
    std::vector<int> mFaceIds;          // their cube faces (0 for the one map)
    bool mCube = false;         // the built maps are the cube's
    bool mCulled = false;       // the built maps keep only the depths receivers read
    std::shared_ptr<const std::vector<glm::vec3>> mReceivers; // receivers(), once
    bool mReceiversGathered = false;
    bool mFrameClipped = false; // the one map's frame was clipped
    // A view found receivers outside the one map where they may be hidden: the cube wherever
    // the one map's frame is clipped.
    bool mWantCube = false;
    bool mProbedCube = false; // the cube chosen by the probe, before any one map was built
    geometry::PcssFrame mCubeFrame;
    int mIndexLayers = 0;
    SampleMapSetup mSetup;
    std::optional<Pending> mPending;
    double mMapsMs = 0.0, mUploadMs = 0.0;
    double mFirstMapMs = 0.0; // the one map built before the cube in the same frame
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
