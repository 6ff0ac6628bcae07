#include <geometry/reference/ErrorImage.h>
#include <geometry/reference/ErrorStats.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <span>
#include <stdexcept>
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

// ---- flicker (DESIGN.md §5) -------------------------------------------------------------------

namespace {
std::vector<std::span<const float>> spans(const std::vector<std::vector<float>>& frames) {
    return {frames.begin(), frames.end()};
}
} // namespace

TEST(FlickerTest, ConstantOffsetFromTruthIsNotFlicker) {
    // The method is 0.1 too dark everywhere but moves exactly as the truth: flicker 0.
    const std::vector<std::vector<float>> truth{{0.2f, 0.5f}, {0.3f, 0.6f}, {0.1f, 0.9f}};
    std::vector<std::vector<float>> method = truth;
    for (auto& f : method)
        for (float& x : f) x -= 0.1f;
    EXPECT_NEAR(geometry::flicker(spans(method), spans(truth)), 0.0, 1e-7);
}

TEST(FlickerTest, KnownAnswer) {
    // Truth still; the method toggles one of two pixels by 0.4 every frame:
    // pair means 0.2, 0.2 → flicker 0.2. The third (NaN) pixel never counts.
    const float nan = std::numeric_limits<float>::quiet_NaN();
    const std::vector<std::vector<float>> truth{{0.5f, 0.5f, nan}, {0.5f, 0.5f, nan},
                                                {0.5f, 0.5f, nan}};
    const std::vector<std::vector<float>> method{{0.5f, 0.1f, 0.0f}, {0.5f, 0.5f, 1.0f},
                                                 {0.5f, 0.1f, 0.0f}};
    EXPECT_NEAR(geometry::flicker(spans(method), spans(truth)), 0.2, 1e-6);
    // Truth moving and the method frozen is flicker too (a shadow that does not follow).
    EXPECT_NEAR(geometry::flicker(spans(truth), spans(method)), 0.2, 1e-6);
}

TEST(FlickerTest, PerPairMeansAreAveragedEqually) {
    // Pair 1: one pixel of two differs by 1 → 0.5; pair 2: none → 0. Mean 0.25.
    const std::vector<std::vector<float>> truth{{0, 0}, {0, 0}, {0, 0}};
    const std::vector<std::vector<float>> method{{0, 0}, {1, 0}, {1, 0}};
    EXPECT_NEAR(geometry::flicker(spans(method), spans(truth)), 0.25, 1e-9);
}

TEST(FlickerTest, RejectsMismatchedSequences) {
    const std::vector<std::vector<float>> two{{0.f}, {1.f}}, three{{0.f}, {1.f}, {0.f}};
    const std::vector<std::vector<float>> one{{0.f}}, ragged{{0.f}, {1.f, 2.f}};
    EXPECT_THROW(geometry::flicker(spans(two), spans(three)), std::invalid_argument);
    EXPECT_THROW(geometry::flicker(spans(one), spans(one)), std::invalid_argument);
    EXPECT_THROW(geometry::flicker(spans(ragged), spans(ragged)), std::invalid_argument);
}

// ---- error heat map ---------------------------------------------------------------------------

TEST(ErrorHeatMapTest, ColoursFollowTheError) {
    const float nan = std::numeric_limits<float>::quiet_NaN();
    // 4 pixels: exact, error = scale/2, error = 2 × scale (saturates), surface only in one image.
    const std::vector<float> ref{0.5f, 0.5f, 0.5f, nan};
    const std::vector<float> v{0.5f, 0.625f, 1.0f, 0.5f}; // exact in binary
    const geometry::RgbImage img = geometry::errorHeatMap(v, ref, 4, 1, 0.25f);
    ASSERT_EQ(img.width, 4);
    ASSERT_EQ(img.height, 1 + geometry::errorLegendHeight(4));
    auto px = [&](int x, int y) {
        const std::uint8_t* p = &img.rgb[(static_cast<std::size_t>(y) * img.width + x) * 3];
        return std::array<int, 3>{p[0], p[1], p[2]};
    };
    std::uint8_t c[3];
    geometry::heatColour(0.0f, c);
    EXPECT_EQ(px(0, 0), (std::array<int, 3>{c[0], c[1], c[2]}));
    EXPECT_EQ(px(0, 0), (std::array<int, 3>{0, 0, 0}));
    geometry::heatColour(0.5f, c);
    EXPECT_EQ(px(1, 0), (std::array<int, 3>{c[0], c[1], c[2]}));
    geometry::heatColour(1.0f, c);
    EXPECT_EQ(px(2, 0), (std::array<int, 3>{c[0], c[1], c[2]}));
    EXPECT_EQ(px(3, 0), (std::array<int, 3>{0, 255, 0}));
}

TEST(ErrorHeatMapTest, RampBrightensMonotonically) {
    double last = -1.0;
    for (int i = 0; i <= 100; ++i) {
        std::uint8_t c[3];
        geometry::heatColour(static_cast<float>(i) / 100.0f, c);
        const double luma = 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2];
        EXPECT_GE(luma, last) << "t = " << i / 100.0;
        last = luma;
    }
}

TEST(ErrorHeatMapTest, LegendHasTheBarAndLabels) {
    const int w = 200, h = 10;
    const std::vector<float> zeros(static_cast<std::size_t>(w) * h, 0.0f);
    const geometry::RgbImage img = geometry::errorHeatMap(zeros, zeros, w, h);
    // The bar runs from the ramp's first colour on the left to its last on the right, and the
    // label row has ink (black) pixels.
    const int barY = h + 4 + 3; // font scale 1 at width 200 (< 256)
    auto at = [&](int x, int y) { return &img.rgb[(static_cast<std::size_t>(y) * w + x) * 3]; };
    std::uint8_t first[3], last[3];
    geometry::heatColour(0.0f, first);
    geometry::heatColour(1.0f, last);
    EXPECT_TRUE(std::equal(first, first + 3, at(2, barY)));
    EXPECT_TRUE(std::equal(last, last + 3, at(w - 3, barY)));
    std::size_t ink = 0;
    for (int y = barY + 5; y < img.height; ++y)
        for (int x = 0; x < w; ++x) ink += at(x, y)[0] == 0 && at(x, y)[1] == 0 && at(x, y)[2] == 0;
    EXPECT_GT(ink, 30u); // six labels of 1–4 glyphs
    EXPECT_THROW(geometry::errorHeatMap(zeros, zeros, w, h + 1), std::invalid_argument);
    EXPECT_THROW(geometry::errorHeatMap(zeros, zeros, w, h, 0.0f), std::invalid_argument);
}
