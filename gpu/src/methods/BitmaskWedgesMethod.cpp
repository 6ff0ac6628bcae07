// wedges-bitmask: per silhouette group, the set of the light's N samples it hides, as a bit
// mask; groups combine exactly, V = 1 - popcount(OR over groups) / N (geometry/shadow/LightMask.h).
// Per batch of groups that cannot interact on screen (GroupBatches.h), scissored to the batch:
// - the groups' own z-fail volumes into the stencil (the centre's count of each group);
// - their wedges find, per fragment, the samples their edge's region holds
//   (shaders/wedge-bitmask.frag) and record them for the group, by one of two rules
//   (`combine`):
//   - counts (default): each sample's signed crossing count, 4 bits biased by 8, eight to a
//     32-bit layer of an R32UI array, by image atomic adds (order-free, no carries while each
//     count stays in [-8, 7]); where they touched, bitmask-combine.frag reads the stencil's
//     centre count (a STENCIL_INDEX view of the frame's depth-stencil) and hides the samples
//     whose centre + count is non-zero. Exact wherever the counts fit, folds included;
//   - parity: XOR of the samples into the group mask by the fixed-function logic op (no
//     atomics, nothing read back); where the centre is hidden the complement is taken. Exact
//     while the group's projection covers no sample twice; where it folds (open level geometry
//     behind itself, a torus seen obliquely) a doubly covered sample reads as lit;
// - the group's mask is ORed into the final mask by the logic op; in the group's umbra, where no
//   wedge reached, every sample;
// - after the last batch, V from the final mask's popcount (shaders/bitmask-resolve.frag).
#include "engine/DebugViews.h"
#include "engine/Method.h"
#include "engine/PotentialSet.h"
#include "passes/WedgeTilePass.h"
#include "passes/FullscreenPass.h"
#include "passes/StencilVolumePass.h"
#include "passes/WedgePass.h"
#include "engine/ShaderBindings.h"
#include "engine/MethodOptions.h"
#include "methods/GroupBatches.h"
#include "methods/SilhouetteBatchMethod.h"
#include "methods/MethodUtil.h"

#include <geometry/shadow/LightMask.h>

#include <array>
#include <memory>
#include <numbers>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace gpu {

namespace {

// The method's options (engine/MethodOptions.h) and what follows from them.
struct MaskLayout : BitmaskOptions {

    int targets() const { return samples > 128 ? 2 : 1; }
    GLenum format() const {
        return samples == 32 ? GL_R32UI : samples == 64 ? GL_RG32UI : GL_RGBA32UI;
    }
    std::size_t bytesPerTarget() const { return samples == 32 ? 4 : samples == 64 ? 8 : 16; }
    // The tiled evaluation's resolve (the mark in a layer of its own, not the stencil).
    std::vector<std::string> tiledDefines() const {
        std::vector<std::string> d = defines();
        d.push_back("BITMASK_TILED 1");
        return d;
    }
    std::vector<std::string> defines() const {
        std::vector<std::string> d{"BITMASK_SAMPLES " + std::to_string(samples)};
        if (rotated) d.push_back("BITMASK_ROTATED 1");
        if (counts) d.push_back("BITMASK_COUNTS 1");
        if (potential) {
            d.push_back("BITMASK_POTENTIAL 1");
            d.push_back("WEDGE_APEXES 1");
        }
        return d;
    }
    // The parity variant's (the umbra step of combine=counts draws with it).
    std::vector<std::string> parityDefines() const {
        MaskLayout l = *this;
        l.counts = false;
        l.potential = false;
        return l.defines();
    }
};

MaskLayout maskLayout(std::span<const ParameterValue> parameters) {
    return {bitmaskOptions(parameters)};
}

// Logic ops on the integer targets (blending does not apply to them).
constexpr PipelineState kCombineState{.logicOp = true, .logicOpMode = GL_OR};

enum CombineMode : GLuint { kGroupMask = 0, kComplement = 1, kEverySample = 2 };

// silhouettes=potential evaluate=tiles: the resolve in two draws split by a stencil of their own.
// bitmask-resolve-split.frag marks the pixels that need the full resolve (a wedge added to their
// counts, or their own plane may cut the light); the full resolve runs there, its lit variant
// (BITMASK_RESOLVE_LIT: D(P, c) alone) everywhere else, with the stencil tested before the
// shader. On llvmpipe, which runs every branch of a shader masked, the full resolve cost its
// whole length at every pixel: on data/box.json at 256², 48 of the frame's 204 M instructions.
// The same V and masks as one draw of the full resolve.
class TiledResolve {
public:
    TiledResolve(const ShaderLoader& shaders, const MaskLayout& layout)
        : mSplit(shaders, "bitmask-resolve-split.frag", "bitmask-resolve-split", kSplitState,
                 layout.defines()),
          mFull(shaders, "bitmask-potential-resolve.frag", "bitmask-potential-resolve-tiled",
                drawn(1), layout.tiledDefines()),
          mLit(shaders, "bitmask-potential-resolve.frag", "bitmask-potential-resolve-lit", drawn(0),
               withLit(layout.tiledDefines())) {}

