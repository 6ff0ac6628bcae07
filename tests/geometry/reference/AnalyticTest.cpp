#include <geometry/reference/Analytic.h>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <vector>

namespace {

using geometry::HorizontalRect;

// Unit-area light at height 4: [-0.5, 0.5]^2.
geometry::RectLight unitLight() {
    geometry::RectLight light;
    light.center = {0.0f, 4.0f, 0.0f};
    light.u = {0.5f, 0.0f, 0.0f};
    light.v = {0.0f, 0.0f, 0.5f};
    return light;
}

// Midpoint-rule estimate over an n x n grid of light points, testing every segment against every
// occluder directly (no projection): an independent route to the same integral.
double bruteForce(const geometry::RectLight& light, const std::vector<HorizontalRect>& occ,
                  const glm::vec3& p, int n) {
    int visible = 0;
    for (int j = 0; j < n; ++j) {
        for (int i = 0; i < n; ++i) {
            const float s = -1.0f + (2.0f * static_cast<float>(i) + 1.0f) / static_cast<float>(n);
            const float t = -1.0f + (2.0f * static_cast<float>(j) + 1.0f) / static_cast<float>(n);
            const glm::dvec3 y = glm::dvec3(light.point(s, t));
            bool blocked = false;
            for (const HorizontalRect& o : occ) {
                if (!(o.y > p.y && o.y < y.y)) continue;
                const double a = (o.y - p.y) / (y.y - p.y);
                const double x = p.x + a * (y.x - p.x);
                const double z = p.z + a * (y.z - p.z);
                if (x >= o.x0 && x <= o.x1 && z >= o.z0 && z <= o.z1) {
                    blocked = true;
                    break;
                }
            }
            visible += blocked ? 0 : 1;
        }
    }
    return static_cast<double>(visible) / (static_cast<double>(n) * n);
}

// Small deterministic generator for the randomised comparison.
struct Lcg {
    std::uint64_t state;
    float next(float lo, float hi) {
        state = state * 6364136223846793005ull + 1442695040888963407ull;
        return lo + (hi - lo) * static_cast<float>(state >> 40) / 16777216.0f;
    }
};

} // namespace

TEST(AnalyticTest, FullyCoveredIsZero) {
    // Occluder at half height, 2x wider than the light: its projection from P (scale 2) covers
    // [-2, 2]^2, more than the whole light.
    const std::vector<HorizontalRect> occ{{-1.0f, 1.0f, -1.0f, 1.0f, 2.0f}};
    EXPECT_FLOAT_EQ(geometry::visibilityParallelRects(unitLight(), occ, {0, 0, 0}), 0.0f);
}

TEST(AnalyticTest, FarToTheSideIsOne) {
    const std::vector<HorizontalRect> occ{{-1.0f, 1.0f, -1.0f, 1.0f, 2.0f}};
    EXPECT_FLOAT_EQ(geometry::visibilityParallelRects(unitLight(), occ, {20, 0, 0}), 1.0f);
    EXPECT_FLOAT_EQ(geometry::visibilityParallelRects(unitLight(), {}, {0, 0, 0}), 1.0f);
}

TEST(AnalyticTest, HalfCovered) {
    // Occluder x in [0, 5] at height 2 projects from the origin to x in [0, 10]: exactly the
    // half x > 0 of the light.
    const std::vector<HorizontalRect> occ{{0.0f, 5.0f, -5.0f, 5.0f, 2.0f}};
    EXPECT_FLOAT_EQ(geometry::visibilityParallelRects(unitLight(), occ, {0, 0, 0}), 0.5f);
}

TEST(AnalyticTest, QuarterCoveredByProjectedSquare) {
    // P at height 0, occluder [0, 0.125]^2 at height 2 projects to [0, 0.25]^2 (scale 2):
    // area 1/16 of the unit light.
    const std::vector<HorizontalRect> occ{{0.0f, 0.125f, 0.0f, 0.125f, 2.0f}};
    EXPECT_FLOAT_EQ(geometry::visibilityParallelRects(unitLight(), occ, {0, 0, 0}), 15.0f / 16.0f);
}

