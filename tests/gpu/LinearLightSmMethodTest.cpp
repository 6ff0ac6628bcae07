// The linear-light-sm method (Heidrich, Brabec & Seidel 2000; gpu/src/methods/SampleMapsMethod.cpp
// with linear lights, shaders/linear-light-skin.*) on the GL driver:
// - for a linear light (the paper's case) over one square, the skins' ramps give the penumbra
//   along the light against the reference of the same light, up to the maps' texels;
// - for the rectangle, built from parallel linear lights, the error falls as they are added
//   (measured on the parallel square and the three plates);
// - its known failure, the paper's own: a penumbra that no end point sees (the floor under a gap
//   between two plates, lit from the light's middle only) is drawn dark;
// - the maps and skins are reused while the light stays; bad parameters are refused.
#include "GlTestEnv.h"
#include "RenderTestUtil.h"

#include <geometry/core/Error.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

namespace {

using testutil::Rendered;

class LinearLightSmMethod : public GlTest {};

testutil::VisibilityDiff diff(const Rendered& a, const Rendered& b) {
    return testutil::visibilityDiff(a.visibility, b.visibility, 0.05f);
}

TEST_F(LinearLightSmMethod, ALinearLightsPenumbraFromTheSkins) {
    // The parallel square under a light 1 m long and 2 mm wide: the paper's linear light.
    auto scene = geometry::loadScene(testutil::dataPath("parallel-square.json"));
    scene.light.v *= 0.004f;
    const Rendered ref = testutil::render(scene, "reference", 128, 128, 256);
    const Rendered r = testutil::render(scene, "linear-light-sm", 128, 128, 1, {{"lights", "1"}});
    const Rendered hard = testutil::render(scene, "hard", 128, 128, 1);
    const testutil::VisibilityDiff d = diff(r, ref), dh = diff(hard, ref);
    // The penumbra's pixels (0.05 < V < 0.95 in the reference) and how many the skins give.
    std::size_t penumbra = 0, within = 0;
    for (std::size_t i = 0; i < ref.visibility.data.size(); ++i) {
        const float v = ref.visibility.data[i];
        if (!(v > 0.05f && v < 0.95f)) continue;
        ++penumbra;
        within += std::abs(r.visibility.data[i] - v) <= 0.1f;
    }
    std::printf("  linear light over the parallel square 128²: mean %.5f (%zu pixels off by > "
                "0.05), hard %.5f (%zu); %zu of %zu penumbra pixels within 0.1\n",
                d.mean, d.off, dh.mean, dh.off, within, penumbra);
    // Measured: mean 0.00071, 24 pixels off by > 0.05 (the maps' texels along the edges),
    // hard 0.01215 (601); every penumbra pixel within 0.1 (with the ramp interpolated with
    // perspective along the skin instead of linearly in the image: 0.00397, 351 of 601).
    EXPECT_GT(penumbra, 400u);
    EXPECT_LT(d.mean, 0.00071 + 0.0005);
    EXPECT_LE(d.off, 30u);
    EXPECT_EQ(within, penumbra);
    EXPECT_LT(d.mean, dh.mean / 4);
}

TEST_F(LinearLightSmMethod, ErrorFallsWithTheLinearLights) {
    struct Case {
        const char* scene;
        double mean[4]; // measured at lights = 1, 2, 4, 8
    };
    // Measured at 128² against reference N = 256. The plates' error stays high: each plate is
    // narrower than the light, so both end points of a linear light see points whose view of the
    // light's middle a plate hides (their skins then darken them), and the penumbra across the
    // linear lights comes in steps.
    for (const Case& c : {Case{"parallel-square.json", {0.00928, 0.00493, 0.00255, 0.00159}},
                          Case{"plates-three.json", {0.05618, 0.03452, 0.02339, 0.02036}}}) {
        SCOPED_TRACE(c.scene);
        const auto scene = geometry::loadScene(testutil::dataPath(c.scene));
        const Rendered ref = testutil::render(scene, "reference", 128, 128, 256);
        double means[4];
        for (int k = 0; k < 4; ++k) {
            const std::string lights = std::to_string(1 << k);
            const Rendered r =
                testutil::render(scene, "linear-light-sm", 128, 128, 1, {{"lights", lights}});
            means[k] = diff(r, ref).mean;
            EXPECT_EQ(testutil::counter(r.stats, "linear_light_sm_maps"), 2.0 * (1 << k));
            EXPECT_LT(means[k], c.mean[k] + 0.0005) << "lights=" << lights;
        }
        std::printf("  %s 128² vs reference N = 256, lights = 1, 2, 4, 8: %.5f %.5f %.5f %.5f\n",
                    c.scene, means[0], means[1], means[2], means[3]);
        EXPECT_LT(means[3], means[0]);
    }
}

TEST_F(LinearLightSmMethod, APenumbraNoEndPointSeesIsDrawnDark) {
    // data/stability/gap-between-plates.json: the floor under the 0.4 m gap between two plates
    // sees the 2 m light's middle through it, and neither end of any linear light.
    const auto scene = geometry::loadScene(testutil::dataPath("stability/gap-between-plates.json"));
    const Rendered ref = testutil::render(scene, "reference", 128, 128, 256);
    const Rendered r = testutil::render(scene, "linear-light-sm", 128, 128, 1);
    const Rendered sm = testutil::render(scene, "sample-maps", 128, 128, 1);
    std::size_t under = 0, dark = 0, smRight = 0;
    for (std::size_t i = 0; i < ref.visibility.data.size(); ++i) {
        const glm::vec3 p = testutil::pixelPosition(ref.position, i);
        if (!(std::abs(p.y) < 1e-3f && std::abs(p.x) < 0.05f && std::abs(p.z) < 0.5f)) continue;
        ++under;
        EXPECT_GT(ref.visibility.data[i], 0.4f);
        dark += r.visibility.data[i] < 0.05f;
        smRight += std::abs(sm.visibility.data[i] - ref.visibility.data[i]) < 0.1f;
    }
    std::printf("  gap between plates 128²: %zu floor pixels under the gap (V > 0.4 in the "
                "reference): %zu dark in linear-light-sm, %zu within 0.1 in sample-maps\n",
                under, dark, smRight);
    EXPECT_GT(under, 20u);
    EXPECT_EQ(dark, under); // the failure, as the paper describes it
    EXPECT_EQ(smRight, under);
}

// Levels from their first spawn camera with the viewer's lamp, against raytrace N = 256. The lamp
// hangs in a room: casters reach the light's plane, so the end points' maps are clipped (as
// sample-maps' are) and what they cannot hold hides nothing: on oa_dm5's view the walls left and
// right, dark in the reference, are drawn lit (the method's failure there, and sample-maps':
// 0.23238); kaos2's view lies within the maps (no shadow in it but along the walls' feet).
TEST_F(LinearLightSmMethod, LevelSpawnViewsWithTheLamp) {
    struct Case {
        const char* level;
        double mean; // measured
    };
    // Measured at 128x72: kaos2 0.00223 (90 pixels off by > 0.05; sample-maps 0.00902), oa_dm5
    // 0.23263 (2513 of 9193).
    for (const Case& c : {Case{"kaos2.glb", 0.00223}, Case{"oa_dm5.glb", 0.23263}}) {
        SCOPED_TRACE(c.level);
        const geometry::Scene scene = testutil::levelWithLamp(c.level, 0);
        const Rendered ref = testutil::render(scene, "raytrace", 128, 72, 256);
        const Rendered r = testutil::render(scene, "linear-light-sm", 128, 72, 1);
        const Rendered sm = testutil::render(scene, "sample-maps", 128, 72, 1);
        const testutil::VisibilityDiff d = diff(r, ref), ds = diff(sm, ref);
        std::printf("  %s camera 0 128x72 vs raytrace N = 256: linear-light-sm mean %.5f (%zu of "
                    "%zu off by > 0.05), sample-maps %.5f; clipped %g\n",
                    c.level, d.mean, d.off, d.pixels, ds.mean,
                    testutil::counter(r.stats, "linear_light_sm_clipped"));
        EXPECT_EQ(testutil::counter(r.stats, "linear_light_sm_clipped"), 1.0);
        EXPECT_LT(d.mean, c.mean + 0.001);
    }
}

TEST_F(LinearLightSmMethod, MapsAndSkinsAreReusedWhileTheLightStays) {
    const auto scene = geometry::loadScene(testutil::dataPath("parallel-square.json"));
    testutil::SceneRenderer sr(scene);
    gpu::RenderSettings s = testutil::frameSettings("linear-light-sm", 64, 64);
    EXPECT_EQ(testutil::counter(sr.renderer.renderFrame(s), "linear_light_sm_cached"), 0.0);
    EXPECT_EQ(testutil::counter(sr.renderer.renderFrame(s), "linear_light_sm_cached"), 1.0);
    geometry::RectLight moved = scene.light;
    moved.center.x += 0.3f;
    s.light = moved;
    EXPECT_EQ(testutil::counter(sr.renderer.renderFrame(s), "linear_light_sm_cached"), 0.0);
}

TEST_F(LinearLightSmMethod, BadParametersAreRefused) {
    const auto scene = geometry::loadScene(testutil::dataPath("parallel-square.json"));
    for (const gpu::ParameterValue& p :
         {gpu::ParameterValue{"lights", "3"}, gpu::ParameterValue{"resolution", "64"},
          gpu::ParameterValue{"samples", "16"}}) {
        SCOPED_TRACE(p.name + "=" + p.value);
        EXPECT_THROW(testutil::render(scene, "linear-light-sm", 32, 32, 1, {p}),
                     geometry::InputError);
    }
}

} // namespace