    void resize(int width, int height) {
        mStencil = Texture({.width = width, .height = height, .format = GL_STENCIL_INDEX8,
                            .label = "bitmask-resolve-split"});
        mSplitFbo = Framebuffer({.attachments = {{GL_STENCIL_ATTACHMENT, &mStencil}},
                                 .label = "bitmask-resolve-split"});
    }
    // The resolve's framebuffer attaches it (as its stencil).
    const Texture& split() const { return mStencil; }

    // The caller binds what the full resolve reads (counts, stencil view, area, G-buffer).
    // `setUniforms` for the full resolve; the lit variant reads the estimate alone.
    void execute(const Framebuffer& target, int width, int height, GLuint estimate,
                 const std::function<void()>& setUniforms) const {
        applyState(PipelineState{}); // the clear writes every stencil bit
        const GLint zero = 0;
        glClearNamedFramebufferiv(mSplitFbo.id(), GL_STENCIL, 0, &zero);
        mSplit.execute(mSplitFbo, width, height);
        mFull.execute(target, width, height, drawn(1), setUniforms);
        mLit.execute(target, width, height, drawn(0), [&] { glUniform1ui(0, estimate); });
    }

private:
    static constexpr PipelineState kSplitState{
        .colorWrite = false,
        .stencilTest = true,
        .stencilFront = {.func = GL_ALWAYS, .ref = 1, .depthPass = GL_REPLACE},
        .stencilBack = {.func = GL_ALWAYS, .ref = 1, .depthPass = GL_REPLACE},
    };
    // Where the split's stencil is `ref`, unchanged.
    static constexpr PipelineState drawn(GLint ref) {
        return PipelineState{.stencilTest = true,
                             .stencilWriteMask = 0,
                             .stencilFront = {.func = GL_EQUAL, .ref = ref},
                             .stencilBack = {.func = GL_EQUAL, .ref = ref}};
    }
    static std::vector<std::string> withLit(std::vector<std::string> defines) {
        defines.push_back("BITMASK_RESOLVE_LIT 1");
        return defines;
    }

    FullscreenPass mSplit, mFull, mLit;
    Texture mStencil;
    Framebuffer mSplitFbo;
};

class BitmaskWedgesMethod final : public SilhouetteBatchMethod {
public:
    explicit BitmaskWedgesMethod(const MethodResources& r)
        : BitmaskWedgesMethod(r, maskLayout(r.parameters)) {}

    bool countsOwnPlane() const override { return mLayout.potential; }

