// The wedge methods on the GPU against their CPU model and against the reference:
// - The GPU's V equals clamp(V_hard - Σ edgeCoverage) evaluated on the CPU (double) at the
//   G-buffer positions of the same render, for the same directed silhouette edges: this checks
//   the GPU hulls (no pixel with coverage may be missed), the float coverage and the blending.
// - One occluder: V against the GPU reference (N = 256, 128²): mean ≤ 0.01, p99 ≤ 0.05.
// - Hard cases (camera inside a wedge or a volume, light close to an occluder, an edge touching
//   the light's plane): no GL error, no NaN, V in [0, 1].
#include "GlTestEnv.h"
#include "RenderTestUtil.h"

#include <geometry/reference/Analytic.h>
#include <geometry/models/BlendModel.h>
#include <geometry/reference/ErrorStats.h>
#include <geometry/reference/Framing.h>
#include <geometry/reference/RayTracer.h>
#include <geometry/shadow/Silhouette.h>
#include <geometry/shadow/Topology.h>
#include <geometry/shadow/Wedge.h>

#include <algorithm>
#include <array>
#include <numeric>
#include <cmath>

namespace {

using testutil::Rendered;

// Σ over the light centre's directed silhouette edges of edgeCoverage at every surface pixel
// (the settings of the GPU path: gpu/src/engine/CasterSet.cpp).
std::vector<double> cpuCoverageSum(const geometry::Scene& scene, const Rendered& r) {
    const geometry::SilhouetteSettings settings = geometry::SilhouetteSettings::lean();
    std::vector<std::pair<glm::vec3, glm::vec3>> edges;
    for (const auto& object : scene.objects) {
        if (object.method == geometry::ShadowMethod::None) continue;
        const geometry::Topology topology(object.mesh);
        geometry::SilhouetteExtractor extractor(topology);
        const geometry::SilhouetteFrame& f = extractor.update(scene.light, scene.bounds(), settings);
        for (const auto& e : f.edges)
            edges.emplace_back(topology.positions()[e.v0], topology.positions()[e.v1]);
    }
    std::vector<double> sum(r.visibility.data.size(), 0.0);
    for (std::size_t i = 0; i < sum.size(); ++i) {
        if (!std::isfinite(r.visibility.data[i])) continue;
        const glm::vec3 p = testutil::pixelPosition(r.position, i);
        for (const auto& [e0, e1] : edges) sum[i] += geometry::edgeCoverage(p, e0, e1, scene.light);
    }
    return sum;
}

struct ModelCheck {
    std::size_t pixels = 0, wrong = 0, penumbra = 0;
    double maxErr = 0.0;
};

ModelCheck checkAgainstModel(const std::filesystem::path& path, int size, float tolerance) {
    auto scene = geometry::loadScene(path);
    if (!scene.cameras.empty()) geometry::selectFramedCamera(scene); // a level: its framed view
    const std::string sceneFile = path.filename().string();
    const Rendered hard = testutil::render(scene, "hard", size);
    const Rendered additive = testutil::render(scene, "wedges-additive", size);
    const std::vector<double> sum = cpuCoverageSum(scene, additive);
    ModelCheck c;
    std::vector<float> expected(sum.size(), std::nanf(""));
    for (std::size_t i = 0; i < sum.size(); ++i) {
        const float v = additive.visibility.data[i];
        if (!std::isfinite(v)) continue;
        ++c.pixels;
        const double e = std::clamp(double(hard.visibility.data[i]) - sum[i], 0.0, 1.0);
        expected[i] = float(e);
        if (e > 0.01 && e < 0.99) ++c.penumbra;
        const double err = std::abs(v - e);
        c.maxErr = std::max(c.maxErr, err);
        if (err > tolerance) {
            ++c.wrong;
            const glm::vec3 p = testutil::pixelPosition(additive.position, i);
            std::printf("  pixel %zu (x %zu, y %zu) at (%.4f %.4f %.4f): GPU %.4f, model %.4f "
                        "(hard %.0f, coverage sum %.4f)\n",
                        i, i % size, i / size, p.x, p.y, p.z, v, e, hard.visibility.data[i],
                        sum[i]);
        }
    }
    if (c.wrong > 0) testutil::writeComparisonImages("additive-model-" + sceneFile, additive.visibility,
                                                     expected);
    return c;
}

class AdditiveWedges : public GlTest {};

// Float (GPU) against double (CPU) coverage: a few 1e-5 per edge at these scales; a pixel whose
// sum is off by more than 2e-3 has a missed or extra wedge, not rounding.
constexpr float kModelTolerance = 2e-3f;

TEST_F(AdditiveWedges, GpuEqualsCpuModelOnOverlappingPlates) {
    const ModelCheck c = checkAgainstModel(testutil::dataPath("overlap.json"), 128, kModelTolerance);
    std::printf("  overlap.json: %zu pixels, %zu in penumbra, max |GPU - model| %.2e\n", c.pixels,
                c.penumbra, c.maxErr);
    EXPECT_GT(c.penumbra, 500u); // the test sees a real penumbra
    EXPECT_EQ(c.wrong, 0u);
}

TEST_F(AdditiveWedges, GpuEqualsCpuModelOnTheDemo) {
    const ModelCheck c = checkAgainstModel(testutil::dataPath("demo.json"), 128, kModelTolerance);
    std::printf("  demo.json: %zu pixels, %zu in penumbra, max |GPU - model| %.2e\n", c.pixels,
                c.penumbra, c.maxErr);
    EXPECT_GT(c.penumbra, 500u);
    // Measured: 1 pixel (0.185 off), on a box face in its own hard shadow whose plane contains
    // one of the silhouette edges and cuts the light: there P lies on the plane through the
    // edge, its projection of the edge degenerates to the line where that plane meets the
    // light's, and float and double resolve the sign of the cross product differently. A pixel
    // with a missing or extra wedge would show along a whole penumbra, not alone.
    EXPECT_LE(c.wrong, 3u);
}

TEST_F(AdditiveWedges, GpuEqualsCpuModelOnALevel) {
    // Thousands of open-mesh silhouette edges seen from inside, wedges around the camera.
    const auto path = testutil::sharedPath("levels/oa_dm4.glb");
    ASSERT_TRUE(std::filesystem::exists(path)) << path;
    const ModelCheck c = checkAgainstModel(path, 96, kModelTolerance);
    std::printf("  oa_dm4: %zu pixels, %zu in penumbra, %zu off, max |GPU - model| %.2e\n",
                c.pixels, c.penumbra, c.wrong, c.maxErr);
    EXPECT_GT(c.penumbra, 100u);
    EXPECT_LE(c.wrong, 3u);
}

geometry::ErrorStats againstReference(const std::string& sceneFile, const std::string& method,
                                      int size = 128, int samples = 256) {
    const auto scene = geometry::loadScene(testutil::dataPath(sceneFile));
    const Rendered ref = testutil::render(scene, "reference", size, samples);
    const Rendered r = testutil::render(scene, method, size);
    const auto e = geometry::compareVisibility(r.visibility.data, ref.visibility.data);
    std::printf("  %s %s vs reference N=%d at %d²: mean %.4f, p99 %.4f, max %.4f, %.2f%% > 0.05\n",
                sceneFile.c_str(), method.c_str(), samples, size, e.meanAbs, e.p99, e.max,
                e.badPixelPct);
    return e;
}

// One occluder, one silhouette: additive wedges are exact up to the reference's sampling.
class AdditiveOneOccluder : public GlTest, public ::testing::WithParamInterface<const char*> {};

TEST_P(AdditiveOneOccluder, MatchesTheReference) {
    const auto e = againstReference(GetParam(), "wedges-additive");
    EXPECT_LE(e.meanAbs, 0.01);
    EXPECT_LE(e.p99, 0.05);
    EXPECT_LE(e.badPixelPct, 1.0); // measured 0, 0, 0.43 %
    // The hard shadow of the same view is far off: the test measures the penumbra.
    EXPECT_GT(againstReference(GetParam(), "hard").meanAbs, 10 * e.meanAbs);
}

// Measured (128², N = 256): plate 0.0004 / p99 0.008, tilted plate 0.0010 / 0.011, box 0.0015 /
// 0.029 (the box's bottom edges: its own faces and the floor meet its penumbra).
INSTANTIATE_TEST_SUITE_P(Scenes, AdditiveOneOccluder,
                         ::testing::Values("parallel-square.json", "plate-tilted.json",
                                           "box.json"));

// Where additive wedges fail, measured and bounded (never loosened to pass): mean error against
// the reference at 128², N = 256, with ~25% headroom for sampling and rasterisation; every one
// stays better than hard shadows. Penumbrae of different silhouette groups overlap in all of
// them; where their *hard* shadows overlap too, one group's negative coverage (inside its hard
// shadow) adds light back inside the other's umbra: light leaks (plates-three, diamonds).
// A method's error on a scene as measured (against the reference, 128², N = 256).
struct MeasuredCase {
    const char* scene;
    double measuredMean;
    double measuredP99;
    double measuredBadPct; // % of pixels off by more than 0.05
};

// The measured error with ~25% headroom for sampling and rasterisation; returns the error.
geometry::ErrorStats expectAsMeasured(const std::string& method, const MeasuredCase& c) {
    const auto e = againstReference(c.scene, method);
    EXPECT_LE(e.meanAbs, 1.25 * c.measuredMean + 0.001);
    EXPECT_LE(e.p99, 1.25 * c.measuredP99 + 0.01);
    EXPECT_LE(e.badPixelPct, 1.25 * c.measuredBadPct + 0.25);
    return e;
}

// "plates-three.json" -> "plates_three" (test names).
std::string sceneTestName(const ::testing::TestParamInfo<MeasuredCase>& info) {
    std::string name = info.param.scene;
    name = name.substr(0, name.find('.'));
    std::replace(name.begin(), name.end(), '-', '_');
    return name;
}

class AdditiveOverlap : public GlTest, public ::testing::WithParamInterface<MeasuredCase> {};

TEST_P(AdditiveOverlap, ErrorIsAsMeasured) {
    const auto e = expectAsMeasured("wedges-additive", GetParam());
    EXPECT_LT(e.meanAbs, againstReference(GetParam().scene, "hard").meanAbs);
}

INSTANTIATE_TEST_SUITE_P(
    Scenes, AdditiveOverlap,
    ::testing::Values(MeasuredCase{"overlap.json", 0.0022, 0.029, 0.63},
                      MeasuredCase{"plates-three.json", 0.0459, 0.711, 17.40},
                      MeasuredCase{"bars-cross.json", 0.0068, 0.171, 2.31},
                      MeasuredCase{"spheres-nine.json", 0.0138, 0.277, 4.11},
                      MeasuredCase{"torus-box.json", 0.0066, 0.216, 1.76},
                      MeasuredCase{"diamonds.json", 0.0177, 0.504, 6.16}),
    sceneTestName);

TEST_F(AdditiveWedges, OverlapIsWorseThanOneOccluder) {
    // The failure is real, not noise: light leaks where hard shadows overlap.
    EXPECT_GT(againstReference("plates-three.json", "wedges-additive").meanAbs, 0.03);
}

// Curved occluders: wedges from the light centre's silhouette (Assarsson & Akenine-Möller)
// miss part of the penumbra where other light points see another silhouette. Measured (128²,
// N = 256): sphere mean 0.0043, p99 0.10, max 0.43; torus 0.0054, 0.12, 0.49 — concentrated on
// the occluders' own terminators; their floor shadows are close to exact.
TEST_F(AdditiveWedges, CurvedOccludersApproximateAsMeasured) {
    const auto sphere = againstReference("sphere.json", "wedges-additive");
    const auto torus = againstReference("torus.json", "wedges-additive");
    EXPECT_LE(sphere.meanAbs, 0.006);
    EXPECT_LE(sphere.p99, 0.13);
    EXPECT_LE(torus.meanAbs, 0.007);
    EXPECT_LE(torus.p99, 0.15);
}

TEST_F(AdditiveWedges, OpenArenaLevelErrorIsMeasured) {
    // A real level seen from inside (framed view, light under the ceiling): thousands of open
    // silhouette edges in hundreds of groups whose penumbrae overlap everywhere. Additive wedges
    // double-count there, and inside one group's hard shadow another group's negative coverage
    // adds light back (light leaks): the method is worse than hard shadows on such a view.
    const auto path = testutil::sharedPath("levels/oa_dm4.glb");
    ASSERT_TRUE(std::filesystem::exists(path)) << path;
    const auto scene = testutil::framedLevel("levels/oa_dm4.glb");
    const Rendered ref = testutil::render(scene, "reference", 128, 96, 64);
    const Rendered hard = testutil::render(scene, "hard", 128, 96, 1);
    const Rendered add = testutil::render(scene, "wedges-additive", 128, 96, 1);
    const auto eh = geometry::compareVisibility(hard.visibility.data, ref.visibility.data);
    const auto ea = geometry::compareVisibility(add.visibility.data, ref.visibility.data);
    std::printf("  oa_dm4 128x96 vs reference N=64: hard mean %.4f p99 %.3f %.2f%% > 0.05; "
                "additive mean %.4f p99 %.3f %.2f%% > 0.05\n",
                eh.meanAbs, eh.p99, eh.badPixelPct, ea.meanAbs, ea.p99, ea.badPixelPct);
    // Measured here: hard mean 0.038 (p99 0.47), additive mean 0.078 (p99 1.0, 19% of pixels
    // off by more than 0.05): documented, not hidden; per-silhouette blending is the fix.
    EXPECT_LT(ea.meanAbs, 0.12);
    EXPECT_GT(ea.meanAbs, eh.meanAbs);
}

void expectValidIn(const Rendered& r) {
    std::size_t surface = 0;
    for (float v : r.visibility.data) {
        if (std::isnan(v)) continue; // no surface
        ++surface;
        ASSERT_TRUE(std::isfinite(v));
        ASSERT_GE(v, 0.0f);
        ASSERT_LE(v, 1.0f);
    }
    EXPECT_GT(surface, 0u);
}

// Renders V with each wedge method and checks it is finite and within [0, 1] on every surface
// pixel.
double counter(const Rendered& r, const std::string& name) {
    for (const auto& c : r.stats.counters)
        if (c.name == name) return c.value;
    return -1.0;
}

void expectValidVisibility(const geometry::Scene& scene, int size = 64) {
    for (const char* method :
         {"wedges-additive", "wedges-multiply", "wedges-blend", "wedges-bitmask"}) {
        SCOPED_TRACE(method);
        const Rendered r = testutil::render(scene, method, size);
        expectValidIn(r);
    }
}

geometry::Scene sceneFromJson(const std::string& json) {
    return geometry::parseScene(json, testutil::dataPath("."), "test scene");
}

constexpr const char* kPlateAndFloor = R"(
    {"name": "floor", "type": "quad", "center": [0, 0, 0], "u": [3, 0, 0], "v": [0, 0, -3]},
    {"name": "plate", "type": "quad", "center": [0, 1, 0], "u": [0.5, 0, 0], "v": [0, 0, -0.5]},
    {"name": "box", "type": "box", "center": [1.2, 0.6, 0.3], "size": [0.4, 0.4, 0.4]})";

