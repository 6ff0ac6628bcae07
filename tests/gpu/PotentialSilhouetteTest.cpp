// wedges-bitmask silhouettes=potential: the GPU's masks against the definition (per sample, the
// triangles the segment from the receiver crosses, counted two-sided: geometry/models/MaskModel.h
// potentialCountModel), bit for bit, on curved casters, a big light, a grazing light and a level;
// the ratio estimator's accuracy against the N = 1024 reference; the 4-bit counts' overflow
// detected and reported; the camera inside a volume and a wedge.
#include "ClosedForm.h"
#include "GlTestEnv.h"
#include "RenderTestUtil.h"
#include "TestErrors.h"

#include <geometry/core/Error.h>
#include <geometry/models/MaskModel.h>
#include <geometry/reference/ErrorStats.h>
#include <geometry/reference/Framing.h>
#include <geometry/scene/Primitives.h>
#include <geometry/shadow/LightMask.h>
#include <geometry/shadow/PotentialSilhouettes.h>
#include <geometry/shadow/Topology.h>
#include <gpu/Methods.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace {

using testutil::Rendered;

class PotentialSilhouettes : public GlTest {};

double counter(const gpu::FrameStats& s, const char* name) {
    for (const auto& k : s.counters)
        if (k.name == name) return k.value;
    return -1.0;
}

std::vector<std::array<glm::dvec3, 3>> sceneTriangles(const geometry::Scene& scene) {
    std::vector<std::array<glm::dvec3, 3>> out;
    for (const geometry::SceneObject& o : scene.objects) {
        if (o.method == geometry::ShadowMethod::None) continue;
        for (const glm::uvec3& t : o.mesh.triangles)
            out.push_back({glm::dvec3(o.mesh.positions[t.x]), glm::dvec3(o.mesh.positions[t.y]),
                           glm::dvec3(o.mesh.positions[t.z])});
    }
    return out;
}

struct Comparison {
    std::size_t pixels = 0, skippedPixels = 0, ambiguousBits = 0, wrongBits = 0, wrongPixels = 0;
    int maxCount = 0;
};

// The GPU's final masks (hidden where the count is non-zero) against the model at each pixel's
// G-buffer point, moved 1e-5 of the scene's size towards the camera (the GPU takes a receiver
// on the visible side of its own surface). Samples within 1e-4 (light coordinates) of a
// projected triangle edge, where float decides, are left out and counted; so are pixels whose
// light centre is within 0.01 of one (the rasterised volumes decide the centre's count there).
Comparison compare(const geometry::Scene& scene, const gpu::LightMasks& masks,
                   const geometry::FloatImage& position, const geometry::Camera& camera) {
    const auto triangles = sceneTriangles(scene);
    const std::vector<glm::vec2> samples = geometry::lightMaskPattern(masks.samples, 1);
    const geometry::Aabb b = scene.bounds();
    const double nudge = 1e-5 * glm::length(glm::dvec3(b.max - b.min));
    const int words = masks.samples / 32;
    Comparison c;
    for (int row = 0; row < masks.height; ++row)
        for (int x = 0; x < masks.width; ++x) {
            const int y = masks.height - 1 - row;
            const std::size_t top = std::size_t(row) * masks.width + x;
            const glm::dvec3 pf(position.data[3 * top], position.data[3 * top + 1],
                                position.data[3 * top + 2]);
            if (!std::isfinite(pf.x)) continue;
            const glm::dvec3 p = pf + nudge * glm::normalize(glm::dvec3(camera.eye) - pf);
            const geometry::CountModel m =
                geometry::potentialCountModel(p, triangles, scene.light, samples);
            if (m.centreAmbiguous) {
                ++c.skippedPixels;
                continue;
            }
            ++c.pixels;
            std::size_t wrong = 0;
            for (int w = 0; w < words; ++w) {
                std::uint32_t expected = 0;
                for (int k = 0; k < 32; ++k) {
                    const int count = m.count[std::size_t(32 * w + k)];
                    c.maxCount = std::max(c.maxCount, count);
                    if (count != 0) expected |= 1u << k;
                }
                const std::uint32_t gpu =
                    masks.words[(std::size_t(y) * masks.width + x) * words + w];
                wrong += std::popcount((gpu ^ expected) & ~m.ambiguous[w]);
                c.ambiguousBits += std::popcount(m.ambiguous[w]);
            }
            c.wrongBits += wrong;
            c.wrongPixels += wrong > 0;
        }
    return c;
}