    BitmaskWedgesMethod(const MethodResources& r, const MaskLayout& layout)
        : SilhouetteBatchMethod(r.shaders, wedgePass(r.shaders, layout)), mLayout(layout),
          mCombine(r.shaders, "bitmask-combine.frag", "bitmask-combine", kCombineState,
                   mLayout.defines()),
          mUmbra(r.shaders, "bitmask-combine.frag", "bitmask-umbra", kCombineState,
                 mLayout.parityDefines()),
          mClear(r.shaders, mLayout.counts ? "bitmask-counts-reset.frag" : "bitmask-clear.frag",
                 "bitmask-clear", PipelineState{}, mLayout.defines()),
          mResolve(r.shaders, "bitmask-resolve.frag", "bitmask-resolve", PipelineState{},
                   mLayout.defines()),
          mPotentialResolve(r.shaders, "bitmask-potential-resolve.frag", "bitmask-potential-resolve",
                            PipelineState{}, mLayout.defines()),
          mReceiverNudge(r.shaders, "receiver-nudge.frag", "receiver-nudge", kReceiverNudgeState),
          mTiles(layout.potential && layout.evaluate != BitmaskOptions::Evaluate::Raster
                     ? std::make_unique<WedgeTilePass>(r.shaders, layout.defines())
                     : nullptr),
          mTiledResolve(layout.potential && layout.evaluate != BitmaskOptions::Evaluate::Raster
                            ? std::make_unique<TiledResolve>(r.shaders, layout)
                            : nullptr),
          mSamples({.size = 0, .label = "light-samples"}),
          mMaskStats({.size = MASK_STAT_COUNT * sizeof(std::uint32_t), .label = "mask-stats"}) {}

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
        mFinalNoStencilFbo = Framebuffer({.attachments = final, .label = "bitmask-final"});
        if (mLayout.counts)
            mCounts = Texture({.target = GL_TEXTURE_2D_ARRAY, .width = width, .height = height,
                               .layers = countLayers(), .format = GL_R32UI,
                               .label = "bitmask-counts"});
        if (mLayout.potential) {
            mArea = Texture({.width = width, .height = height, .format = GL_RGBA32F,
                             .label = "bitmask-area"});
            mAreaFbo = Framebuffer({.attachments = {{GL_COLOR_ATTACHMENT0, &mArea}},
                                    .label = "bitmask-area"});
            mResolveVisibility = 0;
        }
        if (mTiledResolve) mTiledResolve->resize(width, height);
        mStencilView.reset();
        mWidth = width;
        mHeight = height;
    }

    std::size_t targetBytesPerPixel() const override {
        return 2 * std::size_t(mLayout.targets()) * mLayout.bytesPerTarget() +
               (mLayout.counts ? 4 * std::size_t(countLayers()) : 0) + // 4 bits a sample
               (mLayout.potential ? 16 : 0) + // A per quadrant (RGBA32F)
               (mTiledResolve ? 1 : 0);       // the resolve's split (a stencil byte)
    }

    void execute(const FrameContext& ctx) override {
        if (mLayout.potential) {
            executePotential(ctx);
            return;
        }
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
        bindSampleTable();
        if (mLayout.counts) {
            const GLuint bias = 0x88888888u; // every 4-bit count at its bias, 8
            glClearTexImage(mCounts.id(), 0, GL_RED_INTEGER, GL_UNSIGNED_INT, &bias);
            glBindImageTexture(IMAGE_GROUP_COUNTS, mCounts.id(), 0, GL_TRUE, 0, GL_READ_WRITE,
                               GL_R32UI);
            bindStencilView(t);
        }
        runBatches(ctx, mGroupFbo);
        {
            ScopedPass pass(&ctx.timers, "resolve");
            for (int i = 0; i < mLayout.targets(); ++i)
                glBindTextureUnit(TEXUNIT_FINAL0 + i, mFinal[i].id());
            mResolve.execute(t.visibilityFbo, t.width, t.height);
        }
        ctx.addCounter("light_samples", mLayout.samples);
    }

