// The sample-maps method (gpu/src/methods/SampleMapsMethod.cpp, shaders/sample-maps-lookup.frag)
// on the GL driver:
// - on opaque data scenes it computes what `reference` computes with the same samples (the
//   same stratified points for N and the seed), up to the maps' texels along shadow edges;
// - the shared trees alone (their own framing, the foliage case) against alpha-aware
//   raytrace N = 256 over the trees' pixels: within the 0.02, and better than pcss;
// - the early out (early_out=on: receivers whose pyramid to the light holds no caster skip the
//   maps) gives the V that reading every map gives, on the oak over its ground;
// - casters reaching the light's plane are counted as clipped;
// - a memory-hungry combination of parameters is refused with the figure.
#include "GlTestEnv.h"
#include "RenderTestUtil.h"

#include <geometry/core/Error.h>
#include <geometry/reference/ErrorStats.h>
#include <geometry/reference/Framing.h>
#include <geometry/scene/Primitives.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>

namespace {

using testutil::Rendered;

class SampleMapsMethod : public GlTest {};

using Diff = testutil::VisibilityDiff;

Diff diff(const Rendered& a, const Rendered& b, float tol) {
    return testutil::visibilityDiff(a.visibility, b.visibility, tol);
}

TEST_F(SampleMapsMethod, EqualsTheReferenceOfTheSameSamplesOnOpaqueScenes) {
    struct Case {
        const char* scene;
        double mean;      // measured mean |dV| against reference N = 64: the maps' texels
                          // move each sample's shadow edge by a fraction of a texel, so the
                          // bands of the 64 samples fall slightly elsewhere
        std::size_t off;  // measured pixels off by > 0.1 (of 96²)
    };
    for (const Case& c : {Case{"parallel-square.json", 0.00091, 0},
                          Case{"plates-three.json", 0.00499, 0},
                          Case{"sphere.json", 0.00179, 0},
                          Case{"torus.json", 0.00291, 3}}) {
        SCOPED_TRACE(c.scene);
        const auto scene = geometry::loadScene(testutil::dataPath(c.scene));
        const Rendered ref = testutil::render(scene, "reference", 96, 96, 64);
        const Rendered r = testutil::render(scene, "sample-maps", 96, 96, 1);
        const Diff d = diff(r, ref, 0.1f);
        std::printf("  %s 96²: sample-maps vs reference N=64 (same samples): mean %.5f, %zu of "
                    "%zu pixels off by > 0.1\n",
                    c.scene, d.mean, d.off, d.pixels);
        EXPECT_GT(d.pixels, 1000u);
        EXPECT_LT(d.mean, c.mean + 0.0005);
        EXPECT_LE(d.off, c.off + 5);
        EXPECT_EQ(testutil::counter(r.stats, "sample_maps"), 64.0);
    }
}

TEST_F(SampleMapsMethod, TreesAloneAgainstAlphaAwareRaytrace) {
    const std::filesystem::path foliage = std::filesystem::path(PENUMBRA_SHARED_DIR) / "foliage";
    struct Case {
        const char* file;
        double mean, pcss; // measured (pcss: with its blockers confirmed in the pyramid)
    };
    for (const Case& c : {Case{"oak_hungarian_1.glb", 0.0111, 0.0343},
                          Case{"palm_date_new_1.glb", 0.0190, 0.0515}}) {
        SCOPED_TRACE(c.file);
        const auto scene = geometry::loadScene(foliage / c.file);
        const Rendered truth = testutil::render(scene, "raytrace", 128, 128, 256);
        const Rendered r = testutil::render(scene, "sample-maps", 128, 128, 1);
        const Rendered p = testutil::render(scene, "pcss", 128, 128, 1);
        const Diff d = diff(r, truth, 0.05f), dp = diff(p, truth, 0.05f);
        std::printf("  %s alone 128² vs raytrace N=256 over its %zu pixels: sample-maps mean "
                    "%.4f (%zu off by > 0.05), pcss %.4f (%zu)\n",
                    c.file, d.pixels, d.mean, d.off, dp.mean, dp.off);
        EXPECT_GT(d.pixels, 500u);
        EXPECT_LT(d.mean, 0.02); // the target
        EXPECT_LT(d.mean, c.mean + 0.002);
        EXPECT_LT(d.mean, 0.7 * dp.mean);
        EXPECT_LT(dp.mean, c.pcss + 0.005);
    }
}

TEST_F(SampleMapsMethod, EarlyOutGivesTheVOfEveryMap) {
    auto scene = geometry::loadScene(testutil::dataPath("tree-oak.json"));
    // The ground only receives, as in auto's composition (whose wedge path shadows it): its
    // pixels under the crown but outside every leaf's pyramid are the early out's.
    scene.objects[0].method = geometry::ShadowMethod::None;
    for (const char* plane : {"on", "off"}) {
        SCOPED_TRACE(plane);
        const Rendered on = testutil::render(scene, "sample-maps", 128, 128, 1,
                                             {{"early_out", "on"}, {"plane", plane}});
        const Rendered off = testutil::render(scene, "sample-maps", 128, 128, 1,
                                              {{"early_out", "off"}, {"plane", plane}});
        const Diff d = diff(on, off, 1e-6f);
        std::size_t shadowed = 0;
        for (const float v : off.visibility.data) shadowed += std::isfinite(v) && v < 0.99f;
        const double empty = testutil::counter(on.stats, "sample_maps_early_out_pixels");
        const double quadrants = testutil::counter(on.stats, "sample_maps_quadrant_skip_pixels");
        std::printf("  tree-oak 128², ground receiving, plane=%s: early_out on vs off: %zu of %zu "
                    "pixels differ (mean %.6f); %zu pixels shadowed; %.0f pixels read no map, "
                    "%.0f skipped some quadrants' maps\n",
                    plane, d.off, d.pixels, d.mean, shadowed, empty, quadrants);
        EXPECT_GT(shadowed, 2000u); // the oak's shadow is on the ground
        // Both tests skip work here (so the comparison tests them), and off counts nothing.
        EXPECT_GT(empty, 500.0);
        EXPECT_GT(quadrants, 200.0);
        EXPECT_EQ(testutil::counter(off.stats, "sample_maps_early_out_pixels"), 0.0);
        // Measured on llvmpipe: none differ. The early out is exact up to the maps'
        // rasterisation (a sliver map k misses), so another rasteriser may differ in a few.
        EXPECT_LE(d.off, d.pixels / 1000);
        EXPECT_LT(d.mean, 1e-5);
    }
}

TEST_F(SampleMapsMethod, CastersReachingTheLightsPlaneAreCountedAsClipped) {
    auto scene = geometry::loadScene(testutil::dataPath("sphere.json"));
    // The sphere casts, the floor only receives. Under the scene's light (above the sphere)
    // the maps hold the sphere; a horizontal light beside it, level with its centre, has half
    // of it behind its plane: clipped, and counted.
    scene.objects[0].method = geometry::ShadowMethod::None; // the floor only receives
    gpu::RenderSettings s = testutil::frameSettings("sample-maps", 48, 48);
    testutil::SceneRenderer above(scene);
    EXPECT_EQ(testutil::counter(above.renderer.renderFrame(s), "sample_maps_clipped"), 0.0);
    // The light's plane through the sphere: part of it behind every sample.
    geometry::RectLight level = scene.light;
    level.center = {0.0f, 1.0f, -1.5f};
    level.u = {0.3f, 0.0f, 0.0f};
    level.v = {0.0f, 0.0f, 0.3f};
    s.light = level;
    testutil::SceneRenderer beside(scene);
    EXPECT_EQ(testutil::counter(beside.renderer.renderFrame(s), "sample_maps_clipped"), 1.0);
}

TEST_F(SampleMapsMethod, TooMuchMapMemoryIsRefusedWithTheFigure) {
    const auto scene = geometry::loadScene(testutil::dataPath("sphere.json"));
    try {
        testutil::render(scene, "sample-maps", 32, 32, 1,
                         {{"samples", "256"}, {"resolution", "1024"}});
        FAIL() << "not refused";
    } catch (const geometry::InputError& e) {
        EXPECT_NE(std::string(e.what()).find("1024 MiB of shadow maps, over the 256 MiB limit"),
                  std::string::npos)
            << e.what();
    }
}

} // namespace