// Curved casters, a light large next to its occluder, a light grazing a plate, and a level from
// a spawn camera with the viewer's lamp: the masks against the definition, away from float ties.
// Not bit for bit: measured at 64², 0.3-1.5 % of the compared pixels hold wrong bits (sphere 22-53
// of 3824 at N = 32-256; at N = 64 torus 42, spheres-nine 109 of 3368, large-light 31 of 2779,
// light-grazing 16 of 461, kaos2 44 of 3742 wholly wrong: there the two disagree on the centre's
// count),
// 0.03-0.9 % of the bits; where the GPU is compared with the reference of its own samples (N
// hard passes, the same offsets) it agrees to 0.00001 mean (PotentialSilhouettes
// .MatchesTheReferenceOfItsSamples). These bounds document the measured disagreement with the
// double definition (open: which side of the ties decides, the model's receiver moved towards the
// camera by 1e-5 of the scene or the stencil's polygon offset).
TEST_F(PotentialSilhouettes, MasksEqualTheDefinitionBitForBit) {
    struct Case {
        std::string name;
        geometry::Scene scene;
    };
    std::vector<Case> cases;
    for (const char* f : {"sphere.json", "torus.json", "spheres-nine.json"})
        cases.push_back({f, geometry::loadScene(testutil::dataPath(f))});
    for (const char* f : {"large-light-small-occluder.json", "light-grazing.json"})
        cases.push_back({f, geometry::loadScene(testutil::dataPath(std::string("stability/") + f))});
    const auto kaos2 = testutil::sharedPath("levels/kaos2.glb");
    ASSERT_TRUE(std::filesystem::exists(kaos2)) << kaos2;
    cases.push_back({"kaos2 spawn 3 + lamp", testutil::levelWithLamp("kaos2.glb", 3)});
    for (const Case& k : cases) {
        gpu::ShaderLoader shaders(gpu::defaultShaderDir());
        gpu::Renderer renderer(k.scene, shaders);
        // Every N on the sphere, N = 64 elsewhere (the model is the test's cost).
        for (const int n : {32, 64, 256}) {
            if (n != 64 && k.name != "sphere.json") continue;
            SCOPED_TRACE(k.name + " N=" + std::to_string(n));
            gpu::RenderSettings s;
            s.method = "wedges-bitmask";
            s.width = s.height = 64;
            s.parameters = {{"samples", std::to_string(n)}, {"estimate", "samples"}};
            const gpu::FrameStats stats = renderer.renderFrame(s);
            const gpu::LightMasks masks = renderer.lightMasks();
            ASSERT_EQ(masks.samples, n);
            const Comparison c = compare(k.scene, masks, renderer.position(), k.scene.camera);
            std::printf("  %s N=%d: %zu pixels (%zu skipped), %zu ambiguous bits, %zu wrong bits "
                        "in %zu pixels; largest count %d; %.0f wedges (%.0f centre silhouette)\n",
                        k.name.c_str(), n, c.pixels, c.skippedPixels, c.ambiguousBits,
                        c.wrongBits, c.wrongPixels, c.maxCount, counter(stats, "wedges"),
                        counter(stats, "wedges_centre_silhouette"));
            EXPECT_GT(c.pixels, 400u);
            EXPECT_LE(c.wrongPixels, c.pixels / 12);
            EXPECT_LE(c.wrongBits, c.pixels * n / 100);
            EXPECT_EQ(counter(stats, "count_overflow_pixels"), 0.0);
            // estimate=samples: V is the popcount.
            EXPECT_EQ(testutil::pixelsNotThePopcount(renderer.visibility(), masks), 0u);
        }
    }
}

// One wedges-bitmask frame with evaluate=raster, then one with evaluate=tiles and `tiled`'s
// other settings, on `renderer`, at `size`²: each frame's stats, V and masks.
// One frame's counters, V and light masks, kept after the renderer has moved on.
struct KeptFrame {
    gpu::FrameStats stats;
    geometry::FloatImage v;
    gpu::LightMasks masks;
};
KeptFrame renderAndKeep(gpu::Renderer& renderer, const gpu::RenderSettings& s) {
    KeptFrame f;
    f.stats = renderer.renderFrame(s);
    f.v = renderer.visibility();
    f.masks = renderer.lightMasks();
    return f;
}
// The same V and masks, bit for bit.
void expectSameFrame(const KeptFrame& a, const KeptFrame& b) {
    EXPECT_EQ(testutil::countDiffering(a.v, b.v, 0.0), 0u);
    EXPECT_TRUE(a.masks.words == b.masks.words);
}

struct RasterAndTiled {
    gpu::FrameStats rasterStats, tiledStats;
    geometry::FloatImage rasterV, tiledV;
    gpu::LightMasks rasterMasks, tiledMasks;
};
RasterAndTiled rasterThenTiled(gpu::Renderer& renderer, int size, gpu::RenderSettings tiled = {}) {
    RasterAndTiled out;
    gpu::RenderSettings s;
    s.method = tiled.method = "wedges-bitmask";
    s.width = s.height = tiled.width = tiled.height = size;
    // estimate=quadrants in both: the default estimate=moments needs the tiled evaluation.
    s.parameters = {{"evaluate", "raster"}, {"estimate", "quadrants"}};
    KeptFrame raster = renderAndKeep(renderer, s);
    tiled.parameters = {{"evaluate", "tiles"}, {"estimate", "quadrants"}};
    KeptFrame tiledFrame = renderAndKeep(renderer, tiled);
    out.rasterStats = raster.stats;
    out.rasterV = std::move(raster.v);
    out.rasterMasks = std::move(raster.masks);
    out.tiledStats = tiledFrame.stats;
    out.tiledV = std::move(tiledFrame.v);
    out.tiledMasks = std::move(tiledFrame.masks);
    return out;
}

// A frame past the tiled evaluation's loop budget: counted (wedge_tiles_truncated), refused
// (wedge_tiles_over_limit), rasterised instead: V and the masks the raster pass's, bit for bit.
void expectRasterisedPastTheBudget(const RasterAndTiled& f) {
    EXPECT_GT(counter(f.tiledStats, "wedge_tiles_truncated"), 0.0);
    EXPECT_EQ(counter(f.tiledStats, "wedge_tiles_over_limit"), 1.0);
    EXPECT_EQ(testutil::countDiffering(f.tiledV, f.rasterV, 0.0), 0u);
    EXPECT_TRUE(f.tiledMasks.words == f.rasterMasks.words);
}

// Two frames of a data/ scene with the same settings on one renderer (a buffer sized by the
// last frame: the first frame does not fit it, the second does).
std::pair<KeptFrame, KeptFrame> renderTwice(const char* file, const gpu::RenderSettings& s) {
    const geometry::Scene scene = geometry::loadScene(testutil::dataPath(file));
    gpu::ShaderLoader shaders(gpu::defaultShaderDir());
    gpu::Renderer renderer(scene, shaders);
    KeptFrame first = renderAndKeep(renderer, s);
    KeptFrame second = renderAndKeep(renderer, s);
    return {std::move(first), std::move(second)};
}

