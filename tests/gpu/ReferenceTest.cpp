// The two references — N stratified hard-shadow passes on the GPU, and N Embree rays per pixel —
// against each other and against the exact visibility of parallel rectangles.
#include "GlTestEnv.h"
#include "RenderTestUtil.h"

#include <geometry/Analytic.h>
#include <geometry/ErrorStats.h>

#include <cctype>
#include <cmath>

namespace {

using testutil::Rendered;

// Exact V at every floor pixel (NaN elsewhere) for scenes of horizontal rectangles.
std::vector<float> closedFormFloor(const geometry::Scene& scene, const Rendered& r,
                                   std::span<const geometry::HorizontalRect> rects) {
    std::vector<float> v(r.visibility.data.size(), std::nanf(""));
    for (std::size_t i = 0; i < v.size(); ++i) {
        const glm::vec3 p = testutil::pixelPosition(r.position, i);
        if (std::isfinite(r.visibility.data[i]) && std::fabs(p.y) < 1e-3f)
            v[i] = geometry::visibilityParallelRects(scene.light, rects, p);
    }
    return v;
}

geometry::ErrorStats check(const std::string& name, const Rendered& r,
                           const std::vector<float>& expected) {
    const auto e = geometry::compareVisibility(r.visibility.data, expected);
    if (e.meanAbs >= 0.01) testutil::writeComparisonImages(name, r.visibility, expected);
    std::printf("%s: %zu px, mean %.5f rmse %.5f p99 %.5f max %.5f\n", name.c_str(), e.pixels,
                e.meanAbs, e.rmse, e.p99, e.max);
    return e;
}

class Reference : public GlTest {};

// N = 256 at 128^2 (the bench uses 1024). The tolerance 0.01 on the mean is the sampling error
// budget of 256 stratified samples: the error lives only in the penumbra and is at most ~1/16
// per penumbra pixel there; the max is not bounded tighter than one stratum row (1/16 + slack).
constexpr int kSamples = 256;
constexpr int kSize = 128;

struct SceneCase {
    const char* file;
    std::vector<geometry::HorizontalRect> rects;
};

void PrintTo(const SceneCase& c, std::ostream* os) { *os << c.file; }

class ReferenceClosedForm : public Reference, public ::testing::WithParamInterface<SceneCase> {};

TEST_P(ReferenceClosedForm, GpuAndEmbreeMatchExactVisibility) {
    const auto& param = GetParam();
    const auto scene = geometry::loadScene(testutil::dataPath(param.file));
    const Rendered gl = testutil::render(scene, "reference", kSize, kSamples);
    const Rendered rt = testutil::render(scene, "raytrace", kSize, kSamples);
    const std::string stem = std::filesystem::path(param.file).stem().string();

    const auto exact = closedFormFloor(scene, gl, param.rects);
    const auto eGl = check(stem + "-reference-vs-exact", gl, exact);
    const auto eRt = check(stem + "-raytrace-vs-exact", rt, exact);
    EXPECT_GT(eGl.pixels, 5000u);
    EXPECT_LT(eGl.meanAbs, 0.01);
    EXPECT_LT(eRt.meanAbs, 0.01);
    EXPECT_LT(eGl.max, 0.1);
    EXPECT_LT(eRt.max, 0.1);

    // The two references on every surface pixel (floor and occluders).
    const auto both = check(stem + "-reference-vs-raytrace", gl, rt.visibility.data);
    EXPECT_EQ(both.mismatchedCoverage, 0u);
    EXPECT_LT(both.meanAbs, 0.01);

    // There must be a real penumbra for this to mean anything.
    int penumbra = 0;
    for (float v : exact) penumbra += std::isfinite(v) && v > 0.05f && v < 0.95f;
    EXPECT_GT(penumbra, 500);
}

INSTANTIATE_TEST_SUITE_P(
    Scenes, ReferenceClosedForm,
    ::testing::Values(SceneCase{"parallel-square.json", {{-0.5f, 0.5f, -0.5f, 0.5f, 1.0f}}},
                      SceneCase{"overlap.json",
                                {{-0.9f, 0.1f, -0.4f, 0.6f, 1.0f},
                                 {0.1f, 0.8f, -0.45f, 0.25f, 2.0f}}},
                      SceneCase{"plates-three.json",
                                {{-0.8f, -0.1f, 0.0f, 0.7f, 0.6f},
                                 {0.0f, 0.6f, -0.15f, 0.45f, 1.2f},
                                 {-0.25f, 0.25f, -0.7f, -0.2f, 1.8f}}}),
    [](const auto& info) { // "plates-three.json" -> "PlatesThree"
        std::string name;
        bool upper = true;
        for (char c : std::filesystem::path(info.param.file).stem().string()) {
            if (c == '-') {
                upper = true;
            } else {
                name += upper ? char(std::toupper(static_cast<unsigned char>(c))) : c;
                upper = false;
            }
        }
        return name;
    });

// On a real level the references agree too (no closed form there): open and non-manifold
// geometry, surfaces whose plane cuts the light, contact shadows.
TEST_F(Reference, GpuAndEmbreeAgreeOnOpenArenaLevel) {
    const auto scene = geometry::loadScene(testutil::sharedPath("levels/oa_dm4.glb"));
    const Rendered gl = testutil::render(scene, "reference", 96, kSamples);
    const Rendered rt = testutil::render(scene, "raytrace", 96, kSamples);
    const auto e = check("oa_dm4-reference-vs-raytrace", gl, rt.visibility.data);
    EXPECT_GT(e.pixels, 8000u);
    EXPECT_EQ(e.mismatchedCoverage, 0u);
    // Same budget as the closed-form scenes: sampling noise lives in the penumbrae only.
    EXPECT_LT(e.meanAbs, 0.01);
}

} // namespace
