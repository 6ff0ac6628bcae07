#include <geometry/core/Sampling.h>

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <vector>

namespace {

// The grid the header documents: nx the largest divisor of n not above sqrt(n).
void expectedGrid(int n, int& nx, int& ny) {
    nx = 1;
    for (int d = 1; d * d <= n; ++d) {
        if (n % d == 0) nx = d;
    }
    ny = n / nx;
}

// Every cell of the nx * ny grid over [-1,1]^2 holds exactly one point.
void expectStratified(const std::vector<glm::vec2>& pts, int n) {
    int nx = 0, ny = 0;
    expectedGrid(n, nx, ny);
    std::vector<int> count(static_cast<std::size_t>(n), 0);
    for (const glm::vec2& p : pts) {
        const int i = std::min(nx - 1, static_cast<int>((p.x + 1.0f) * 0.5f * nx));
        const int j = std::min(ny - 1, static_cast<int>((p.y + 1.0f) * 0.5f * ny));
        ++count[static_cast<std::size_t>(j * nx + i)];
    }
    for (int c = 0; c < n; ++c) EXPECT_EQ(count[static_cast<std::size_t>(c)], 1) << "cell " << c;
}

} // namespace

TEST(SamplingTest, CountsAndRange) {
    for (int n : {1, 2, 3, 4, 12, 16, 64, 100, 256, 1000, 1024}) {
        const auto pts = geometry::stratifiedSquare(n, 7);
        ASSERT_EQ(pts.size(), static_cast<std::size_t>(n));
        for (const glm::vec2& p : pts) {
            EXPECT_GE(p.x, -1.0f);
            EXPECT_LE(p.x, 1.0f);
            EXPECT_GE(p.y, -1.0f);
            EXPECT_LE(p.y, 1.0f);
        }
    }
}

TEST(SamplingTest, OnePointPerCell) {
    for (int n : {4, 6, 12, 16, 18, 64, 100, 256, 1024}) {
        SCOPED_TRACE(n);
        expectStratified(geometry::stratifiedSquare(n, 3), n);
    }
}

TEST(SamplingTest, Deterministic) {
    const auto a = geometry::stratifiedSquare(256, 42);
    const auto b = geometry::stratifiedSquare(256, 42);
    ASSERT_EQ(a.size(), b.size());
    for (std::size_t i = 0; i < a.size(); ++i) {
        EXPECT_EQ(a[i].x, b[i].x);
        EXPECT_EQ(a[i].y, b[i].y);
    }
    // A different seed moves the jitter (but not the strata).
    const auto c = geometry::stratifiedSquare(256, 43);
    int same = 0;
    for (std::size_t i = 0; i < a.size(); ++i) same += (a[i] == c[i]);
    EXPECT_LT(same, 4);
}

TEST(SamplingTest, SinglePointIsJitteredOverTheWholeSquare) {
    // n = 1 is one cell covering the square: the point is uniform in it, so different seeds
    // must spread over it rather than sit at the centre.
    float minX = 1.0f, maxX = -1.0f;
    for (std::uint32_t seed = 0; seed < 64; ++seed) {
        const auto pts = geometry::stratifiedSquare(1, seed);
        ASSERT_EQ(pts.size(), 1u);
        minX = std::min(minX, pts[0].x);
        maxX = std::max(maxX, pts[0].x);
    }
    EXPECT_LT(minX, -0.5f);
    EXPECT_GT(maxX, 0.5f);
}

TEST(SamplingTest, PrimeCountIsOneRow) {
    // A prime has no divisor but 1 below its root: a 1 x n grid of strips, one point per strip.
    const int n = 13;
    const auto pts = geometry::stratifiedSquare(n, 5);
    ASSERT_EQ(pts.size(), 13u);
    expectStratified(pts, n);
}

TEST(SamplingTest, MeanIsNearCentre) {
    // Stratification makes the mean converge much faster than 1/sqrt(n): each coordinate's mean
    // error is below (cell width)/sqrt(n) * (1/sqrt(12)) ~ 0.0011 for n = 1024 (32x32 cells of
    // width 1/16); 0.01 leaves a wide margin while still catching a biased generator.
    const auto pts = geometry::stratifiedSquare(1024, 9);
    glm::dvec2 mean(0.0);
    for (const glm::vec2& p : pts) mean += glm::dvec2(p);
    mean /= static_cast<double>(pts.size());
    EXPECT_NEAR(mean.x, 0.0, 0.01);
    EXPECT_NEAR(mean.y, 0.0, 0.01);
}

TEST(SamplingTest, RejectsNonPositiveCount) {
    EXPECT_THROW(geometry::stratifiedSquare(0, 1), std::invalid_argument);
}

// scrambledNet: a (0, k, 2)-net in base 2 — every 2^a x 2^(k-a) grid holds one point per cell.
TEST(SamplingTest, ScrambledNetHasOnePointInEveryElementaryInterval) {
    for (int k = 0; k <= 8; ++k) {
        const int n = 1 << k;
        SCOPED_TRACE(n);
        const auto pts = geometry::scrambledNet(n, 11);
        ASSERT_EQ(pts.size(), static_cast<std::size_t>(n));
        for (int a = 0; a <= k; ++a) {
            const int nx = 1 << a, ny = n / nx;
            std::vector<int> count(static_cast<std::size_t>(n), 0);
            for (const glm::vec2& p : pts) {
                ASSERT_GT(p.x, -1.0f);
                ASSERT_LT(p.x, 1.0f);
                ASSERT_GT(p.y, -1.0f);
                ASSERT_LT(p.y, 1.0f);
                const int i = static_cast<int>((p.x + 1.0f) * 0.5f * nx);
                const int j = static_cast<int>((p.y + 1.0f) * 0.5f * ny);
                ++count[static_cast<std::size_t>(j * nx + i)];
            }
            for (int c = 0; c < n; ++c)
                EXPECT_EQ(count[static_cast<std::size_t>(c)], 1) << a << " x-bits, cell " << c;
        }
    }
}

TEST(SamplingTest, ScrambledNetIsDeterministicAndSeeded) {
    const auto a = geometry::scrambledNet(32, 5), b = geometry::scrambledNet(32, 5);
    const auto c = geometry::scrambledNet(32, 6);
    int differ = 0;
    for (std::size_t i = 0; i < a.size(); ++i) {
        EXPECT_EQ(a[i], b[i]);
        differ += a[i] != c[i];
    }
    EXPECT_GT(differ, 16); // another seed scrambles differently
}

TEST(SamplingTest, ScrambledNetRejectsOtherCounts) {
    for (int n : {0, -4, 3, 24, 1 << 17})
        EXPECT_THROW(geometry::scrambledNet(n, 1), std::invalid_argument) << n;
}