// evaluate=tiles (the wedges binned to 8 x 8 pixel tiles, then every pixel over
// its tile's list in one compute pass, the fragment shader's arithmetic in lib/BitmaskEdge.glsl)
// against evaluate=raster (the hulls rasterised, a fragment per pixel and wedge) on one
// renderer: the same masks, and the same V up to the rounding of the areas (fixed point in the
// tiled pass, blending in the raster pass), on curved casters, a big light, overlapping plates,
// the camera inside a volume and a wedge, and two levels' spawn views with the lamp. Measured at
// 96²: no pixel's mask differs, V by at most 1.2e-7. One pixel is allowed: at 256² the big
// light's view has one where the raster pass misses a fragment between two hulls' faces (0.0031
// off; the tiled value lies with its neighbours and the reference).
TEST_F(PotentialSilhouettes, TiledEvaluationEqualsTheRasterPass) {
    struct Case {
        std::string name;
        geometry::Scene scene;
    };
    std::vector<Case> cases;
    for (const char* f : {"sphere.json", "torus.json", "plates-three.json"})
        cases.push_back({f, geometry::loadScene(testutil::dataPath(f))});
    for (const char* f :
         {"large-light-small-occluder.json", "camera-in-volume.json", "camera-in-wedge.json"})
        cases.push_back({f, geometry::loadScene(testutil::dataPath(std::string("stability/") + f))});
    cases.push_back({"kaos2 spawn 3 + lamp", testutil::levelWithLamp("kaos2.glb", 3)});
    cases.push_back({"oa_dm5 spawn 1 + lamp", testutil::levelWithLamp("oa_dm5.glb", 0)});
    for (const Case& k : cases) {
        SCOPED_TRACE(k.name);
        gpu::ShaderLoader shaders(gpu::defaultShaderDir());
        gpu::Renderer renderer(k.scene, shaders);
        const RasterAndTiled f = rasterThenTiled(renderer, 96);
        const gpu::FrameStats &rs = f.rasterStats, &ts = f.tiledStats;
        const geometry::FloatImage &rv = f.rasterV, &tv = f.tiledV;
        const gpu::LightMasks &rm = f.rasterMasks, &tm = f.tiledMasks;
        ASSERT_EQ(rm.words.size(), tm.words.size());
        const int words = tm.samples / 32;
        std::size_t maskPixels = 0, vPixels = 0, nanPixels = 0;
        double worst = 0.0;
        for (std::size_t i = 0; i < tv.data.size(); ++i) {
            if (std::isnan(tv.data[i]) != std::isnan(rv.data[i])) ++nanPixels;
            if (std::isnan(tv.data[i]) || std::isnan(rv.data[i])) continue;
            const double d = std::abs(double(tv.data[i]) - rv.data[i]);
            worst = std::max(worst, d);
            vPixels += d > 1e-5;
        }
        for (std::size_t p = 0; p < tm.words.size() / words; ++p)
            maskPixels += !std::equal(tm.words.begin() + p * words, tm.words.begin() + (p + 1) * words,
                                      rm.words.begin() + p * words);
        std::printf("  %s: %zu pixels' masks differ, %zu pixels' V by > 1e-5 (largest %.2g); "
                    "%.0f tile entries, %.0f pairs added (raster: %.0f fragments)\n",
                    k.name.c_str(), maskPixels, vPixels, worst,
                    counter(ts, "wedge_tile_entries"), counter(ts, "wedge_fragments"),
                    counter(rs, "wedge_fragments"));
        EXPECT_EQ(nanPixels, 0u);
        EXPECT_LE(maskPixels, 1u);
        EXPECT_LE(vPixels, 1u);
        EXPECT_EQ(counter(ts, "wedge_tiles_over_limit"), 0.0);
        // The same counts, so the same pixels past 4 bits (oa_dm5's view has one).
        EXPECT_EQ(counter(ts, "count_overflow_pixels"), counter(rs, "count_overflow_pixels"));
        if (counter(rs, "wedge_fragments") > 0) {
            EXPECT_GT(counter(ts, "wedge_tile_entries"), 0.0);
        }
    }
}

// The default estimate=moments on the tiled counts: the same masks as the raster pass's
// (estimate=quadrants there), V different only in the pixels whose V the moments gave; and a
// moments frame over the tile lists' limit is rasterised and resolved by quadrants, as said
// (wedge_tiles_over_limit, no moment pixels), V equal to the raster pass's.
TEST_F(PotentialSilhouettes, MomentsKeepTheCountsAndFallBackWithTheFrame) {
    const geometry::Scene scene = geometry::loadScene(testutil::dataPath("plates-three.json"));
    gpu::ShaderLoader shaders(gpu::defaultShaderDir());
    gpu::Renderer renderer(scene, shaders);
    const RasterAndTiled f = rasterThenTiled(renderer, 96);
    gpu::RenderSettings s = testutil::frameSettings("wedges-bitmask", 96, 96);
    const gpu::FrameStats moments = renderer.renderFrame(s);
    const geometry::FloatImage mv = renderer.visibility();
    EXPECT_TRUE(renderer.lightMasks().words == f.rasterMasks.words);
    const std::size_t differ = testutil::countDiffering(mv, f.rasterV, 1e-5);
    std::printf("  plates-three 96²: %zu pixels' V differ from quadrants, %.0f by the moments\n",
                differ, counter(moments, "moment_pixels"));
    EXPECT_GT(counter(moments, "moment_pixels"), 0.0);
    EXPECT_LE(double(differ), counter(moments, "moment_pixels"));
    s.wedgeTileEntryLimit = 16;
    const gpu::FrameStats over = renderer.renderFrame(s);
    EXPECT_EQ(counter(over, "wedge_tiles_over_limit"), 1.0);
    EXPECT_EQ(counter(over, "moment_pixels"), 0.0);
    EXPECT_EQ(testutil::countDiffering(renderer.visibility(), f.rasterV, 0.0), 0u);
}