    bool drawDebug(DebugView view, const FrameContext& ctx, DebugViews& debug) override {
        if (view != DebugView::WedgeWireframe) return false;
        if (!mLayout.potential) return drawWedgeWireframe(ctx, mWedges, debug);
        // The potential set's own wedges (and silhouette cones) as this frame set them up and
        // drew them (depth-aware culling may have left some out), not the centre's edges.
        mPotential.bind(ctx.casters);
        const DrawSet& drawn = mDrawnWedges ? *mDrawnWedges : mPotential.wedges();
        debug.drawWedgeLines(mWedges, ctx.targets, drawn);
        std::size_t edges = 0;
        for (const GLsizei n : drawn.edgeCount) edges += static_cast<std::size_t>(n);
        debug.note = "wedges: " + std::to_string(edges / 2) + " of " +
                     std::to_string(mPotential.wedgeCount()) +
                     " potential silhouette edges' hulls as drawn (cyan; dim where behind a "
                     "surface; an edge seen end-on from the light as its two silhouette cones)";
        return true;
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
    // Layers of the counts array: eight 4-bit counts each, with silhouettes=potential two
    // checksum layers, and with the tiled evaluation its mark layer and estimate=moments' P.
    int countLayers() const {
        return mLayout.samples / 8 + (mLayout.potential ? 2 : 0) + (tiled() ? 2 : 0);
    }
    // evaluate=tiles or auto: the tiled evaluation's passes exist (the counts array holds its
    // mark and moment layers).
    bool tiled() const {
        return mLayout.potential && mLayout.evaluate != BitmaskOptions::Evaluate::Raster;
    }
    // estimate=moments: the tiled evaluation also sums the pairs' overlaps (every frame tiled
    // that its limits allow, whatever the number of edges).
    bool moments() const {
        return tiled() && mLayout.estimate == BitmaskOptions::Estimate::Moments;
    }

    // silhouettes=potential: one stencil pass (D(P, c), two-sided, every caster), one wedge
    // pass over every potential silhouette edge (counts and A), one resolve.
    void executePotential(const FrameContext& ctx) {
        const Targets& t = ctx.targets;
        uploadPattern(ctx.settings.seed);
        {
            const auto t0 = Clock::now();
            mPotential.update(ctx.casters, ctx.casterSubset, ctx.light);
            ctx.addCpuTime("potential-silhouettes", msSince(t0));
        }
        mPotential.bind(ctx.casters);
        bindSampleTable();
        glNamedFramebufferTexture(mAreaFbo.id(), GL_DEPTH_STENCIL_ATTACHMENT, t.depthStencil.id(),
                                  0);
        if (mResolveVisibility != t.visibility.id()) {
            std::vector<FramebufferAttachment> a{{GL_COLOR_ATTACHMENT0, &t.visibility}};
            for (int i = 0; i < mLayout.targets(); ++i)
                a.push_back({GLenum(GL_COLOR_ATTACHMENT1 + i), &mFinal[i]});
            // (The tiled resolve's split: its stencil, which no shader samples.)
            if (mTiledResolve) a.push_back({GL_STENCIL_ATTACHMENT, &mTiledResolve->split()});
            mResolveFbo = Framebuffer({.attachments = a, .label = "bitmask-potential-resolve"});
            mResolveVisibility = t.visibility.id();
        }
        const GLuint none = 0u;
        glClearNamedBufferData(mMaskStats.id(), GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, &none);
        glBindImageTexture(IMAGE_GROUP_COUNTS, mCounts.id(), 0, GL_TRUE, 0, GL_READ_WRITE,
                           GL_R32UI);
        // Depth-aware culling (as the per-group methods do, RenderSettings::depthAwareCulling):
        // the wedges of edges whose shadow cone meets no visible surface are neither set up nor
        // drawn (levels: the edges of other rooms).
        const DrawSet* wedgeSet = &mPotential.wedges();
        std::span<const CasterRange> wedgeRuns = mPotential.wedgeRuns();
        std::size_t hiddenWedges = 0;
        if (depthAwareFrame(ctx)) {
            const SurfaceTiles tiles = measureSurface(ctx, mSurface);
            const auto t0 = Clock::now();
            const std::vector<std::uint8_t> keep = segmentsReachingSurface(
                mPotential.edgeStarts(), mPotential.edgeEnds(), ctx.casters.sceneBounds(), tiles,
                ctx.light, ctx.viewProj, t.width, t.height);
            mPotential.keptWedges(keep, mKeptWedges, mKeptRuns);
            for (const std::uint8_t k : keep) hiddenWedges += k == 0;
            ctx.addCpuTime("depth-aware-culling", msSince(t0));
            wedgeSet = &mKeptWedges;
            wedgeRuns = mKeptRuns;
        }
        mDrawnWedges = wedgeSet;
        {
            ScopedPass pass(&ctx.timers, "wedge-setup");
            mWedges.beginFrame(mPotential.wedgeSlots());
            mWedges.setup(wedgeRuns, mPotential.twinOffset());
            clearStencil(t);
        }
        {
            ScopedPass pass(&ctx.timers, "shadow-volume");
            if (mPotential.flatTriangles() > 0) {
                glBindTextureUnit(TEXUNIT_POSITION, t.position.id());
                glBindTextureUnit(TEXUNIT_NORMAL, t.normal.id());
                mReceiverNudge.execute(t.visibilityFbo, t.width, t.height);
            }
            mVolumes.drawCentre(t.visibilityFbo, t, mPotential.volumes());
        }
        // evaluate=tiles (or auto with kAutoTiledEdges potential edges drawn or more: on fewer
        // the raster pass wastes little and the tiled passes' fixed cost shows; bench-tiles.md);
        // the raster pass otherwise, or where this frame's tile lists would pass their limits
        // (counted: wedge_tiles_over_limit).
        std::size_t drawnEdges = 0;
        for (const GLsizei n : wedgeSet->edgeCount) drawnEdges += static_cast<std::size_t>(n);
        drawnEdges /= 2; // the set holds each edge's twin slot too
        const bool tryTiles =
            tiled() && (mLayout.evaluate == BitmaskOptions::Evaluate::Tiles || moments() ||
                        drawnEdges >= BitmaskOptions::kAutoTiledEdges);
        bool tiledFrame = false;
        // The facet normals: the wedge passes take a receiver whose plane holds the light's
        // centre a little towards the eye (lib/BitmaskEdge.glsl potentialReceiver).
        glBindTextureUnit(TEXUNIT_NORMAL, t.normal.id());
        if (tryTiles) {
            ScopedPass pass(&ctx.timers, "wedges");
            mWedges.bindWedges();
            if (moments()) bindStencilView(t);
            // The mark layer: the evaluation writes the pixels of tiles with a list only.
            glClearTexSubImage(mCounts.id(), 0, 0, 0, mLayout.samples / 8 + 2, t.width, t.height,
                               1, GL_RED_INTEGER, GL_UNSIGNED_INT, &none);
            tiledFrame = mTiles->run(t, *wedgeSet, mPotential.wedgeSlots(), mArea, mSamples,
                                     ctx.settings.wedgeTileEntryLimit, moments());
        }
        if (!tiledFrame) {
            ScopedPass pass(&ctx.timers, "wedges");
            applyState(PipelineState{}); // colour writes on, no scissor: whole-frame clears
            const float zero[4] = {0.0f, 0.0f, 0.0f, 0.0f};
            glClearNamedFramebufferfv(mAreaFbo.id(), GL_COLOR, 0, zero);
            const GLuint bias = 0x88888888u;
            const int layers = mLayout.samples / 8;
            glClearTexSubImage(mCounts.id(), 0, 0, 0, 0, t.width, t.height, layers,
                               GL_RED_INTEGER, GL_UNSIGNED_INT, &bias);
            glClearTexSubImage(mCounts.id(), 0, 0, 0, layers, t.width, t.height, 2,
                               GL_RED_INTEGER, GL_UNSIGNED_INT, &none);
            // Marking the stencil where a wedge reached: the resolve skips the other pixels.
            mWedges.draw(mAreaFbo, t, *wedgeSet, nullptr, /*markTouched=*/true);
        }
        {
            ScopedPass pass(&ctx.timers, "resolve");
            glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT);
            bindStencilView(t);
            glBindTextureUnit(TEXUNIT_PARTS0, mArea.id());
            glBindTextureUnit(TEXUNIT_POSITION, t.position.id());
            glBindTextureUnit(TEXUNIT_NORMAL, t.normal.id());
            glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BINDING_MASK_STATS, mMaskStats.id());
            const GLuint estimate = GLuint(mLayout.estimate);
            const auto uniforms = [&] {
                glUniform1ui(0, estimate);
                glUniform2ui(1, mRunQuadrants[0], mRunQuadrants[1]);
            };
            if (tiledFrame)
                mTiledResolve->execute(mResolveFbo, t.width, t.height, estimate, uniforms);
            else
                mPotentialResolve.execute(mResolveFbo, t.width, t.height, PipelineState{},
                                          uniforms);
            glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_TEXTURE_UPDATE_BARRIER_BIT |
                            GL_BUFFER_UPDATE_BARRIER_BIT);
        }
        WedgeCounts counts = mWedges.counts();
        if (tiled()) ctx.addCounter("wedge_evaluation_tiled", tiledFrame ? 1.0 : 0.0);
        if (tryTiles) {
            const WedgeTileStats& tileStats = mTiles->stats();
            ctx.addCounter("wedge_tiles_over_limit", tiledFrame ? 0.0 : 1.0);
            ctx.addCounter("wedge_tiles_truncated", static_cast<double>(tileStats.truncated));
            if (tiledFrame) {
                // The pairs that passed the fragment shader's discards (the raster pass's
                // fragments that pass them: its samples-passed query on llvmpipe).
                counts.fragments = tileStats.pairsAdded;
                ctx.addCounter("wedge_tile_entries", static_cast<double>(tileStats.entries));
                ctx.addCounter("wedge_tiles", static_cast<double>(tileStats.tiles));
                ctx.addCounter("wedge_tiles_active", static_cast<double>(tileStats.activeTiles));
                ctx.addCounter("wedge_tiles_refilled", static_cast<double>(tileStats.refilled));
                if (moments())
                    ctx.addCounter("wedge_moment_reruns",
                                   static_cast<double>(tileStats.momentRerun));
            }
        }
        addWedgeCounters(ctx, counts, mPotential.wedgeRuns());
        ctx.addCounter("wedges_silhouette_cones", counts.cones);
        ctx.addCounter("wedges_hidden", static_cast<double>(hiddenWedges));
        std::array<std::uint32_t, MASK_STAT_COUNT> stats{};
        glGetNamedBufferSubData(mMaskStats.id(), 0, sizeof(stats), stats.data());
        const geometry::PotentialEdgeStats& e = mPotential.stats();
        ctx.addCounter("wedges_centre_silhouette", mPotential.centreEdgeCount());
        ctx.addCounter("potential_interior_edges", static_cast<double>(e.interior));
        ctx.addCounter("potential_boundary_edges", static_cast<double>(e.boundary));
        ctx.addCounter("potential_nonmanifold_edges", static_cast<double>(e.nonManifold));
        ctx.addCounter("centre_in_plane_triangles", mPotential.flatTriangles());
        ctx.addCounter("count_overflow_pixels", stats[MASK_STAT_OVERFLOW]);
        ctx.addCounter("count_negative_pixels", stats[MASK_STAT_NEGATIVE]);
        ctx.addCounter("own_plane_pixels", stats[MASK_STAT_OWN_PLANE]);
        if (moments()) {
            ctx.addCounter("moment_pixels", stats[MASK_STAT_MOMENTS]);
            ctx.addCounter("moment_pixels_fallback", stats[MASK_STAT_MOMENTS_FALLBACK]);
        }
        ctx.addCounter("light_samples", mLayout.samples);
    }

    static WedgePass wedgePass(const ShaderLoader& shaders, const MaskLayout& layout) {
        return WedgePass(shaders,
                         layout.potential ? WedgePass::Output::BitmaskPotential
                         : layout.counts  ? WedgePass::Output::BitmaskCounts
                                          : WedgePass::Output::Bitmask,
                         layout.defines());
    }

    void combine(const FrameContext& ctx, const GroupBatch&, const TouchedStates& states) override {
        if (mLayout.counts) {
            combineCounts(ctx.targets, states.touched);
            return;
        }
        combineMask(ctx.targets, states.lit, kGroupMask);
        combineMask(ctx.targets, states.occluded, kComplement);
    }

    void reset(const FrameContext& ctx, const GroupBatch&, const PipelineState& stencil) override {
        mClear.execute(mGroupFbo, ctx.targets.width, ctx.targets.height, stencil, [] {});
        // The next batch's wedges add to the counts just reset.
        if (mLayout.counts) glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
    }

    void umbra(const FrameContext& ctx, const GroupBatch&, const UmbraStates& states) override {
        combineMask(ctx.targets, states.zero, kEverySample);
    }

    // The light-samples table as a storage buffer (the wedge fragment shader) and as a uniform
    // block (lib/Bindings.h BINDING_LIGHT_SAMPLES_UBO: the tiled evaluation, the moments pass
    // and the potential resolve's own-plane samples, where llvmpipe reads a uniform per lane in
    // about half the instructions of a buffer's or texel's).
    void bindSampleTable() const {
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BINDING_LIGHT_SAMPLES, mSamples.id());
        glBindBufferBase(GL_UNIFORM_BUFFER, BINDING_LIGHT_SAMPLES_UBO, mSamples.id());
    }

    void uploadPattern(std::uint32_t seed) {
        if (mSamples.size() > 0 && seed == mSeed) return;
        // (s, t, angle about the centre, quadrant of its run of 8) per sample, in the
        // pattern's angle order (shaders/wedge-bitmask.frag finds the run between two rays by
        // bisection; bitmask-potential-resolve.frag sums per quadrant, a word at a time).
        const std::vector<glm::vec2> pattern = geometry::lightMaskPattern(mLayout.samples, seed);
        const std::vector<int> runQuadrants = geometry::lightMaskRunQuadrants(pattern);
        std::vector<glm::vec4> table;
        for (std::size_t i = 0; i < pattern.size(); ++i)
            table.emplace_back(pattern[i], geometry::maskSampleAngle(pattern[i]),
                               static_cast<float>(runQuadrants[i / 8]));
        // Then, per angle bin's start, the first sample at or after it (LIGHT_SAMPLE_ANGLE_BINS,
        // lib/Bindings.h): where the shaders' bisection for a ray's first sample starts.
        std::size_t first = 0;
        for (int b = 0; b <= LIGHT_SAMPLE_ANGLE_BINS; ++b) {
            const double start =
                -std::numbers::pi + 2.0 * std::numbers::pi * b / LIGHT_SAMPLE_ANGLE_BINS;
            while (first < pattern.size() && double(table[first].z) < start) ++first;
            const std::size_t entry = b == LIGHT_SAMPLE_ANGLE_BINS ? pattern.size() : first;
            table.emplace_back(static_cast<float>(entry), 0.0f, 0.0f, 0.0f);
        }
        // At most 256 samples and the bins: 8.2 KB, within the 16 KB of a uniform block that
        // every GL 4.5 driver allows; checked, for a driver that reports less.
        GLint maxBlock = 0;
        glGetIntegerv(GL_MAX_UNIFORM_BLOCK_SIZE, &maxBlock);
        if (table.size() * sizeof(glm::vec4) > static_cast<std::size_t>(maxBlock))
            throw std::runtime_error("wedges-bitmask: the light-samples table (" +
                                     std::to_string(table.size() * sizeof(glm::vec4)) +
                                     " bytes) is larger than GL_MAX_UNIFORM_BLOCK_SIZE (" +
                                     std::to_string(maxBlock) + ")");
        mSamples = Buffer({.size = table.size() * sizeof(glm::vec4), .data = table.data(),
                           .flags = 0, .label = "light-samples"});
        // The same quadrants, 2 bits a run, for the potential resolve's uniform.
        if (runQuadrants.size() > 32)
            throw std::logic_error("wedges-bitmask: more than 256 light samples");
        mRunQuadrants = {0u, 0u};
        for (std::size_t r = 0; r < runQuadrants.size(); ++r)
            mRunQuadrants[r / 16] |= static_cast<GLuint>(runQuadrants[r]) << (2 * (r % 16));
        mSeed = seed;
    }

    // The group masks into the final mask where `stencil` selects (bitmask-combine.frag); the
    // umbra (kEverySample) with the parity program in either mode (it reads no group state).
    void combineMask(const Targets& t, const PipelineState& stencil, CombineMode mode) {
        for (int i = 0; i < mLayout.targets(); ++i)
            glBindTextureUnit(TEXUNIT_PARTS0 + i, mGroup[i].id());
        const FullscreenPass& pass = mode == kEverySample ? mUmbra : mCombine;
        pass.execute(mFinalFbo, t.width, t.height, withStencil(kCombineState, stencil),
                     [&] { glUniform1ui(0, mode); });
    }

    // combine=counts: the batch's touched pixels (the shader reads the stencil's mark and
    // centre count itself, so the final mask's framebuffer has no stencil attached), within
    // the batch's scissor.
    void combineCounts(const Targets& t, const PipelineState& touched) {
        glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT); // the wedges' atomic adds
        PipelineState state = kCombineState;
        state.scissor = touched.scissor;
        state.scissorRect = touched.scissorRect;
        mCombine.execute(mFinalNoStencilFbo, t.width, t.height, state,
                         [&] { glUniform1ui(0, kGroupMask); });
        glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT); // before the reset overwrites them
    }

    // A view of the frame's depth-stencil texture that samples its stencil (made again when the
    // targets are).
    void bindStencilView(const Targets& t) {
        if (!mStencilView || mStencilSource != t.depthStencil.id()) {
            GLuint view = 0;
            glGenTextures(1, &view);
            glTextureView(view, GL_TEXTURE_2D, t.depthStencil.id(), GL_DEPTH32F_STENCIL8, 0, 1,
                          0, 1);
            glTextureParameteri(view, GL_DEPTH_STENCIL_TEXTURE_MODE, GL_STENCIL_INDEX);
            glTextureParameteri(view, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
            glTextureParameteri(view, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
            mStencilView = Handle<TextureDeleter>(view);
            mStencilSource = t.depthStencil.id();
        }
        glBindTextureUnit(TEXUNIT_STENCIL, mStencilView.id());
    }

    struct TextureDeleter {
        void operator()(GLuint id) const { glDeleteTextures(1, &id); }
    };

    MaskLayout mLayout;
    // silhouettes=potential: receivers whose plane holds the light centre, their depth moved
    // as the wedge passes move them (receiver-nudge.frag).
    static constexpr PipelineState kReceiverNudgeState{
        .depthTest = true, .depthFunc = GL_ALWAYS, .depthWrite = true, .colorWrite = false};
    FullscreenPass mCombine, mUmbra, mClear, mResolve, mPotentialResolve, mReceiverNudge;
    DrawSet mKeptWedges;                // silhouettes=potential, depth-aware: this frame's
    std::vector<CasterRange> mKeptRuns; // wedges and set-up runs
    const DrawSet* mDrawnWedges = nullptr; // the wedge set the last frame drew (debug view)
    PotentialSet mPotential;
    std::unique_ptr<WedgeTilePass> mTiles;         // silhouettes=potential evaluate=tiles
    std::unique_ptr<TiledResolve> mTiledResolve;   // its resolve
    Texture mArea; // silhouettes=potential: per quadrant, the wedges' sum of m coverage
    Framebuffer mAreaFbo, mResolveFbo;
    GLuint mResolveVisibility = 0;
    Texture mCounts; // combine=counts: 4 bits a sample, biased
    Handle<TextureDeleter> mStencilView;
    GLuint mStencilSource = 0;
    Framebuffer mFinalNoStencilFbo;
    Buffer mSamples, mMaskStats;
    std::uint32_t mSeed = 0;
    std::array<GLuint, 2> mRunQuadrants{}; // each run of 8 samples' quadrant, 2 bits a run
    std::array<Texture, 2> mGroup, mFinal;
    Framebuffer mGroupFbo, mFinalFbo;
    int mWidth = 0, mHeight = 0;
};

} // namespace

std::unique_ptr<VisibilityMethod> createBitmaskWedgesMethod(const MethodResources& r) {
    return std::make_unique<BitmaskWedgesMethod>(r);
}

} // namespace gpu