TEST(AnalyticTest, OverlapIsUnionNotSum) {
    // Two occluders hiding the same half of the light (DESIGN.md §4: additive wedges would give
    // 0; the truth is 0.5), at different heights.
    const std::vector<HorizontalRect> occ{{0.0f, 5.0f, -5.0f, 5.0f, 2.0f},
                                          {0.0f, 5.0f, -5.0f, 5.0f, 3.0f}};
    EXPECT_FLOAT_EQ(geometry::visibilityParallelRects(unitLight(), occ, {0, 0, 0}), 0.5f);
    // Partial overlap: x > 0 (half) and z > 0 (half) overlap in a quarter: union 3/4.
    const std::vector<HorizontalRect> cross{{0.0f, 5.0f, -5.0f, 5.0f, 2.0f},
                                            {-5.0f, 5.0f, 0.0f, 5.0f, 3.0f}};
    EXPECT_FLOAT_EQ(geometry::visibilityParallelRects(unitLight(), cross, {0, 0, 0}), 0.25f);
}

TEST(AnalyticTest, OnlyOccludersBetweenPointAndLightCount) {
    const std::vector<HorizontalRect> below{{-9.0f, 9.0f, -9.0f, 9.0f, -1.0f}};
    const std::vector<HorizontalRect> atPoint{{-9.0f, 9.0f, -9.0f, 9.0f, 0.0f}};
    const std::vector<HorizontalRect> atLight{{-9.0f, 9.0f, -9.0f, 9.0f, 4.0f}};
    const std::vector<HorizontalRect> above{{-9.0f, 9.0f, -9.0f, 9.0f, 5.0f}};
    for (const auto* occ : {&below, &atPoint, &atLight, &above}) {
        EXPECT_FLOAT_EQ(geometry::visibilityParallelRects(unitLight(), *occ, {0, 0, 0}), 1.0f);
    }
}

TEST(AnalyticTest, RejectsNonAxisAlignedLight) {
    geometry::RectLight tilted = unitLight();
    tilted.u = {0.5f, 0.1f, 0.0f};
    EXPECT_THROW(geometry::visibilityParallelRects(tilted, {}, {0, 0, 0}), std::invalid_argument);
    geometry::RectLight rotated = unitLight();
    rotated.u = {0.0f, 0.0f, 0.5f};
    rotated.v = {0.5f, 0.0f, 0.0f};
    EXPECT_THROW(geometry::visibilityParallelRects(rotated, {}, {0, 0, 0}), std::invalid_argument);
}

TEST(AnalyticTest, NonFinitePointIsNaN) {
    const float nan = std::numeric_limits<float>::quiet_NaN();
    EXPECT_TRUE(std::isnan(geometry::visibilityParallelRects(unitLight(), {}, {nan, 0, 0})));
}

TEST(AnalyticTest, MatchesBruteForce) {
    // Random points and 1-4 random occluders per case against a 400 x 400 midpoint grid. The grid
    // misclassifies only the light cells an edge of the union crosses: at most ~4 * 400 of
    // 160000 cells per occluder in the worst case, each wrong by a fraction of a cell, and on
    // average half-cancelling. 0.005 is well above what that leaves for up to 4 occluders.
    Lcg rng{12345};
    geometry::RectLight light;
    light.center = {0.3f, 5.0f, -0.2f};
    light.u = {0.8f, 0.0f, 0.0f};
    light.v = {0.0f, 0.0f, 0.4f};
    double worst = 0.0;
    for (int c = 0; c < 60; ++c) {
        std::vector<HorizontalRect> occ;
        const int count = 1 + c % 4;
        for (int k = 0; k < count; ++k) {
            const float x = rng.next(-1.5f, 1.5f), z = rng.next(-1.5f, 1.5f);
            const float w = rng.next(0.1f, 1.2f), d = rng.next(0.1f, 1.2f);
            occ.push_back({x, x + w, z, z + d, rng.next(1.0f, 4.5f)});
        }
        const glm::vec3 p{rng.next(-3.0f, 3.0f), rng.next(-0.5f, 0.5f), rng.next(-3.0f, 3.0f)};
        const double exact = geometry::visibilityParallelRects(light, occ, p);
        const double brute = bruteForce(light, occ, p, 400);
        EXPECT_NEAR(exact, brute, 0.005) << "case " << c;
        worst = std::max(worst, std::abs(exact - brute));
    }
    std::printf("[analytic vs 400^2 grid] worst |diff| over 60 cases: %.5f\n", worst);
}