// Where a frame's tile lists would pass their limit (RenderSettings::wedgeTileEntryLimit; by
// default what one buffer texture holds) the frame rasterises the hulls instead and says so
// (wedge_tiles_over_limit): V and the masks are the raster pass's, bit for bit; the next frame
// under the limit is tiled again.
TEST_F(PotentialSilhouettes, TiledEvaluationOverItsLimitRasterises) {
    const geometry::Scene scene = geometry::loadScene(testutil::dataPath("sphere.json"));
    gpu::ShaderLoader shaders(gpu::defaultShaderDir());
    gpu::Renderer renderer(scene, shaders);
    gpu::RenderSettings limited;
    limited.wedgeTileEntryLimit = 16;
    const RasterAndTiled f = rasterThenTiled(renderer, 64, limited);
    EXPECT_EQ(counter(f.tiledStats, "wedge_tiles_over_limit"), 1.0);
    EXPECT_EQ(testutil::countDiffering(f.tiledV, f.rasterV, 0.0), 0u);
    EXPECT_TRUE(f.tiledMasks.words == f.rasterMasks.words);
    gpu::RenderSettings s = testutil::frameSettings("wedges-bitmask", 64, 64);
    s.parameters = {{"evaluate", "tiles"}};
    const gpu::FrameStats under = renderer.renderFrame(s);
    EXPECT_EQ(counter(under, "wedge_tiles_over_limit"), 0.0);
    EXPECT_GT(counter(under, "wedge_tile_entries"), 16.0);
}

// The lists filled two ways: the count stage records its entries while they fit a buffer sized
// by the last frame's (at least 4096), and the place stage writes them into the lists; where
// they do not fit (a renderer's first tiled frame of spheres-nine at 128², 72 052 entries),
// the fill stage tests every slot's tiles again. Both give the same lists (in another order):
// V and the masks bit for bit, the same entries, and wedge_tiles_refilled says which ran.
TEST_F(PotentialSilhouettes, TiledListsRecordedOrRefilledAlike) {
    gpu::RenderSettings s = testutil::frameSettings("wedges-bitmask", 128, 128);
    s.parameters = {{"estimate", "quadrants"}, {"evaluate", "tiles"}};
    const auto [first, second] = renderTwice("spheres-nine.json", s);
    std::printf("  spheres-nine at 128²: %.0f entries; refilled %.0f, then %.0f\n",
                counter(first.stats, "wedge_tile_entries"),
                counter(first.stats, "wedge_tiles_refilled"),
                counter(second.stats, "wedge_tiles_refilled"));
    ASSERT_EQ(counter(first.stats, "wedge_evaluation_tiled"), 1.0);
    ASSERT_EQ(counter(second.stats, "wedge_evaluation_tiled"), 1.0);
    EXPECT_GT(counter(first.stats, "wedge_tile_entries"), 4096.0);
    EXPECT_EQ(counter(first.stats, "wedge_tiles_refilled"), 1.0);
    EXPECT_EQ(counter(second.stats, "wedge_tiles_refilled"), 0.0);
    EXPECT_EQ(counter(first.stats, "wedge_tile_entries"),
              counter(second.stats, "wedge_tile_entries"));
    expectSameFrame(second, first);
}

// estimate=moments: the pixels that need P (their samples see two or more layer counts) keep
// the edges that added there in a buffer sized by the last frame's (at least 1024 pixels), and
// a pass of their own computes P. Where they do not fit (a renderer's first frame of
// plates-three at 128²: about 3 700 such pixels) the evaluation runs again with room for all:
// the same V and masks as the next frame, which fits, bit for bit, and wedge_moment_reruns
// says which ran.
TEST_F(PotentialSilhouettes, MomentPixelsThatDoNotFitRunTheEvaluationAgain) {
    const auto [first, second] =
        renderTwice("plates-three.json", testutil::frameSettings("wedges-bitmask", 128, 128));
    std::printf("  plates-three at 128²: %.0f moment pixels; reruns %.0f, then %.0f\n",
                counter(first.stats, "moment_pixels"),
                counter(first.stats, "wedge_moment_reruns"),
                counter(second.stats, "wedge_moment_reruns"));
    ASSERT_EQ(counter(first.stats, "wedge_evaluation_tiled"), 1.0);
    EXPECT_GT(counter(first.stats, "moment_pixels"), 1024.0);
    EXPECT_EQ(counter(first.stats, "wedge_moment_reruns"), 1.0);
    EXPECT_EQ(counter(second.stats, "wedge_moment_reruns"), 0.0);
    EXPECT_EQ(counter(first.stats, "moment_pixels"), counter(second.stats, "moment_pixels"));
    expectSameFrame(second, first);
}

// A tile whose list is too long for one pixel's loop budget (WEDGE_TILES_LOOP_BUDGET: llvmpipe
// ends an invocation's loops silently after 65535 iterations in all): a 600-segment sphere at
// 64², seen with a field of view four times as wide as the scene's (117.8 degrees), so that its
// 115 000 wedges fall on about as few tiles as at 16² with the scene's own (at a quarter of
// that zoom its pixels' lists fit, since only the pairs whose R meets the light count in full).
// Counted (wedge_tiles_truncated), the frame rasterised instead: V and the masks are the raster
// pass's, bit for bit.
// Before the budget such a frame dropped pairs silently (the 10^6-triangle sphere of EdgeCases
// at 128²: 178 pixels off the reference of the same samples, 2 with the raster pass).
TEST_F(PotentialSilhouettes, TiledEvaluationPastItsLoopBudgetRasterises) {
    geometry::Scene scene = geometry::loadScene(testutil::dataPath("sphere.json"));
    scene.objects[1].mesh = geometry::makeSphere({0.0f, 1.0f, 0.0f}, 0.5f, 600);
    const float halfTan = 4.0f * std::tan(glm::radians(0.5f * scene.camera.fovYDeg));
    scene.camera.fovYDeg = glm::degrees(2.0f * std::atan(halfTan));
    gpu::ShaderLoader shaders(gpu::defaultShaderDir());
    gpu::Renderer renderer(scene, shaders);
    const RasterAndTiled f = rasterThenTiled(renderer, 64);
    std::printf("  600-segment sphere at 64², field of view %.1f degrees: %.0f pixels past the "
                "loop budget\n",
                scene.camera.fovYDeg, counter(f.tiledStats, "wedge_tiles_truncated"));
    expectRasterisedPastTheBudget(f);
}