TEST_F(AdditiveWedges, CameraInsideAWedge) {
    // Just below the plate's edge, looking down at the floor: inside that edge's wedge.
    expectValidVisibility(sceneFromJson(std::string(R"({
        "camera": {"eye": [0.5, 0.8, 0.0], "target": [0.6, 0, 0.2], "up": [0, 0, -1], "fov_y_deg": 60},
        "light": {"center": [0, 3, 0], "u": [0.5, 0, 0], "v": [0, 0, 0.5]},
        "objects": [)") + kPlateAndFloor + "]}"));
}

TEST_F(AdditiveWedges, CameraInsideAVolume) {
    expectValidVisibility(sceneFromJson(std::string(R"({
        "camera": {"eye": [0.0, 0.5, 0.0], "target": [1.5, 0, 0.5], "up": [0, 1, 0], "fov_y_deg": 70},
        "light": {"center": [0, 3, 0], "u": [0.5, 0, 0], "v": [0, 0, 0.5]},
        "objects": [)") + kPlateAndFloor + "]}"));
}

TEST_F(AdditiveWedges, PerSilhouetteUmbraWithoutWedgesIsDark) {
    // The camera inside the plate's umbra (light and plate the same size: the umbra is the prism
    // |x|, |z| <= 0.5 below the plate), looking straight down: no wedge lies between the camera
    // and the floor, so no wedge marks these pixels; only the plate's volume reaches them, and
    // the per-silhouette methods must still combine the group's full occlusion there.
    const auto scene = sceneFromJson(std::string(R"({
        "camera": {"eye": [0.0, 0.5, 0.0], "target": [0, 0, 0], "up": [0, 0, -1], "fov_y_deg": 20},
        "light": {"center": [0, 3, 0], "u": [0.5, 0, 0], "v": [0, 0, 0.5]},
        "objects": [)") + kPlateAndFloor + "]}");
    for (const char* method : {"wedges-multiply", "wedges-blend", "wedges-bitmask"}) {
        SCOPED_TRACE(method);
        const Rendered r = testutil::render(scene, method, 64);
        expectValidIn(r);
        double maxV = 0.0;
        for (const float v : r.visibility.data)
            if (std::isfinite(v)) maxV = std::max(maxV, double(v));
        std::printf("  %s: max V %.4f, %.0f umbra pixels, %.0f touched\n", method, maxV,
                    counter(r, "pixels_umbra"), counter(r, "pixels_blended"));
        EXPECT_EQ(maxV, 0.0);
        // wedges-bitmask's default (silhouettes=potential) has no per-group umbra step: its
        // stencil count alone hides every sample there (V = 0, checked above).
        if (std::string(method) != "wedges-bitmask") {
            EXPECT_GT(counter(r, "pixels_umbra"), 0.5 * 64 * 64);
        }
    }
}

TEST_F(AdditiveWedges, LightCloseToAnOccluder) {
    expectValidVisibility(sceneFromJson(std::string(R"({
        "camera": {"eye": [0, 4, 3], "target": [0, 0, 0], "up": [0, 1, 0], "fov_y_deg": 50},
        "light": {"center": [0, 1.02, 0], "u": [0.4, 0, 0], "v": [0, 0, 0.4]},
        "objects": [)") + kPlateAndFloor + "]}"));
}

TEST_F(AdditiveWedges, EdgeTouchingTheLightsPlane) {
    // A wall whose top edge lies in the light's plane and points at the light: seen along that
    // edge the light surrounds its line, so its wedge has no bounded hull and takes the
    // full-screen path.
    const auto scene = sceneFromJson(R"({
        "camera": {"eye": [0, 4, 4], "target": [0, 0, 0], "up": [0, 1, 0], "fov_y_deg": 60},
        "light": {"center": [0, 2, 0], "u": [0.3, 0, 0], "v": [0, 0, 0.3]},
        "objects": [
            {"name": "floor", "type": "quad", "center": [0, 0, 0], "u": [3, 0, 0], "v": [0, 0, -3]},
            {"name": "wall", "type": "quad", "center": [1.5, 1, 0], "u": [0.5, 0, 0], "v": [0, 1, 0]}
        ]})");
    expectValidVisibility(scene);
    const Rendered r = testutil::render(scene, "wedges-additive", 64);
    double fullscreen = -1;
    for (const auto& c : r.stats.counters)
        if (c.name == "wedges_fullscreen") fullscreen = c.value;
    EXPECT_GT(fullscreen, 0.0);
}

// ---- wedges-multiply: per-silhouette visibility buffers, V = Π V_s ---------------------------

// Measured (128², N = 256). One group per occluder: multiply equals additive where one group
// alone is involved; where hard shadows of different groups overlap it has no light leaks.
class MultiplyScenes : public GlTest, public ::testing::WithParamInterface<MeasuredCase> {};

TEST_P(MultiplyScenes, ErrorIsAsMeasured) { expectAsMeasured("wedges-multiply", GetParam()); }

INSTANTIATE_TEST_SUITE_P(
    Scenes, MultiplyScenes,
    ::testing::Values(MeasuredCase{"parallel-square.json", 0.0004, 0.008, 0.0},
                      MeasuredCase{"box.json", 0.0015, 0.029, 0.43},
                      MeasuredCase{"overlap.json", 0.0031, 0.064, 1.16},
                      MeasuredCase{"plates-three.json", 0.0098, 0.096, 8.01},
                      MeasuredCase{"bars-cross.json", 0.0016, 0.024, 0.10},
                      MeasuredCase{"spheres-nine.json", 0.0188, 0.277, 9.42},
                      MeasuredCase{"torus-box.json", 0.0036, 0.079, 1.28},
                      MeasuredCase{"diamonds.json", 0.0025, 0.026, 0.0}),
    sceneTestName);

TEST_F(AdditiveWedges, MultiplyRemovesTheLightLeaksWhereHardShadowsOverlap) {
    for (const char* scene : {"plates-three.json", "diamonds.json"}) {
        SCOPED_TRACE(scene);
        const double additive = againstReference(scene, "wedges-additive").meanAbs;
        const double multiply = againstReference(scene, "wedges-multiply").meanAbs;
        // Measured: plates-three 0.0459 -> 0.0098, diamonds 0.0177 -> 0.0025.
        EXPECT_LT(multiply, 0.5 * additive);
    }
}

TEST_F(AdditiveWedges, MultiplyBatchesGroupsThatCannotInteract) {
    // Passes grow with the overlap depth, not the number of groups: eight small boxes far apart
    // under a small light have disjoint screen rectangles and share one batch; the floor's own
    // group covers the screen and takes another.
    std::string objects =
        R"({"name": "floor", "type": "quad", "center": [0, 0, 0], "u": [9, 0, 0], "v": [0, 0, -9]})";
    for (int i = 0; i < 8; ++i) {
        const float x = -7.0f + 2.0f * static_cast<float>(i);
        objects += R"(, {"type": "box", "center": [)" + std::to_string(x) +
                   R"(, 0.5, 0], "size": [0.3, 0.3, 0.3]})";
    }
    const auto scene = sceneFromJson(R"({
        "camera": {"eye": [0, 12, 0.01], "target": [0, 0, 0], "up": [0, 0, -1], "fov_y_deg": 70},
        "light": {"center": [0, 6, 0], "u": [0.1, 0, 0], "v": [0, 0, 0.1]},
        "objects": [)" + objects + "]}");
    const Rendered mul = testutil::render(scene, "wedges-multiply", 128);
    expectValidIn(mul);
    std::printf("  9 casters: %.0f groups drawn, %.0f batches\n", counter(mul, "groups_drawn"),
                counter(mul, "batches"));
    EXPECT_EQ(counter(mul, "groups_drawn"), 9.0);
    EXPECT_LE(counter(mul, "batches"), 3.0);
    // Within a batch's rectangle only the pixels its wedges or volumes reach are combined (the
    // stencil mark): far fewer than the rectangles hold, and some in the umbrae.
    const double touched = counter(mul, "pixels_blended"), umbra = counter(mul, "pixels_umbra"),
                 rects = counter(mul, "batch_rect_pixels");
    std::printf("  combined: %.0f touched + %.0f umbra of %.0f rectangle pixels\n", touched,
                umbra, rects);
    EXPECT_GT(touched, 0.0);
    EXPECT_LT(touched + umbra, 0.5 * rects);
    // And the batched result is the same as multiplying group by group would be: the additive
    // method is exact here (no two groups' penumbrae meet), so the two must agree.
    const Rendered add = testutil::render(scene, "wedges-additive", 128);
    double maxDiff = 0.0;
    for (std::size_t i = 0; i < mul.visibility.data.size(); ++i)
        if (std::isfinite(mul.visibility.data[i]))
            maxDiff = std::max(maxDiff, double(std::abs(mul.visibility.data[i] -
                                                        add.visibility.data[i])));
    EXPECT_LT(maxDiff, 1e-4);
}

TEST_F(AdditiveWedges, MultiplyStrayPixelsAreBounded) {
    // Each group's volume is counted alone, so a volume edge grazing a G-buffer point is not
    // cancelled by a neighbouring group's coincident face as it is in the all-groups count.
    // Measured on the demo at 512²: two pixels where the left wall meets the floor (G-buffer
    // points 12 µm from the floor's volume edge) read 0 instead of 1; and two on the boxes
    // where the light's plane crosses the surface's own plane at a grazing edge, which the
    // reference hides by the receiver's own-plane rule (raytrace: 0.48 and 0; the reference
    // 0.47 and 0) and the centre's wedges do not (1).
    const auto scene = geometry::loadScene(testutil::dataPath("demo.json"));
    const Rendered ref = testutil::render(scene, "reference", 512, 512, 32);
    const Rendered mul = testutil::render(scene, "wedges-multiply", 512);
    std::size_t off = 0;
    for (std::size_t i = 0; i < ref.visibility.data.size(); ++i)
        if (std::isfinite(ref.visibility.data[i]) &&
            std::abs(ref.visibility.data[i] - mul.visibility.data[i]) > 0.5f)
            ++off;
    std::printf("  demo 512²: %zu pixels off by more than 0.5\n", off);
    EXPECT_LE(off, 5u);
}

// The model's groups of a scene (lean silhouettes, as the renderer extracts them).
std::vector<geometry::blend::Group> modelGroups(const geometry::Scene& scene) {
    std::vector<geometry::blend::Group> groups;
    for (const auto& object : scene.objects) {
        if (object.method == geometry::ShadowMethod::None) continue;
        const geometry::Topology topology(object.mesh);
        geometry::SilhouetteExtractor extractor(topology);
        const auto& f =
            extractor.update(scene.light, scene.bounds(), geometry::SilhouetteSettings::lean());
        for (auto& g : geometry::blend::silhouetteGroups(f, topology)) groups.push_back(g);
    }
    return groups;
}

// The GPU's multiply against its CPU model at the G-buffer points of the same render:
// V = Π over groups of clamp(V_hard,s - Σ_s edgeCoverage), V_hard,s from the group's own
// z-fail count (geometry::blend::centreCount). This checks the batching, the per-batch
// stencil clears and scissors and the product, not only the tolerance against the reference.
TEST_F(AdditiveWedges, MultiplyEqualsItsCpuModel) {
    for (const char* sceneFile : {"plates-three.json", "diamonds.json", "bars-cross.json"}) {
        SCOPED_TRACE(sceneFile);
        const auto scene = geometry::loadScene(testutil::dataPath(sceneFile));
        const Rendered mul = testutil::render(scene, "wedges-multiply", 128);
        const auto light = geometry::blend::lightFrame(scene.light);
        const std::vector<geometry::blend::Group> groups = modelGroups(scene);
        std::size_t pixels = 0, wrong = 0;
        double maxErr = 0.0;
        for (std::size_t i = 0; i < mul.visibility.data.size(); ++i) {
            if (!std::isfinite(mul.visibility.data[i])) continue;
            ++pixels;
            const glm::dvec3 p(testutil::pixelPosition(mul.position, i));
            double v = 1.0;
            // A point on an occluder counts as outside that occluder's own volume (the GPU's
            // cap offset): the hard query starts a hair towards the light centre.
            const glm::dvec3 lifted = p + 1e-5 * (light.c - p);
            for (const auto& g : groups) {
                double vs = geometry::blend::centreCount(light, lifted, g) != 0 ? 0.0 : 1.0;
                for (const auto& e : g.edges)
                    vs -= geometry::edgeCoverage(glm::vec3(p), glm::vec3(e[0]), glm::vec3(e[1]),
                                                 scene.light);
                v *= std::clamp(vs, 0.0, 1.0);
            }
            const double err = std::abs(v - mul.visibility.data[i]);
            maxErr = std::max(maxErr, err);
            if (err > kModelTolerance && wrong++ < 4)
                std::printf("    p (%.4f %.4f %.4f): GPU %.4f model %.4f\n", p.x, p.y, p.z,
                            mul.visibility.data[i], v);
        }
        std::printf("  %s: %zu pixels, %zu off by > %.0e, max %.2e\n", sceneFile, pixels, wrong,
                    double(kModelTolerance), maxErr);
        EXPECT_EQ(wrong, 0u); // measured: 0 of 16,384 (max 2e-6)
    }
}

TEST_F(AdditiveWedges, PerSilhouetteMethodsOnALevelAreMeasured) {
    // A level seen from inside: most groups' influence rectangles cover most of the screen, and
    // only depth-aware batching keeps the passes few (measured: 16 groups drawn, 149 culled,
    // 7 batches; by rectangles alone 90 groups in 66 batches), and
    // groups of open level geometry overlap their own penumbrae (light leaks inside one group,
    // which no per-group combination removes): multiply is worse than hard shadows on this view.
    const auto path = testutil::sharedPath("levels/oa_dm4.glb");
    ASSERT_TRUE(std::filesystem::exists(path)) << path;
    const auto scene = testutil::framedLevel("levels/oa_dm4.glb");
    const Rendered ref = testutil::render(scene, "reference", 128, 96, 64);
    const Rendered mul = testutil::render(scene, "wedges-multiply", 128, 96, 1);
    expectValidIn(mul);
    const Rendered blend = testutil::render(scene, "wedges-blend", 128, 96, 1);
    expectValidIn(blend);
    const auto eb = geometry::compareVisibility(blend.visibility.data, ref.visibility.data);
    std::printf("  oa_dm4 128x96: blend vs reference N=64: mean %.4f p99 %.3f %.2f%% > 0.05\n",
                eb.meanAbs, eb.p99, eb.badPixelPct);
    EXPECT_LT(eb.meanAbs, 0.06); // measured 0.0454: per-group self-overlap, as for multiply
    const auto e = geometry::compareVisibility(mul.visibility.data, ref.visibility.data);
    std::printf("  oa_dm4 128x96: %.0f groups drawn, %.0f culled, %.0f batches; multiply vs "
                "reference N=64: mean %.4f p99 %.3f %.2f%% > 0.05\n",
                counter(mul, "groups_drawn"), counter(mul, "groups_culled"),
                counter(mul, "batches"), e.meanAbs, e.p99, e.badPixelPct);
    EXPECT_LT(e.meanAbs, 0.06); // measured 0.0485 (hard 0.0376, additive 0.0776)
    // wedges-bitmask with the reference's own 64 samples (measured 0.0365; with combine=parity
    // 0.0446: a group of open level geometry folding behind itself reads doubly covered samples
    // as lit). What remains is the centre's silhouette standing for the whole light's.
    const Rendered bits = testutil::render(scene, "wedges-bitmask", 128, 96, 1);
    expectValidIn(bits);
    const auto ek = geometry::compareVisibility(bits.visibility.data, ref.visibility.data);
    std::printf("  oa_dm4 128x96: bitmask N=64 vs reference N=64: mean %.4f p99 %.3f %.2f%% > "
                "0.05\n",
                ek.meanAbs, ek.p99, ek.badPixelPct);
    EXPECT_LT(ek.meanAbs, eb.meanAbs);
}

// Depth-aware culling (GroupBatches.h) leaves out the groups and wedges that reach no visible
// surface tile, and batches the rest by those tiles. Against drawing every group in the view
// frustum (batched by screen rectangles), on kaos2's spawn views with the viewer's lamp (hung
// under the ceiling ahead): hard must give the same V bit for bit, additive and multiply the
// same up to float order (a sum, a product), blend the same up to the order in which groups
// blend (it is not commutative: within a few 8-bit steps, as BlendEqualsItsCpuModel allows).
// wedges-bitmask's default (potential silhouettes, no groups) leaves out single potential edges
// whose shadow cones reach no visible surface: the same V up to the order of its float area sum.
// A group or wedge left out wrongly shows as a whole missing shadow or penumbra, far more.
TEST_F(AdditiveWedges, DepthAwareCullingChangesOnlyTheOrder) {
    const auto path = testutil::sharedPath("levels/kaos2.glb");
    ASSERT_TRUE(std::filesystem::exists(path)) << path;
    geometry::Scene scene = geometry::loadScene(path);
    const geometry::RayTracer tracer(scene);
    gpu::ShaderLoader shaders(gpu::defaultShaderDir());
    for (const int camera : {3, 8}) {
        geometry::selectCamera(scene, camera);
        const std::optional<geometry::RectLight> lamp =
            geometry::lampAhead(scene, tracer, scene.camera);
        ASSERT_TRUE(lamp) << "camera " << camera;
        gpu::Renderer renderer(scene, shaders);
        for (const std::string variant : {"hard", "wedges-additive", "wedges-multiply",
                                          "wedges-blend", "wedges-bitmask", "potential"}) {
            // "potential": wedges-bitmask's default, one pass with no groups, whose culling is
            // per potential edge (its wedges' A sums in another order).
            const bool potential = variant == "potential";
            const std::string method = potential ? "wedges-bitmask" : variant;
            SCOPED_TRACE(variant + " camera " + std::to_string(camera));
            const bool batched = variant == "wedges-multiply" || variant == "wedges-blend" ||
                                 variant == "wedges-bitmask";
            gpu::RenderSettings s;
            s.method = method;
            s.width = 160;
            s.height = 90;
            s.light = *lamp;
            // The batched variant (silhouettes=potential draws no batches).
            if (variant == "wedges-bitmask") s.parameters = {{"silhouettes", "centre"}};
            s.depthAwareCulling = false;
            const gpu::FrameStats plainStats = renderer.renderFrame(s);
            const geometry::FloatImage plain = renderer.visibility();
            s.depthAwareCulling = true;
            const gpu::FrameStats tiledStats = renderer.renderFrame(s);
            const geometry::FloatImage tiled = renderer.visibility();
            const auto count = [](const gpu::FrameStats& st, const char* name) {
                for (const auto& k : st.counters)
                    if (k.name == name) return k.value;
                return -1.0;
            };
            std::size_t pixels = 0, differ = 0, far = 0;
            double maxDiff = 0.0;
            for (std::size_t i = 0; i < plain.data.size(); ++i) {
                ASSERT_EQ(std::isfinite(plain.data[i]), std::isfinite(tiled.data[i]));
                if (!std::isfinite(plain.data[i])) continue;
                ++pixels;
                const double d = std::abs(double(plain.data[i]) - tiled.data[i]);
                maxDiff = std::max(maxDiff, d);
                differ += d > 1e-4;
                far += d > 8.0 / 255.0; // BlendEqualsItsCpuModel's order tolerance
            }
            std::printf("  kaos2 camera %d, %s 160x90: %.0f groups hidden", camera,
                        variant.c_str(), potential ? 0.0 : count(tiledStats, "groups_hidden"));
            if (method != "hard")
                std::printf(", %.0f wedges of %.0f", count(tiledStats, "wedges_hidden"),
                            count(tiledStats, "wedges"));
            if (batched)
                std::printf(", batches %.0f -> %.0f", count(plainStats, "batches"),
                            count(tiledStats, "batches"));
            std::printf("; %zu of %zu pixels differ by > 1e-4, max %.2e\n", differ, pixels,
                        maxDiff);
            if (potential) {
                EXPECT_GT(count(tiledStats, "wedges_hidden"), 0.0); // it leaves wedges out here
                EXPECT_EQ(count(plainStats, "wedges_hidden"), 0.0);
            } else {
                EXPECT_GT(count(tiledStats, "groups_hidden"), 0.0); // it leaves groups out here
            }
            EXPECT_EQ(far, 0u);
            if (batched) {
                EXPECT_LT(count(tiledStats, "batches"), count(plainStats, "batches"));
            }
            if (variant == "hard" || variant == "wedges-bitmask") {
                EXPECT_EQ(maxDiff, 0.0); // bitmask: XOR and OR do not depend on the order
            } else if (method != "wedges-blend") {
                EXPECT_LE(maxDiff, 1e-5);
            }
        }
    }
}

// ---- wedges-blend: per-silhouette buffers blended with overlap correction ----------------------

// The GPU's blend against geometry::blend::blendVisibility (R = 4, Overlap::Paper, 8-bit
// storage) at the G-buffer points of the same render. The blend is not associative (the final
// rectangle grows with each blend, spreading its occlusion), and groups reach a pixel in batch
// order on the GPU: a pixel matches when some order of the groups reproduces it within a few
// 8-bit steps (each blend rounds once). A missing wedge, a wrong corner or a broken
// read-modify-write shows as far more.
constexpr double kBlendModelTolerance = 8.0 / 255.0;

TEST_F(AdditiveWedges, BlendEqualsItsCpuModel) {
    for (const char* sceneFile : {"plates-three.json", "diamonds.json", "bars-cross.json"}) {
        SCOPED_TRACE(sceneFile);
        const auto scene = geometry::loadScene(testutil::dataPath(sceneFile));
        const Rendered blend = testutil::render(scene, "wedges-blend", 128);
        const auto light = geometry::blend::lightFrame(scene.light);
        const std::vector<geometry::blend::Group> groups = modelGroups(scene);
        std::size_t pixels = 0, wrong = 0, penumbra = 0;
        double maxErr = 0.0, sumErr = 0.0;
        std::vector<geometry::blend::GroupState> states(groups.size());
        for (std::size_t i = 0; i < blend.visibility.data.size(); ++i) {
            if (!std::isfinite(blend.visibility.data[i])) continue;
            ++pixels;
            const glm::dvec3 p(testutil::pixelPosition(blend.position, i));
            // A point on an occluder is outside that occluder's own volume (the cap offset).
            const glm::dvec3 lifted = p + 1e-5 * (light.c - p);
            for (std::size_t g = 0; g < groups.size(); ++g)
                states[g] = geometry::blend::groupState(scene.light, lifted, groups[g], 4);
            const geometry::blend::BlendSettings paper8{.overlap = geometry::blend::Overlap::Paper,
                                                        .bits = 8};
            double v = geometry::blend::blendVisibility(states, paper8);
            penumbra += v > 0.02 && v < 0.98;
            double err = std::abs(v - blend.visibility.data[i]);
            if (err > kBlendModelTolerance) {
                // Only the groups that occlude part of the light here can change with the order.
                std::vector<geometry::blend::GroupState> active;
                for (const auto& st : states)
                    if (st.visibility() < 1.0) active.push_back(st);
                std::vector<std::size_t> order(active.size());
                std::iota(order.begin(), order.end(), std::size_t(0));
                std::vector<geometry::blend::GroupState> permuted(active.size());
                do {
                    for (std::size_t k = 0; k < order.size(); ++k) permuted[k] = active[order[k]];
                    const double w = geometry::blend::blendVisibility(permuted, paper8);
                    if (std::abs(w - blend.visibility.data[i]) < err) {
                        err = std::abs(w - blend.visibility.data[i]);
                        v = w;
                    }
                } while (std::next_permutation(order.begin(), order.end()));
            }
            maxErr = std::max(maxErr, err);
            sumErr += err;
            if (err > kBlendModelTolerance && wrong++ < 3)
                std::printf("    p (%.4f %.4f %.4f): GPU %.4f model %.4f\n", p.x, p.y, p.z,
                            blend.visibility.data[i], v);
        }
        std::printf("  %s: %zu pixels (%zu penumbra), %zu off by > 8/255, mean %.2e max %.2e\n",
                    sceneFile, pixels, penumbra, wrong, sumErr / double(pixels), maxErr);
        EXPECT_GT(penumbra, 1000u);
        EXPECT_EQ(wrong, 0u); // measured: 0 (max 0.031, plates-three)
    }
}

// Closed form on the floor of axis-aligned plates parallel to the light: their rectangles are
// exact, so the overlap estimate is too; what is left is the 8-bit storage.
class BlendClosedForm : public GlTest,
                        public ::testing::WithParamInterface<std::pair<const char*, int>> {};

TEST_P(BlendClosedForm, MatchesExactVisibility) {
    const auto [file, which] = GetParam();
    const auto scene = geometry::loadScene(testutil::dataPath(file));
    const std::vector<geometry::HorizontalRect> rects =
        which == 2 ? std::vector<geometry::HorizontalRect>{{-0.9f, 0.1f, -0.4f, 0.6f, 1.0f},
                                                           {0.1f, 0.8f, -0.45f, 0.25f, 2.0f}}
                   : std::vector<geometry::HorizontalRect>{{-0.8f, -0.1f, 0.0f, 0.7f, 0.6f},
                                                           {0.0f, 0.6f, -0.15f, 0.45f, 1.2f},
                                                           {-0.25f, 0.25f, -0.7f, -0.2f, 1.8f}};
    const Rendered blend = testutil::render(scene, "wedges-blend", 128);
    const Rendered additive = testutil::render(scene, "wedges-additive", 128);
    std::vector<float> exact(blend.visibility.data.size(), std::nanf(""));
    for (std::size_t i = 0; i < exact.size(); ++i) {
        const glm::vec3 p = testutil::pixelPosition(blend.position, i);
        if (std::isfinite(blend.visibility.data[i]) && std::fabs(p.y) < 1e-3f)
            exact[i] = geometry::visibilityParallelRects(scene.light, rects, p);
    }
    const auto e = geometry::compareVisibility(blend.visibility.data, exact);
    const auto ea = geometry::compareVisibility(additive.visibility.data, exact);
    std::printf("  %s floor vs closed form: blend mean %.4f max %.4f (%.2f%% > 0.05); additive "
                "mean %.4f\n",
                file, e.meanAbs, e.max, e.badPixelPct, ea.meanAbs);
    EXPECT_GT(e.pixels, 5000u);
    EXPECT_LE(e.meanAbs, 0.01); // 8-bit storage: a few 1/255 steps per blend
    EXPECT_LE(e.badPixelPct, 0.5);
    EXPECT_LT(e.meanAbs, ea.meanAbs);
}

INSTANTIATE_TEST_SUITE_P(Plates, BlendClosedForm,
                         ::testing::Values(std::pair{"overlap.json", 2},
                                           std::pair{"plates-three.json", 3}),
                         [](const auto& info) { return info.param.second == 2 ? "two" : "three"; });

// Measured (128², N = 256): blend beats additive wherever occluded regions really overlap
// (plates, diamonds, bars) and is level with it on the nine spheres, where rectangles of round
// regions overlap before the regions do (the CPU model's finding).
class BlendScenes : public GlTest, public ::testing::WithParamInterface<MeasuredCase> {};

TEST_P(BlendScenes, ErrorIsAsMeasured) {
    const auto e = expectAsMeasured("wedges-blend", GetParam());
    EXPECT_LT(e.meanAbs, againstReference(GetParam().scene, "hard").meanAbs);
}

INSTANTIATE_TEST_SUITE_P(
    Scenes, BlendScenes,
    ::testing::Values(MeasuredCase{"parallel-square.json", 0.0004, 0.0085, 0.0},
                      MeasuredCase{"overlap.json", 0.0015, 0.0138, 0.0},
                      MeasuredCase{"plates-three.json", 0.0019, 0.0156, 0.01},
                      MeasuredCase{"bars-cross.json", 0.0012, 0.0160, 0.01},
                      MeasuredCase{"spheres-nine.json", 0.0140, 0.2773, 4.12},
                      MeasuredCase{"torus-box.json", 0.0032, 0.0461, 0.94},
                      MeasuredCase{"diamonds.json", 0.0018, 0.0146, 0.0}),
    sceneTestName);

TEST_F(AdditiveWedges, BlendBeatsAdditiveWhereRegionsOverlap) {
    for (const char* scene : {"overlap.json", "plates-three.json", "bars-cross.json",
                              "diamonds.json", "torus-box.json"}) {
        SCOPED_TRACE(scene);
        EXPECT_LT(againstReference(scene, "wedges-blend").meanAbs,
                  againstReference(scene, "wedges-additive").meanAbs);
    }
}

TEST_F(AdditiveWedges, BlendKeepsAFullyOccludedPartFull) {
    // Where one group alone hides the whole light (its umbra) inside the penumbrae of others,
    // blending must keep V = 0 (the update max(A_f, A_s) + (min - E) never falls below a full
    // part). plates-three's plates have umbrae inside each other's penumbrae.
    const auto scene = geometry::loadScene(testutil::dataPath("plates-three.json"));
    const Rendered blend = testutil::render(scene, "wedges-blend", 128);
    const auto light = geometry::blend::lightFrame(scene.light);
    const std::vector<geometry::blend::Group> groups = modelGroups(scene);
    std::size_t umbra = 0, inOtherPenumbra = 0, notZero = 0;
    for (std::size_t i = 0; i < blend.visibility.data.size(); ++i) {
        if (!std::isfinite(blend.visibility.data[i])) continue;
        const glm::dvec3 p(testutil::pixelPosition(blend.position, i));
        const glm::dvec3 lifted = p + 1e-5 * (light.c - p);
        bool full = false, partial = false;
        for (const auto& g : groups) {
            const double v = geometry::blend::groupState(scene.light, lifted, g, 4).visibility();
            full = full || v == 0.0;
            partial = partial || (v > 0.0 && v < 1.0);
        }
        if (!full) continue;
        ++umbra;
        inOtherPenumbra += partial;
        notZero += blend.visibility.data[i] != 0.0f;
    }
    std::printf("  %zu pixels in one group's umbra, %zu of them in another's penumbra\n", umbra,
                inOtherPenumbra);
    EXPECT_GT(inOtherPenumbra, 100u);
    EXPECT_EQ(notZero, 0u);
}

// ---- wedges-blend's parameters: parts (R), bits, overlap ---------------------------------------

struct BlendVariant {
    int parts = 4;
    int bits = 8;
    geometry::blend::Overlap overlap = geometry::blend::Overlap::Paper;

    bool centroid() const { return overlap == geometry::blend::Overlap::Centroid; }
    std::vector<gpu::ParameterValue> parameters() const {
        return {{"parts", std::to_string(parts)},
                {"bits", std::to_string(bits)},
                {"overlap", centroid() ? "centroid" : "paper"}};
    }
    std::string name() const {
        return "parts" + std::to_string(parts) + "_bits" + std::to_string(bits) +
               (centroid() ? "_centroid" : "_paper");
    }
};

// Every combination, the paper's (4, 8, paper) first.
std::vector<BlendVariant> allBlendVariants() {
    std::vector<BlendVariant> out;
    for (const auto overlap : {geometry::blend::Overlap::Paper, geometry::blend::Overlap::Centroid})
        for (const int bits : {8, 16})
            for (const int parts : {4, 1, 8})
                out.push_back({parts, bits, overlap});
    return out;
}

std::vector<BlendVariant> nonDefaultBlendVariants() {
    std::vector<BlendVariant> out = allBlendVariants();
    out.erase(out.begin());
    return out;
}

std::string variantTestName(const ::testing::TestParamInfo<BlendVariant>& info) {
    return info.param.name();
}

Rendered renderBlend(const geometry::Scene& scene, const BlendVariant& v, int size = 128) {
    const Rendered r = testutil::render(scene, "wedges-blend", size, size, 1, v.parameters());
    expectValidIn(r); // V in [0, 1], no NaN (a GL error throws from the render)
    return r;
}

// A variant's GPU against geometry::blend::blendVisibility with the same settings (R parts, the
// same overlap estimate and packing) at the G-buffer points of the same render, as
// BlendEqualsItsCpuModel does for the paper's: a pixel matches when some order of the groups
// reproduces it within `tolerance`. Also counts pixels in one group's umbra that are not 0.
struct BlendModelCheck {
    std::size_t pixels = 0, penumbra = 0, wrong = 0, umbra = 0, umbraNotZero = 0;
    double maxErr = 0.0, meanErr = 0.0;
};

BlendModelCheck checkBlendAgainstModel(const char* sceneFile, const BlendVariant& variant,
                                       double tolerance) {
    const auto scene = geometry::loadScene(testutil::dataPath(sceneFile));
    const Rendered blend = renderBlend(scene, variant);
    const auto light = geometry::blend::lightFrame(scene.light);
    const std::vector<geometry::blend::Group> groups = modelGroups(scene);
    const geometry::blend::BlendSettings settings{.overlap = variant.overlap, .bits = variant.bits};
    BlendModelCheck c;
    std::vector<geometry::blend::GroupState> states(groups.size());
    for (std::size_t i = 0; i < blend.visibility.data.size(); ++i) {
        const float gpu = blend.visibility.data[i];
        if (!std::isfinite(gpu)) continue;
        ++c.pixels;
        const glm::dvec3 p(testutil::pixelPosition(blend.position, i));
        // The GPU's state: the centre's state C with the cap offset (the point lifted a hair
        // towards the light centre), the wedges' sums at the point itself. The two differ only
        // where C does (a point on the group's own light-facing surface): there the lifted
        // point's state, as above. Elsewhere the lift would move the point off the plane of
        // silhouette edges through it (bars-cross: a bar's top face) and change their coverage
        // by up to 3e-3 — more than 16-bit steps.
        const glm::dvec3 lifted = p + 1e-5 * (light.c - p);
        bool full = false;
        for (std::size_t g = 0; g < groups.size(); ++g) {
            const bool same = (geometry::blend::centreCount(light, lifted, groups[g]) != 0) ==
                              (geometry::blend::centreCount(light, p, groups[g]) != 0);
            states[g] = geometry::blend::groupState(scene.light, same ? p : lifted, groups[g],
                                                    variant.parts);
            full = full || states[g].visibility() == 0.0;
        }
        c.umbra += full;
        c.umbraNotZero += full && gpu != 0.0f;
        double v = geometry::blend::blendVisibility(states, settings);
        c.penumbra += v > 0.02 && v < 0.98;
        double err = std::abs(v - gpu);
        if (err > tolerance) {
            std::vector<geometry::blend::GroupState> active;
            for (const auto& st : states)
                if (st.visibility() < 1.0) active.push_back(st);
            std::vector<std::size_t> order(active.size());
            std::iota(order.begin(), order.end(), std::size_t(0));
            std::vector<geometry::blend::GroupState> permuted(active.size());
            do {
                for (std::size_t k = 0; k < order.size(); ++k)
                    permuted[k] = active[order[k]];
                const double w = geometry::blend::blendVisibility(permuted, settings);
                if (std::abs(w - gpu) < err) {
                    err = std::abs(w - gpu);
                    v = w;
                }
            } while (std::next_permutation(order.begin(), order.end()));
        }
        c.maxErr = std::max(c.maxErr, err);
        c.meanErr += err;
        if (err > tolerance && c.wrong++ < 3)
            std::printf("    p (%.4f %.4f %.4f): GPU %.4f model %.4f\n", p.x, p.y, p.z, gpu, v);
    }
    c.meanErr /= double(std::max<std::size_t>(c.pixels, 1));
    std::printf("  %s %s: %zu pixels (%zu penumbra), %zu off by > %.1e, mean %.2e max %.2e; "
                "%zu in one group's umbra, %zu of them not 0\n",
                sceneFile, variant.name().c_str(), c.pixels, c.penumbra, c.wrong, tolerance,
                c.meanErr, c.maxErr, c.umbra, c.umbraNotZero);
    return c;
}

// Within a few steps of the storage, each blend rounding once: 8 / 255 at 8 bits as for the
// paper's variant, 8 / 65535 at 16 (measured max 3.1e-5, two steps).
constexpr double kBlend16ModelTolerance = 8.0 / 65535.0;

class BlendVariants : public GlTest, public ::testing::WithParamInterface<BlendVariant> {};

TEST_P(BlendVariants, EqualsItsCpuModel) {
    const BlendVariant& v = GetParam();
    for (const char* sceneFile : {"plates-three.json", "diamonds.json", "bars-cross.json"}) {
        SCOPED_TRACE(sceneFile);
        const BlendModelCheck c = checkBlendAgainstModel(
            sceneFile, v, v.bits == 16 ? kBlend16ModelTolerance : kBlendModelTolerance);
        EXPECT_GT(c.penumbra, 1000u);
        EXPECT_EQ(c.wrong, 0u);
        EXPECT_EQ(c.umbraNotZero, 0u); // a full part stays full, in every variant
    }
}

// Closed form on the floor of the stacked axis-aligned plates (BlendClosedForm): the bounds of
// the paper's variant hold for every variant.
TEST_P(BlendVariants, StackedPlatesMatchTheClosedForm) {
    const BlendVariant& v = GetParam();
    for (const auto& [file, which] :
         {std::pair{"overlap.json", 2}, std::pair{"plates-three.json", 3}}) {
        SCOPED_TRACE(file);
        const auto scene = geometry::loadScene(testutil::dataPath(file));
        const std::vector<geometry::HorizontalRect> rects =
            which == 2 ? std::vector<geometry::HorizontalRect>{{-0.9f, 0.1f, -0.4f, 0.6f, 1.0f},
                                                               {0.1f, 0.8f, -0.45f, 0.25f, 2.0f}}
                       : std::vector<geometry::HorizontalRect>{{-0.8f, -0.1f, 0.0f, 0.7f, 0.6f},
                                                               {0.0f, 0.6f, -0.15f, 0.45f, 1.2f},
                                                               {-0.25f, 0.25f, -0.7f, -0.2f, 1.8f}};
        const Rendered blend = renderBlend(scene, v);
        const Rendered additive = testutil::render(scene, "wedges-additive", 128);
        std::vector<float> exact(blend.visibility.data.size(), std::nanf(""));
        for (std::size_t i = 0; i < exact.size(); ++i) {
            const glm::vec3 p = testutil::pixelPosition(blend.position, i);
            if (std::isfinite(blend.visibility.data[i]) && std::fabs(p.y) < 1e-3f)
                exact[i] = geometry::visibilityParallelRects(scene.light, rects, p);
        }
        const auto e = geometry::compareVisibility(blend.visibility.data, exact);
        const auto ea = geometry::compareVisibility(additive.visibility.data, exact);
        std::printf("  %s %s floor vs closed form: mean %.4f max %.4f (%.2f%% > 0.05); additive "
                    "mean %.4f\n",
                    file, v.name().c_str(), e.meanAbs, e.max, e.badPixelPct, ea.meanAbs);
        EXPECT_GT(e.pixels, 5000u);
        EXPECT_LE(e.meanAbs, 0.01);
        EXPECT_LE(e.badPixelPct, 0.5);
        EXPECT_LT(e.meanAbs, ea.meanAbs);
    }
}

INSTANTIATE_TEST_SUITE_P(Parameters, BlendVariants, ::testing::ValuesIn(nonDefaultBlendVariants()),
                         variantTestName);

// Every variant against the reference on the overlap scenes (128², N = 256, mean |V - ref|),
// measured (columns in allBlendVariants' order: paper 8 bits, paper 16, centroid 8, centroid
// 16, each R = 4, 1, 8):
//                 paper/8: 4 1 8          paper/16              centroid/8            centroid/16
// plates-three  .00195 .00227 .00189  .00194 .00223 .00189  .00186 .00198 .00187  .00186 .00196
// .00186 bars-cross    .00121 .00155 .00120  .00121 .00156 .00120  .00125 .00172 .00119  .00125
// .00172 .00118 diamonds      .00175 .00241 .00174  .00176 .00240 .00174  .00177 .00202 .00172
// .00177 .00202 .00172 spheres-nine  .01399 .01423 .01395  .01398 .01419 .01395  .01391 .01404
// .01391  .01391 .01400 .01391 torus-box     .00315 .00358 .00307  .00315 .00356 .00307  .00304
// .00324 .00304  .00304 .00323 .00304 What holds on every scene (the CPU model's findings): one
// part is worst (R = 1 over R = 4 by 0.00009-0.00064), eight parts are no worse than four (R = 8 -
// R = 4 within -0.00008..+0.00001), 16 bits are level with 8 (within 0.00004), and the centroid
// estimate never hurts R = 8
// (-0.00004..-0.00001). The centroid estimate helps R = 1 (0.00019-0.00039) except on
// bars-cross (+0.00017: the crossing bars' occluded regions are not the linear densities of
// their rectangles); at R = 4 it is mixed (-0.00011..+0.00004). The differences are a few
// percent of the error: what dominates is the centre-silhouette approximation and, on the
// spheres, rectangles of round regions.
struct VariantTable {
    const char* scene;
    std::array<double, 12> mean; // allBlendVariants' order
};
constexpr VariantTable kBlendVariantsMeasured[] = {
    {"plates-three.json",
     {.00195, .00227, .00189, .00194, .00223, .00189, .00186, .00198, .00187, .00186, .00196,
      .00186}},
    {"bars-cross.json",
     {.00121, .00155, .00120, .00121, .00156, .00120, .00125, .00172, .00119, .00125, .00172,
      .00118}},
    {"diamonds.json",
     {.00175, .00241, .00174, .00176, .00240, .00174, .00177, .00202, .00172, .00177, .00202,
      .00172}},
    {"spheres-nine.json",
     {.01399, .01423, .01395, .01398, .01419, .01395, .01391, .01404, .01391, .01391, .01400,
      .01391}},
    {"torus-box.json",
     {.00315, .00358, .00307, .00315, .00356, .00307, .00304, .00324, .00304, .00304, .00323,
      .00304}},
};
// Each value within this of its measured one (sampling is seeded, rasterisation deterministic:
// what moves it is a change of arithmetic).
constexpr double kVariantValueMargin = 2e-4;
// An order "a below b" holds when a <= b - kVariantOrderMargin; "level" within kVariantLevelMargin.
constexpr double kVariantOrderMargin = 5e-5;
constexpr double kVariantLevelMargin = 1e-4;

TEST_F(AdditiveWedges, BlendVariantsAgainstTheReferenceAreAsMeasured) {
    const std::vector<BlendVariant> variants = allBlendVariants();
    ASSERT_EQ(variants.size(), 12u);
    // Index in allBlendVariants' order.
    auto at = [](bool centroid, int bits, int parts) {
        return (centroid ? 6 : 0) + (bits == 16 ? 3 : 0) + (parts == 4 ? 0 : parts == 1 ? 1 : 2);
    };
    std::printf("  mean |V - reference| at 128², N = 256:\n  %-18s", "scene");
    for (const auto& v : variants)
        std::printf(" %s", v.name().c_str());
    std::printf("\n");
    for (const VariantTable& row : kBlendVariantsMeasured) {
        SCOPED_TRACE(row.scene);
        const auto scene = geometry::loadScene(testutil::dataPath(row.scene));
        const Rendered ref = testutil::render(scene, "reference", 128, 256);
        std::array<double, 12> mean{};
        std::printf("  %-18s", row.scene);
        for (std::size_t i = 0; i < variants.size(); ++i) {
            const Rendered r = renderBlend(scene, variants[i]);
            mean[i] = geometry::compareVisibility(r.visibility.data, ref.visibility.data).meanAbs;
            std::printf(" %.5f", mean[i]);
            EXPECT_NEAR(mean[i], row.mean[i], kVariantValueMargin) << variants[i].name();
        }
        std::printf("\n");
        const bool barsCross = std::string(row.scene) == "bars-cross.json";
        for (const bool centroid : {false, true})
            for (const int bits : {8, 16}) {
                SCOPED_TRACE(std::string(centroid ? "centroid " : "paper ") + std::to_string(bits) +
                             " bits");
                const double r4 = mean[at(centroid, bits, 4)], r1 = mean[at(centroid, bits, 1)],
                             r8 = mean[at(centroid, bits, 8)];
                EXPECT_LE(r4, r1 - kVariantOrderMargin);
                EXPECT_LE(r8, r4 + kVariantOrderMargin);
                for (const int parts : {1, 4, 8})
                    EXPECT_NEAR(mean[at(centroid, 16, parts)], mean[at(centroid, 8, parts)],
                                kVariantLevelMargin);
            }
        for (const int bits : {8, 16}) {
            SCOPED_TRACE(std::to_string(bits) + " bits");
            EXPECT_LE(mean[at(true, bits, 8)], mean[at(false, bits, 8)] + kVariantOrderMargin);
            if (barsCross)
                EXPECT_GE(mean[at(true, bits, 1)], mean[at(false, bits, 1)] + kVariantOrderMargin);
            else
                EXPECT_LE(mean[at(true, bits, 1)], mean[at(false, bits, 1)] - kVariantOrderMargin);
        }
    }
}

} // namespace
