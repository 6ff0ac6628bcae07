#include <geometry/ErrorStats.h>

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

namespace {
constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
} // namespace

TEST(ErrorStatsTest, KnownArrays) {
    // Errors 0, 0.1, 0.02, 0.3 (exact in the arithmetic below up to float rounding of inputs).
    const std::vector<float> v{0.5f, 0.6f, 0.52f, 1.0f};
    const std::vector<float> ref{0.5f, 0.5f, 0.5f, 0.7f};
    const geometry::ErrorStats s = geometry::compareVisibility(v, ref);
    EXPECT_EQ(s.pixels, 4u);
    EXPECT_EQ(s.mismatchedCoverage, 0u);
    const double e1 = 0.6f - 0.5f, e2 = 0.52f - 0.5f, e3 = 1.0f - 0.7f;
    EXPECT_DOUBLE_EQ(s.meanAbs, (e1 + e2 + e3) / 4.0);
    EXPECT_DOUBLE_EQ(s.rmse, std::sqrt((e1 * e1 + e2 * e2 + e3 * e3) / 4.0));
    EXPECT_DOUBLE_EQ(s.max, e3);
    EXPECT_DOUBLE_EQ(s.p99, e3); // nearest rank ceil(0.99 * 4) = 4th smallest
    EXPECT_DOUBLE_EQ(s.badPixelPct, 50.0); // 0.1 and 0.3 exceed 0.05
}

TEST(ErrorStatsTest, PercentileOfHundred) {
    // Errors 0.01 * k for k = 1..100 (shuffled): nearest-rank p99 is the 99th smallest.
    std::vector<float> v, ref;
    for (int k = 100; k >= 1; --k) {
        v.push_back(static_cast<float>(k) / 128.0f); // dyadic: the errors are exact
        ref.push_back(0.0f);
    }
    const geometry::ErrorStats s = geometry::compareVisibility(v, ref);
    EXPECT_EQ(s.pixels, 100u);
    EXPECT_DOUBLE_EQ(s.p99, 99.0 / 128.0);
    EXPECT_DOUBLE_EQ(s.max, 100.0 / 128.0);
    EXPECT_DOUBLE_EQ(s.meanAbs, 50.5 / 128.0);
    // k / 128 > 0.05 for k >= 7: 94 of 100.
    EXPECT_DOUBLE_EQ(s.badPixelPct, 94.0);
}

TEST(ErrorStatsTest, BadPixelThreshold) {
    // Dyadic values either side of 0.05, exact in float: 1/16 = 0.0625 is bad, 3/64 = 0.047 not.
    const std::vector<float> v{0.3125f, 0.296875f};
    const std::vector<float> ref{0.25f, 0.25f};
    const geometry::ErrorStats s = geometry::compareVisibility(v, ref);
    EXPECT_DOUBLE_EQ(s.badPixelPct, 50.0);
}

TEST(ErrorStatsTest, NaNMeansNoSurface) {
    const std::vector<float> v{kNaN, 0.5f, kNaN, 1.0f, 0.25f};
    const std::vector<float> ref{kNaN, kNaN, 0.5f, 1.0f, 0.5f};
    const geometry::ErrorStats s = geometry::compareVisibility(v, ref);
    EXPECT_EQ(s.pixels, 2u);             // indices 3 and 4
    EXPECT_EQ(s.mismatchedCoverage, 2u); // indices 1 and 2
    EXPECT_DOUBLE_EQ(s.meanAbs, 0.125);
    EXPECT_DOUBLE_EQ(s.max, 0.25);
    EXPECT_DOUBLE_EQ(s.rmse, std::sqrt(0.25 * 0.25 / 2.0));
    EXPECT_DOUBLE_EQ(s.p99, 0.25);
    EXPECT_DOUBLE_EQ(s.badPixelPct, 50.0);
}

TEST(ErrorStatsTest, AllEmptyGivesZeros) {
    const std::vector<float> v{kNaN, kNaN};
    const geometry::ErrorStats s = geometry::compareVisibility(v, v);
    EXPECT_EQ(s.pixels, 0u);
    EXPECT_EQ(s.mismatchedCoverage, 0u);
    EXPECT_EQ(s.meanAbs, 0.0);
    EXPECT_EQ(s.p99, 0.0);
    EXPECT_EQ(s.max, 0.0);
    const geometry::ErrorStats none = geometry::compareVisibility({}, {});
    EXPECT_EQ(none.pixels, 0u);
}

TEST(ErrorStatsTest, IdenticalImagesHaveNoError) {
    const std::vector<float> v{0.0f, 0.3f, 1.0f, 0.7f};
    const geometry::ErrorStats s = geometry::compareVisibility(v, v);
    EXPECT_EQ(s.pixels, 4u);
    EXPECT_EQ(s.meanAbs, 0.0);
    EXPECT_EQ(s.rmse, 0.0);
    EXPECT_EQ(s.max, 0.0);
    EXPECT_EQ(s.badPixelPct, 0.0);
}

TEST(ErrorStatsTest, SizeMismatchThrows) {
    const std::vector<float> a{0.0f, 1.0f};
    const std::vector<float> b{0.0f};
    EXPECT_THROW(geometry::compareVisibility(a, b), std::invalid_argument);
}