// The loop budget counts the iterations of the SIMD vector, which llvmpipe limits, not those of
// one lane (wedge-bitmask-tiles.comp): a 600-segment sphere of radius 0.7 under a light of half
// size 0.4 at 64², about 13 000 entries a tile, where every lane's own pairs stayed under the
// budget while its vector's loops, its lanes' pairs falling in different iterations, passed
// llvmpipe's limit. Counted per lane, such a frame stayed tiled and lost pairs silently: 37
// pixels off the raster pass, by up to 0.36 (measured with the binning's spread order, which
// moved the lists' entries into other runs). Counted per vector: past the budget, rasterised,
// V and the masks the raster pass's bit for bit.
TEST_F(PotentialSilhouettes, TiledBudgetCountsTheVectorNotOneLane) {
    geometry::Scene scene = geometry::loadScene(testutil::dataPath("sphere.json"));
    scene.camera.eye = {4.0f, 4.0f, 5.0f};
    scene.camera.target = {0.0f, 0.3f, 0.0f};
    scene.light.center = {0.3f, 3.0f, 0.2f};
    scene.light.u = {0.4f, 0.0f, 0.0f};
    scene.light.v = {0.0f, 0.0f, 0.4f};
    scene.objects[1].mesh = geometry::makeSphere({0.0f, 0.8f, 0.0f}, 0.7f, 600);
    geometry::validateScene(scene);
    gpu::ShaderLoader shaders(gpu::defaultShaderDir());
    gpu::Renderer renderer(scene, shaders);
    const RasterAndTiled f = rasterThenTiled(renderer, 64);
    std::printf("  600-segment sphere at 64²: %.0f pixels past the loop budget, tiled %.0f\n",
                counter(f.tiledStats, "wedge_tiles_truncated"),
                counter(f.tiledStats, "wedge_evaluation_tiled"));
    expectRasterisedPastTheBudget(f);
}

// evaluate=auto (the default) takes the tiled evaluation from BitmaskOptions::kAutoTiledEdges
// potential edges drawn (the sphere's 803) and the raster pass below (the plates' 16), and says
// which (wedge_evaluation_tiled); with the default estimate=moments, which needs the tiled
// evaluation's per-pixel lists, every frame is tiled, and estimate=moments evaluate=raster is
// refused.
TEST_F(PotentialSilhouettes, AutoEvaluationTilesManyEdgesAndRasterisesFew) {
    for (const auto& [file, tiled] : {std::pair{"sphere.json", 1.0}, {"plates-three.json", 0.0}}) {
        SCOPED_TRACE(file);
        const geometry::Scene scene = geometry::loadScene(testutil::dataPath(file));
        const Rendered moments = testutil::render(scene, "wedges-bitmask", 48, 48, 1);
        EXPECT_EQ(counter(moments.stats, "wedge_evaluation_tiled"), 1.0);
        const Rendered r =
            testutil::render(scene, "wedges-bitmask", 48, 48, 1, {{"estimate", "quadrants"}});
        EXPECT_EQ(counter(r.stats, "wedge_evaluation_tiled"), tiled);
        const double drawn = counter(r.stats, "wedges") - counter(r.stats, "wedges_hidden");
        EXPECT_EQ(drawn >= 512.0, tiled == 1.0); // BitmaskOptions::kAutoTiledEdges
    }
    const geometry::Scene plates = geometry::loadScene(testutil::dataPath("plates-three.json"));
    gpu::ShaderLoader shaders(gpu::defaultShaderDir());
    gpu::Renderer renderer(plates, shaders);
    gpu::RenderSettings s = testutil::frameSettings("wedges-bitmask", 48, 48);
    s.parameters = {{"evaluate", "raster"}};
    const std::optional<std::string> error =
        testutil::errorOf<geometry::InputError>([&] { renderer.renderFrame(s); });
    ASSERT_TRUE(error) << "estimate=moments evaluate=raster was accepted";
    EXPECT_NE(error->find("estimate=moments needs the tiled evaluation"), std::string::npos)
        << *error;
}

// Against the reference of the same samples (the same N and seed: what the masks estimate), on
// the single casters, the overlap scenes and the stability suite's layered, curved and big-light
// cases: estimate=samples is exact up to rasterisation; the default estimate=moments against
// the N = 1024 reference at its measured error (128², N = 64; the single casters within the
// issue's bars: sphere 0.0003, torus 0.0004, box 0.0003, plate-tilted 0.0004, parallel-square
// 0.0001, against blend's 0.0042, 0.0052, 0.0010, 0.0004, 0.0001; where plates' penumbrae
// overlap: plates-three 0.00076, diamonds 0.00064, bars-cross 0.00046, overlap 0.00051 against
// blend's 0.0008, 0.0007, 0.0006, 0.0005 and estimate=quadrants' 0.0021, 0.0011, 0.0007,
// 0.0006), never worse than estimate=quadrants (equal where no pixel's samples see two layer
// counts: the single casters) nor than estimate=ratio's one ratio for the whole light.
// A scene file as a test name: "stability/plates-stacked.json" -> "plates_stacked".
std::string sceneTestName(std::string n) {
    n = n.substr(n.rfind('/') + 1);
    n = n.substr(0, n.find('.'));
    std::replace(n.begin(), n.end(), '-', '_');
    return n;
}

struct AccuracyCase {
    const char* scene;
    double ownMean;   // estimate=samples against reference N = 64 (the same samples)
    double ratioMean; // estimate=moments (the default) against reference N = 1024
};

class PotentialAccuracy : public GlTest, public ::testing::WithParamInterface<AccuracyCase> {};

TEST_P(PotentialAccuracy, MatchesTheReferenceOfItsSamples) {
    const AccuracyCase& c = GetParam();
    const geometry::Scene scene = geometry::loadScene(testutil::dataPath(c.scene));
    const Rendered ref64 = testutil::render(scene, "reference", 128, 64);
    const Rendered ref1024 = testutil::render(scene, "reference", 128, 1024);
    const Rendered samples = testutil::render(scene, "wedges-bitmask", 128, 128, 1,
                                              {{"estimate", "samples"}});
    const Rendered ratio = testutil::render(scene, "wedges-bitmask", 128, 128, 1);
    const Rendered quadrants = testutil::render(scene, "wedges-bitmask", 128, 128, 1,
                                                {{"estimate", "quadrants"}});
    const Rendered whole = testutil::render(scene, "wedges-bitmask", 128, 128, 1,
                                            {{"estimate", "ratio"}});
    const Rendered blend = testutil::render(scene, "wedges-blend", 128);
    const auto es = geometry::compareVisibility(samples.visibility.data, ref64.visibility.data);
    const auto er = geometry::compareVisibility(ratio.visibility.data, ref1024.visibility.data);
    const auto ew = geometry::compareVisibility(whole.visibility.data, ref1024.visibility.data);
    const auto eq =
        geometry::compareVisibility(quadrants.visibility.data, ref1024.visibility.data);
    const auto eb = geometry::compareVisibility(blend.visibility.data, ref1024.visibility.data);
    std::printf("  %s: samples vs its samples' reference mean %.5f (%.2f%% > 0.05); moments vs "
                "N=1024 mean %.5f p99 %.4f (%.2f%% > 0.05; %.0f pixels by the moments, %.0f "
                "not); quadrants %.5f; ratio %.5f; blend %.4f\n",
                c.scene, es.meanAbs, es.badPixelPct, er.meanAbs, er.p99, er.badPixelPct,
                counter(ratio.stats, "moment_pixels"),
                counter(ratio.stats, "moment_pixels_fallback"), eq.meanAbs, ew.meanAbs,
                eb.meanAbs);
    EXPECT_LE(es.meanAbs, 1.25 * c.ownMean + 0.00005);
    EXPECT_LE(es.badPixelPct, 0.1);
    EXPECT_LE(er.meanAbs, 1.25 * c.ratioMean + 0.0001);
    EXPECT_LE(er.meanAbs, eq.meanAbs + 0.00002); // the moments never err more than quadrants
    EXPECT_LE(er.meanAbs, ew.meanAbs + 0.00002); // nor than one ratio
}

INSTANTIATE_TEST_SUITE_P(
    Scenes, PotentialAccuracy,
    ::testing::Values(AccuracyCase{"sphere.json", 0.00001, 0.0003},
                      AccuracyCase{"torus.json", 0.00000, 0.0004},
                      AccuracyCase{"box.json", 0.00001, 0.0003},
                      AccuracyCase{"plate-tilted.json", 0.00001, 0.0004},
                      AccuracyCase{"spheres-nine.json", 0.00002, 0.0012},
                      AccuracyCase{"plates-three.json", 0.00000, 0.00076},
                      AccuracyCase{"overlap.json", 0.00000, 0.00051},
                      AccuracyCase{"bars-cross.json", 0.00000, 0.00046},
                      AccuracyCase{"diamonds.json", 0.00000, 0.00064},
                      AccuracyCase{"parallel-square.json", 0.00000, 0.0001},
                      AccuracyCase{"stability/plates-stacked.json", 0.00000, 0.0011},
                      AccuracyCase{"stability/open-nonmanifold.json", 0.00000, 0.00133},
                      AccuracyCase{"stability/large-light-small-occluder.json", 0.00000, 0.0025},
                      AccuracyCase{"stability/light-grazing.json", 0.00015, 0.0026}),
    [](const ::testing::TestParamInfo<AccuracyCase>& info) {
        return sceneTestName(info.param.scene);
    });

// Against the true V where it is known in closed form (the floor under horizontal plates,
// tests/gpu/ClosedForm.h), at N = 32, 64 and 128, beside wedges-blend: exact for one plate at any
// N (parallel-square: 0 at N = 32, 64, 128), and the measured error where penumbrae of plates
// at different heights overlap (128², the floor's pixels). The default estimate=moments is
// exact where the samples see both layer counts there; what is left is pixels whose samples
// miss one (fewer with more samples): overlap 0.00004 / 0.00001 / 0.00000, plates-three
// 0.00025 / 0.00010 / 0.00005, against blend's 0.00012 and 0.00027 (exact on axis-aligned
// rectangles but for its 8 bits); estimate=quadrants, which samples the ratios S_u / S_sum
// there, measured 0.00015 / 0.00011 / 0.00008 and 0.0028 / 0.0019 / 0.0011 (estimate=ratio's
// one ratio 0.00027 / 0.00015 / 0.00012 and 0.0032 / 0.0022 / 0.0014). Asserted: the moments
// never err more than quadrants, nor, from N = 64 (the bar), than blend.
struct ExactCase {
    const char* scene;
    double mean[3]; // N = 32, 64, 128: mean |V - V_exact| over the floor, as measured
    int bad[3];     // pixels off by more than 0.05, as measured
};

class PotentialExact : public GlTest, public ::testing::WithParamInterface<ExactCase> {};

TEST_P(PotentialExact, AgainstTheClosedForm) {
    const ExactCase& c = GetParam();
    const geometry::Scene scene = geometry::loadScene(testutil::dataPath(c.scene));
    const Rendered blend = testutil::render(scene, "wedges-blend", 128);
    const std::vector<float> exact =
        testutil::closedFormFloor(scene, blend, testutil::closedFormRects(c.scene));
    const auto eb = geometry::compareVisibility(blend.visibility.data, exact);
    const int samples[3] = {32, 64, 128};
    for (int k = 0; k < 3; ++k) {
        const std::string n = std::to_string(samples[k]);
        const Rendered r = testutil::render(scene, "wedges-bitmask", 128, 128, 1, {{"samples", n}});
        const Rendered q = testutil::render(scene, "wedges-bitmask", 128, 128, 1,
                                            {{"samples", n}, {"estimate", "quadrants"}});
        const auto e = geometry::compareVisibility(r.visibility.data, exact);
        const auto eq = geometry::compareVisibility(q.visibility.data, exact);
        int bad = 0;
        for (std::size_t i = 0; i < exact.size(); ++i)
            bad += std::isfinite(exact[i]) && std::fabs(r.visibility.data[i] - exact[i]) > 0.05f;
        std::printf("  %s N=%d: %zu floor pixels, mean %.5f p99 %.4f max %.4f, %d off by > 0.05 "
                    "(%.0f pixels by the moments, %.0f not); quadrants mean %.5f; blend mean "
                    "%.5f\n",
                    c.scene, samples[k], e.pixels, e.meanAbs, e.p99, e.max, bad,
                    counter(r.stats, "moment_pixels"), counter(r.stats, "moment_pixels_fallback"),
                    eq.meanAbs, eb.meanAbs);
        EXPECT_GT(e.pixels, 5000u);
        EXPECT_LE(e.meanAbs, 1.25 * c.mean[k] + 0.00002);
        EXPECT_LE(bad, c.bad[k] + c.bad[k] / 4 + 2);
        EXPECT_LE(e.meanAbs, eq.meanAbs + 0.00001);
        // The bar, from N = 64: no more error than wedges-blend's where it is exact on
        // axis-aligned plates.
        if (samples[k] >= 64) {
            EXPECT_LE(e.meanAbs, eb.meanAbs);
        }
    }
}

INSTANTIATE_TEST_SUITE_P(
    Scenes, PotentialExact,
    ::testing::Values(ExactCase{"parallel-square.json", {0.0, 0.0, 0.0}, {0, 0, 0}},
                      ExactCase{"overlap.json", {0.00004, 0.00001, 0.00000}, {0, 0, 0}},
                      ExactCase{"plates-three.json", {0.00025, 0.00010, 0.00005}, {2, 0, 0}}),
    [](const ::testing::TestParamInfo<ExactCase>& info) {
        return sceneTestName(info.param.scene);
    });

// estimate=moments on closed casters: two coarse spheres (12 segments: few edges per pixel) at
// different heights whose penumbrae overlap on the floor, so that the samples see the counts 2
// (one sphere) and 4 (both): the moments give such pixels their exact areas, where quadrants
// sample the ratio. Against `reference` N = 4096 at 96² (measured: moments 0.00051 over the
// view, 373 pixels by the moments and 143 left to quadrants: the receiver's own plane hides
// some of the light there, or more than 16 edges add; quadrants 0.00079); the moments must be
// used, and err less than quadrants (with the pairs' term halved on purpose: 0.00143).
TEST_F(PotentialSilhouettes, MomentsGiveOverlappingClosedCastersTheirAreas) {
    geometry::Scene scene = geometry::loadScene(testutil::dataPath("sphere.json"));
    scene.objects[1].mesh = geometry::makeSphere({0.0f, 0.8f, 0.0f}, 0.35f, 12);
    geometry::SceneObject second = scene.objects[1];
    second.name = "second sphere";
    second.mesh = geometry::makeSphere({0.25f, 1.8f, -0.3f}, 0.25f, 12);
    scene.objects.push_back(second);
    const Rendered truth = testutil::render(scene, "reference", 96, 4096);
    const Rendered moments = testutil::render(scene, "wedges-bitmask", 96, 96, 1);
    const Rendered quadrants =
        testutil::render(scene, "wedges-bitmask", 96, 96, 1, {{"estimate", "quadrants"}});
    const auto em = geometry::compareVisibility(moments.visibility.data, truth.visibility.data);
    const auto eq = geometry::compareVisibility(quadrants.visibility.data, truth.visibility.data);
    std::printf("  two spheres: moments mean %.5f (%.0f pixels by the moments, %.0f not), "
                "quadrants %.5f, against reference N=4096\n",
                em.meanAbs, counter(moments.stats, "moment_pixels"),
                counter(moments.stats, "moment_pixels_fallback"), eq.meanAbs);
    EXPECT_GT(counter(moments.stats, "moment_pixels"), 100.0);
    EXPECT_LT(em.meanAbs, eq.meanAbs);
    EXPECT_EQ(em.badPixelPct, 0.0);
}

// A count past the 4 bits' [-8, 7] (nine plates stacked over the floor, the light centre seen
// through all of them from below the stack's edge... here: a stack of 10 two-sided plates, whose
// counts change by 10 across the stack's outline) is detected by the checksums, counted in
// count_overflow_pixels, and such pixels take the analytic A (clamped), not a wrong count.
TEST_F(PotentialSilhouettes, CountOverflowIsDetectedAndReported) {
    geometry::Scene scene = geometry::loadScene(testutil::dataPath("parallel-square.json"));
    ASSERT_FALSE(scene.objects.empty());
    // Copies of the occluder stacked closely above it: ten layers.
    const geometry::SceneObject base = scene.objects.back();
    for (int k = 1; k < 10; ++k) {
        geometry::SceneObject o = base;
        for (glm::vec3& p : o.mesh.positions) p.y += 0.02f * float(k);
        scene.objects.push_back(o);
    }
    const Rendered r = testutil::render(scene, "wedges-bitmask", 96, 96, 1);
    const double overflow = counter(r.stats, "count_overflow_pixels");
    std::printf("  ten stacked plates: %.0f pixels with counts past 4 bits\n", overflow);
    EXPECT_GT(overflow, 0.0);
    const Rendered ref = testutil::render(scene, "reference", 96, 256);
    const auto e = geometry::compareVisibility(r.visibility.data, ref.visibility.data);
    std::printf("  ten stacked plates: mean %.4f against reference N=256\n", e.meanAbs);
    // The fallback, A clamped, counts every layer: too dark where the ten plates' penumbrae
    // part (measured 0.039 mean over the view, 619 pixels flagged): reported, not hidden.
    EXPECT_LE(e.meanAbs, 0.05);
}

// The camera inside a shadow volume and inside a wedge (the stability suite's scenes): against
// the reference of the same samples, as every wedge method is tested there.
TEST_F(PotentialSilhouettes, CameraInsideAVolumeAndAWedge) {
    for (const char* f : {"camera-in-volume.json", "camera-in-wedge.json"}) {
        SCOPED_TRACE(f);
        const geometry::Scene scene =
            geometry::loadScene(testutil::dataPath(std::string("stability/") + f));
        const Rendered ref = testutil::render(scene, "reference", 96, 64);
        const Rendered r = testutil::render(scene, "wedges-bitmask", 96, 96, 1,
                                            {{"estimate", "samples"}});
        const auto e = geometry::compareVisibility(r.visibility.data, ref.visibility.data);
        std::printf("  %s: mean %.5f, %zu pixels off > 0.05, %.0f wedges with the camera inside\n",
                    f, e.meanAbs, testutil::countDiffering(r.visibility, ref.visibility, 0.05),
                    counter(r.stats, "wedges_camera_inside"));
        EXPECT_LE(e.meanAbs, 0.001);
        EXPECT_LE(testutil::countDiffering(r.visibility, ref.visibility, 0.05), 20u);
    }
}

} // namespace

// The light's centre in the plane of the receivers (testutil::wallsThroughLightCentre), as on
// oa_dm1's eighth spawn view with the lamp (0.0225 mean against raytrace N = 4096 there, 4.5 %
// of the pixels off by more than 0.05, the walls through the lamp drawn black). Seen from such
// a receiver every edge in its plane has the centre on the plane through P and the edge, and
// the triangles of that plane have flat volumes from the centre. Now those triangles take no
// part in the centre's volumes, the caster's wedges are culled by its whole box (not by its
// groups', which no longer hold those triangles), and such a receiver is taken 1/4096 of its
// distance to the eye towards it, by the wedge passes and by the stencil's depth
// (lib/PotentialReceiver.glsl). The fronts of the wall and of the pillar then see the half of
// the light in front of their planes, up to the estimator's rounding.
TEST_F(PotentialSilhouettes, TheLightsCentreInTheReceiversPlane) {
    const geometry::Scene scene = testutil::wallsThroughLightCentre();
    geometry::validateScene(scene);
    const Rendered truth = testutil::render(scene, "raytrace", 96, 96, 1024);
    const Rendered w = testutil::render(scene, "wedges-bitmask", 96, 96, 1);
    const auto e = geometry::compareVisibility(w.visibility.data, truth.visibility.data);
    const std::size_t off = testutil::countDiffering(w.visibility, truth.visibility, 0.05);
    const testutil::WallFront wall = testutil::wallFront(scene, w.visibility, w.position);
    // The pillar's front face (x = 1.5, facing +x): the light's half in front of its plane.
    std::size_t face = 0;
    double faceWorst = 0.0;
    for (std::size_t i = 0; i < w.visibility.data.size(); ++i) {
        const glm::vec3 p(w.position.data[3 * i], w.position.data[3 * i + 1],
                          w.position.data[3 * i + 2]);
        if (!std::isfinite(p.x) || std::abs(p.x - 1.5f) > 1e-3f || p.y < 0.05f) continue;
        ++face;
        faceWorst = std::max(faceWorst, std::abs(double(w.visibility.data[i]) - 0.5));
    }
    std::printf("  walls through the light's centre: mean %.5f against raytrace N=1024, %zu pixels "
                "off by > 0.05; wall front %zu pixels, |V - share in front| max %.4f; pillar "
                "face %zu pixels, |V - 0.5| max %.4f; centre_in_plane_triangles %.0f\n",
                e.meanAbs, off, wall.pixels, wall.worst, face, faceWorst,
                counter(w.stats, "centre_in_plane_triangles"));
    EXPECT_GT(wall.pixels, 400u);
    EXPECT_GT(face, 100u);
    EXPECT_EQ(counter(w.stats, "centre_in_plane_triangles"), 4.0); // the wall's two, the face's
    // Measured at 96²: 0.00109 mean, no pixel off by more than 0.05; on the wall's front at most
    // 0.011 from the half (its corner), on the face 0.019 (the ratio estimator's rounding with
    // the receiver moved). Before: 0.0273 mean, 233 pixels off (the face black in places, the
    // wall lit or black in stripes).
    EXPECT_LT(e.meanAbs, 0.002);
    EXPECT_LE(off, 5u);
    EXPECT_LT(wall.worst, 0.015);
    EXPECT_LT(faceWorst, 0.025);
}

// A thin wall (one quad) beside a light whose plane it crosses: half the light lies behind the
// wall's plane, so its front sees at most the other half, as raytrace counts it. No segment
// from the front crosses the wall (it leaves the wall at its start), so the counts alone drew
// the whole light there; the receiver's own plane is one more layer in the resolve, and one
// more test in the reference's accumulation. Against raytrace N = 1024, and on the wall's
// front against the exact share in front of its plane.
TEST_F(PotentialSilhouettes, TheReceiversOwnPlaneHidesTheLightBehindIt) {
    const geometry::Scene scene = testutil::wallBesideLight();
    geometry::validateScene(scene);
    const Rendered truth = testutil::render(scene, "raytrace", 96, 96, 1024);
    const Rendered w = testutil::render(scene, "wedges-bitmask", 96, 96, 1);
    const Rendered ref = testutil::render(scene, "reference", 96, 96, 256);
    const auto ew = geometry::compareVisibility(w.visibility.data, truth.visibility.data);
    const auto er = geometry::compareVisibility(ref.visibility.data, truth.visibility.data);
    // The wall's front (z > 0): V = the share of the light in front of its plane, exactly for
    // the ratio estimator (nothing else shadows it).
    const testutil::WallFront wall = testutil::wallFront(scene, w.visibility, w.position);
    std::printf("  wall beside the light: wedges-bitmask mean %.4f, reference N=256 %.4f against "
                "raytrace N=1024; on the wall's %zu front pixels |V - share in front| max %.4f "
                "(%zu > 0.01); own_plane_pixels %.0f\n",
                ew.meanAbs, er.meanAbs, wall.pixels, wall.worst, wall.off,
                counter(w.stats, "own_plane_pixels"));
    EXPECT_GT(wall.pixels, 500u);
    EXPECT_GT(counter(w.stats, "own_plane_pixels"), double(wall.pixels) * 0.9);
    // Measured at 96²: 0.0015 and 0.0064 (N = 256's bands); on the wall at most 0.00002.
    // Before the rule (128², the same wall and light): 0.0214 and 0.0216, the front drawn lit.
    EXPECT_LT(ew.meanAbs, 0.0015 + 0.001);
    EXPECT_LT(er.meanAbs, 0.0064 + 0.002);
    EXPECT_LT(wall.worst, 0.002);
}
