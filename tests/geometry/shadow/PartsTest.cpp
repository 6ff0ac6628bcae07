// The float per-quadrant sums (shaders/shared/Parts.h, the shaders' source compiled as C++ through
// geometry/shadow/Parts.h) against the double model
// (geometry/models/BlendModel.h: projectEdge, partCoverage, partEdgeBounds, cornerWinding, R = 4) on
// random lights, edges and points, and against the float edgeCoverage (Σ over the quadrants / 4).
// Max errors are printed.
#include "TestRandom.h"
#include <geometry/models/BlendModel.h>
#include <geometry/shadow/Coverage.h>
#include <geometry/shadow/LightMask.h>
#include <geometry/shadow/Parts.h>
#include <shared/LightMask.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <random>
#include <stdexcept>
#include <vector>

namespace {

using namespace geometry::blend;
using geometry::RectLight;
using glm::vec3;

using testutil::Rng;

struct Case {
    RectLight light;
    vec3 p, e0, e1;
    double magnification = 1.0; // 1 / the nearest end's distance to p's level (relative to p's)
};

// A random light; p and the edge on the same side of it, the edge between them mostly (some
// edges reach beyond p's level or through the light's plane: clipped).
Case randomCase(Rng& rng) {
    Case k;
    k.light.center = vec3(rng.uniform(-3, 3), rng.uniform(-3, 3), rng.uniform(-3, 3));
    const dvec3 a = rng.direction();
    const dvec3 b = glm::normalize(glm::cross(a, rng.direction()));
    k.light.u = vec3(a * rng.uniform(0.2, 1.5));
    k.light.v = vec3(b * rng.uniform(0.2, 1.5));
    const LightFrame f = lightFrame(k.light);
    auto at = [&](double s, double t, double h) { return f.c + s * f.u + t * f.v + h * f.n; };
    const double side = rng.uniform(0, 1) < 0.5 ? -1.0 : 1.0;
    const double hp = rng.uniform(1, 6);
    k.p = vec3(at(rng.uniform(-3, 3), rng.uniform(-3, 3), side * hp));
    // End points projecting near the light (exactly onto light point y where between the two).
    auto end = [&] {
        const dvec3 y = at(rng.uniform(-1.5, 1.5), rng.uniform(-1.5, 1.5), 0.0);
        const double lambda = rng.uniform(-0.1, 1.1);
        k.magnification = std::max(k.magnification, 1.0 / std::max(std::abs(1.0 - lambda), 1e-4));
        return vec3(y + lambda * (dvec3(k.p) - y));
    };
    k.e0 = end();
    k.e1 = end();
    return k;
}

// Distance (light coordinates, the double model's) of the light point of corner k of quadrant q
// to the nearest boundary line of R_e: where float may decide the corner otherwise.
double cornerMargin(const ProjectedEdge& edge, const Part& part, int k) {
    const dvec3 y = part.fromPart * dvec3(part.corners[k], 1.0);
    double m = 1e300;
    for (const dvec3& h : edge.halves)
        m = std::min(m, std::abs(glm::dot(h, y)) / glm::length(glm::dvec2(h)));
    return m;
}

} // namespace

TEST(PartsTest, FloatPartsMatchTheDoubleModel) {
    // Float keeps ~7 digits; the projected coordinates are of the light's size for ends at least
    // p's height from p's level (measured: coverage 1.1e-5, bounds 1.6e-5 with ends within 0.9
    // of the way to p; printed below as error / magnification).
    constexpr double kCoverageTolerance = 1e-4; // of a quadrant's area
    constexpr double kSumTolerance = 2e-6;      // Σ / 4 against the float edgeCoverage
    constexpr double kBoundsTolerance = 1e-4;   // part coordinates
    constexpr double kCornerMargin = 1e-4;      // corners farther from R_e's lines never flip
    // The tolerances above are for ends at least p's height away from p's level; an end at
    // 1 / m of it magnifies the projection's rounding m times: they scale with m up to this.
    constexpr double kMaxMagnification = 1e3;
    constexpr int kItems = 20000;
    Rng rng(0x9a27);
    double maxCoverage = 0.0, maxSum = 0.0, maxBounds = 0.0, maxCoverageRel = 0.0;
    double maxBoundsRel = 0.0;
    int nonZero = 0, nonEmpty = 0, emptinessFlips = 0, inside = 0, windingFlips = 0;
    int windingFlipsFarFromLines = 0;
    int degenerate = 0;
    double maxDegenerateCoverage = 0.0;
    for (int n = 0; n < kItems; ++n) {
        const Case k = randomCase(rng);
        const geometry::CoverageLight cl =
            geometry::coverageLight(k.light.center, k.light.u, k.light.v);
        const geometry::EdgeParts4 twin = geometry::edgeParts4(k.p, k.e0, k.e1, cl);
        const ProjectedEdge edge =
            projectEdge(lightFrame(k.light), dvec3(k.p), dvec3(k.e0), dvec3(k.e1));
        const float cov = geometry::edgeCoverage(k.p, k.e0, k.e1, cl);
        const double sum =
            (double(twin.coverage[0]) + twin.coverage[1] + twin.coverage[2] + twin.coverage[3]) /
            4.0;
        maxSum = std::max(maxSum, std::abs(sum - double(cov)));
        EXPECT_NEAR(sum, cov, kSumTolerance) << n;
        for (int q = 0; q < 4; ++q) {
            const Part part = radialPart(4, q);
            const double exact = partCoverage(edge, part);
            nonZero += exact != 0.0;
            const double err = std::abs(double(twin.coverage[q]) - exact);
            if (k.magnification > kMaxMagnification) {
                // An end within 1e-3 of p's height of p: the projection itself is ill-conditioned
                // in float (edgeCoverage's too); only measured.
                ++degenerate;
                maxDegenerateCoverage = std::max(maxDegenerateCoverage, err);
                continue;
            }
            maxCoverage = std::max(maxCoverage, err);
            maxCoverageRel = std::max(maxCoverageRel, err / k.magnification);
            EXPECT_LE(err, kCoverageTolerance * k.magnification) << n << " quadrant " << q;

            const Rect r = partEdgeBounds(edge, part);
            const glm::vec4 b = twin.bounds[q];
            const bool twinEmpty = b.x > b.z || b.y > b.w;
            if (r.empty() != twinEmpty) {
                // Only an edge grazing the part (its extent there below the tolerance).
                ++emptinessFlips;
                const double extent =
                    twinEmpty ? std::max(r.width(), r.height()) : std::max(b.z - b.x, b.w - b.y);
                EXPECT_LE(extent, kBoundsTolerance) << n << " quadrant " << q;
            } else if (!r.empty()) {
                ++nonEmpty;
                const double d = std::max({std::abs(b.x - r.minX), std::abs(b.y - r.minY),
                                           std::abs(b.z - r.maxX), std::abs(b.w - r.maxY)});
                maxBounds = std::max(maxBounds, d);
                maxBoundsRel = std::max(maxBoundsRel, d / k.magnification);
                EXPECT_LE(d, kBoundsTolerance * k.magnification) << n << " quadrant " << q;
            } else {
                EXPECT_EQ(b, glm::vec4(1.0f, 1.0f, 0.0f, 0.0f));
            }

            for (int c = 1; c < 4; ++c) {
                const int model = cornerWinding(edge, part, c);
                const int got = static_cast<int>(twin.windings[q][c - 1]);
                EXPECT_EQ(float(got), twin.windings[q][c - 1]);
                inside += model != 0;
                if (model == got) continue;
                ++windingFlips;
                if (!edge.region || cornerMargin(edge, part, c) > kCornerMargin * k.magnification) {
                    ++windingFlipsFarFromLines;
                    ADD_FAILURE() << n << " quadrant " << q << " corner " << c << ": model "
                                  << model << " twin " << got;
                }
            }
        }
    }
    std::printf("[ parts    ] %d edges: %d quadrant coverages non-zero, max |float - double| "
                "%.2g; max |Σ/4 - edgeCoverage| %.2g\n",
                kItems, nonZero, maxCoverage, maxSum);
    std::printf("[ parts    ] %d quadrants with an end within 1e-3 of p's level: max coverage "
                "error %.2g (not checked)\n",
                degenerate, maxDegenerateCoverage);
    std::printf("[ parts    ] max error / magnification: coverage %.2g, bounds %.2g\n",
                maxCoverageRel, maxBoundsRel);
    std::printf("[ parts    ] bounds: %d non-empty, max |diff| %.2g, %d emptiness flips; "
                "corners: %d in R_e, %d flips (%d far from R_e's lines)\n",
                nonEmpty, maxBounds, emptinessFlips, inside, windingFlips,
                windingFlipsFarFromLines);
    EXPECT_GT(nonZero, kItems);      // most edges cover some of several quadrants
    EXPECT_GT(nonEmpty, kItems / 2); // and cross some quadrant
    EXPECT_GT(inside, kItems / 4);   // corners in R_e are common
    EXPECT_LE(emptinessFlips, kItems / 1000);
    EXPECT_LE(windingFlips, kItems / 1000);
}

// The light the unit square at the origin (u along x, v along y).
RectLight unitSquareLight() {
    RectLight light;
    light.center = vec3(0.0f);
    light.u = vec3(1.0f, 0.0f, 0.0f);
    light.v = vec3(0.0f, 1.0f, 0.0f);
    return light;
}

// Exact configurations (the light the unit square at the origin, p one unit below, edges half-way:
// the projection is 2 x, exact in float): edges of a closed loop around a quadrant's corner and
// loops whose projected vertices lie exactly on part corners and on the light's axes. The twin's
// windings are the model's (its tie rule), and over a closed loop every corner's sum is within
// [-1, 1].
TEST(PartsTest, TiesOnCornersAndAxesAsTheModel) {
    const RectLight light = unitSquareLight();
    const geometry::CoverageLight cl = geometry::coverageLight(light.center, light.u, light.v);
    const LightFrame f = lightFrame(light);
    const vec3 p(0.0f, 0.0f, -1.0f);
    // Projected loops (light coordinates), counter-clockwise; vertices on corners and axes.
    const std::vector<std::vector<glm::vec2>> loops = {
        {{1, 0}, {1, 1}, {0, 1}, {0.5f, 0.5f}},         // corners of quadrant 0 as vertices
        {{1, -1}, {1, 1}, {-1, 1}, {-1, -1}},           // the light's own outline
        {{0.5f, -0.5f}, {1, 0}, {0.5f, 1.5f}, {-1, 0}}, // through (1, 0) and (-1, 0)
        {{0.25f, 0.25f}, {1.5f, 0.25f}, {1.5f, 1.0f}, {0.25f, 1.0f}}, // a side through (1, 1)
    };
    int checked = 0;
    for (std::size_t l = 0; l < loops.size(); ++l) {
        const auto& loop = loops[l];
        for (int q = 0; q < 4; ++q) {
            const Part part = radialPart(4, q);
            std::array<int, 3> sumModel{}, sumTwin{};
            std::array<float, 4> coverage{};
            double coverageModel = 0.0;
            for (std::size_t i = 0; i < loop.size(); ++i) {
                const glm::vec2 a = loop[i], b = loop[(i + 1) % loop.size()];
                const vec3 e0(0.5f * a.x, 0.5f * a.y, -0.5f), e1(0.5f * b.x, 0.5f * b.y, -0.5f);
                const geometry::EdgeParts4 twin = geometry::edgeParts4(p, e0, e1, cl);
                const ProjectedEdge edge = projectEdge(f, dvec3(p), dvec3(e0), dvec3(e1));
                for (int c = 1; c < 4; ++c) {
                    sumModel[c - 1] += cornerWinding(edge, part, c);
                    sumTwin[c - 1] += static_cast<int>(twin.windings[q][c - 1]);
                    EXPECT_EQ(float(cornerWinding(edge, part, c)), twin.windings[q][c - 1])
                        << "loop " << l << " edge " << i << " quadrant " << q << " corner " << c;
                    ++checked;
                }
                coverage[q] += twin.coverage[q];
                coverageModel += partCoverage(edge, part);
            }
            for (int c = 0; c < 3; ++c) {
                EXPECT_LE(std::abs(sumTwin[c]), 1) << "loop " << l << " quadrant " << q;
            }
            EXPECT_EQ(sumModel, sumTwin);
            EXPECT_NEAR(coverage[q], coverageModel, 1e-6) << "loop " << l << " quadrant " << q;
        }
    }
    EXPECT_EQ(checked, 3 * 4 * 16);
}

namespace {

// Corner windings from edgePartSet's mixed-radix number (Σ_j 16^j w_j, each w_j in [-8, 7]).
std::array<int, 4> decodeWindings(float packed, int corners) {
    std::array<int, 4> w{};
    int n = static_cast<int>(std::lround(packed));
    for (int j = 0; j < corners; ++j) {
        w[j] = ((n + 8) % 16 + 16) % 16 - 8;
        n = (n - w[j]) / 16;
    }
    EXPECT_EQ(n, 0) << packed;
    return w;
}

} // namespace

// edgePartSet (every R, with the moments, a set of four parts at a time) against the double model
// on the random cases above: coverage, first moments, bounds and every corner's winding of every
// part of R = 1, 4 and 8 (both sets). R = 4 also against edgeParts4 (the paper's path).
TEST(PartsTest, FloatPartSetMatchesTheDoubleModelForEveryR) {
    constexpr double kTolerance = 1e-4;    // part area / part coordinates, times magnification
    constexpr double kCornerMargin = 1e-4; // as above
    constexpr double kMaxMagnification = 1e3;
    constexpr int kItems = 6000;
    Rng rng(0x7e11);
    for (const int parts : {1, 4, 8}) {
        double maxCoverage = 0.0, maxMoment = 0.0, maxBounds = 0.0, maxVs4 = 0.0;
        int nonZero = 0, nonEmpty = 0, inside = 0, windingFlips = 0, emptinessFlips = 0;
        for (int n = 0; n < kItems; ++n) {
            const Case k = randomCase(rng);
            if (k.magnification > kMaxMagnification) continue; // ill-conditioned (test above)
            const geometry::CoverageLight cl =
                geometry::coverageLight(k.light.center, k.light.u, k.light.v);
            const ProjectedEdge edge =
                projectEdge(lightFrame(k.light), dvec3(k.p), dvec3(k.e0), dvec3(k.e1));
            const double tolerance = kTolerance * k.magnification;
            for (int set = 0; set < (parts == 8 ? 2 : 1); ++set) {
                const geometry::EdgePartSet twin =
                    geometry::edgePartSet(k.p, k.e0, k.e1, cl, parts, set);
                if (parts == 4) {
                    const geometry::EdgeParts4 paper = geometry::edgeParts4(k.p, k.e0, k.e1, cl);
                    for (int q = 0; q < 4; ++q) {
                        maxVs4 = std::max(maxVs4,
                                          double(std::abs(paper.coverage[q] - twin.coverage[q])));
                        EXPECT_EQ(paper.bounds[q], twin.bounds[q]) << n;
                        EXPECT_EQ(paper.windings[q].x + 16.0f * paper.windings[q].y +
                                      256.0f * paper.windings[q].z,
                                  twin.windings[q])
                            << n;
                    }
                }
                for (int kk = 0; kk < (parts == 1 ? 1 : 4); ++kk) {
                    const Part part = radialPart(parts, 4 * set + kk);
                    const double cov = partCoverage(edge, part);
                    const dvec2 mom = partMoment(edge, part);
                    nonZero += cov != 0.0;
                    const double dc = std::abs(double(twin.coverage[kk]) - cov);
                    const double dm = std::max(std::abs(double(twin.momentX[kk]) - mom.x),
                                               std::abs(double(twin.momentY[kk]) - mom.y));
                    maxCoverage = std::max(maxCoverage, dc / k.magnification);
                    maxMoment = std::max(maxMoment, dm / k.magnification);
                    EXPECT_LE(dc, tolerance) << n << " part " << 4 * set + kk;
                    EXPECT_LE(dm, tolerance) << n << " part " << 4 * set + kk;

                    const Rect r = partEdgeBounds(edge, part);
                    const glm::vec4 b = twin.bounds[kk];
                    const bool twinEmpty = b.x > b.z || b.y > b.w;
                    if (r.empty() != twinEmpty) {
                        ++emptinessFlips;
                        const double extent = twinEmpty ? std::max(r.width(), r.height())
                                                        : std::max(b.z - b.x, b.w - b.y);
                        EXPECT_LE(extent, tolerance) << n << " part " << 4 * set + kk;
                    } else if (!r.empty()) {
                        ++nonEmpty;
                        const double d = std::max({std::abs(b.x - r.minX), std::abs(b.y - r.minY),
                                                   std::abs(b.z - r.maxX), std::abs(b.w - r.maxY)});
                        maxBounds = std::max(maxBounds, d / k.magnification);
                        EXPECT_LE(d, tolerance) << n << " part " << 4 * set + kk;
                    }

                    // The corners that are not the centre, in the packing's order.
                    const int first = parts == 1 ? 0 : 1;
                    const std::array<int, 4> w =
                        decodeWindings(twin.windings[kk], part.cornerCount - first);
                    for (int c = first; c < part.cornerCount; ++c) {
                        const int model = cornerWinding(edge, part, c);
                        inside += model != 0;
                        if (model == w[c - first]) continue;
                        ++windingFlips;
                        if (!edge.region ||
                            cornerMargin(edge, part, c) > kCornerMargin * k.magnification)
                            ADD_FAILURE() << n << " part " << 4 * set + kk << " corner " << c
                                          << ": model " << model << " twin " << w[c - first];
                    }
                }
            }
        }
        std::printf("[ parts    ] R = %d: %d coverages non-zero; max error / magnification: "
                    "coverage %.2g, moments %.2g, bounds %.2g (%d non-empty, %d emptiness "
                    "flips); corners %d in R_e, %d flips; R = 4 against edgeParts4 %.2g\n",
                    parts, nonZero, maxCoverage, maxMoment, maxBounds, nonEmpty, emptinessFlips,
                    inside, windingFlips, maxVs4);
        EXPECT_GT(nonZero, kItems / 2);
        EXPECT_GT(nonEmpty, kItems / 4);
        EXPECT_GT(inside, kItems / 4);
        EXPECT_LE(emptinessFlips, kItems / 1000);
        EXPECT_LE(windingFlips, kItems / 1000);
        EXPECT_LE(maxVs4, 1e-6); // the same quadrant area, integrated with the moments
    }
}

// The tie configurations above (projected vertices exactly on part corners, on the light's axes
// and diagonals) for edgePartSet and every R: each edge's windings are the model's, and over a
// closed loop every corner's sum is within [-1, 1] (what the mixed-radix packing relies on).
TEST(PartsTest, PartSetTiesAsTheModelForEveryR) {
    const RectLight light = unitSquareLight();
    const geometry::CoverageLight cl = geometry::coverageLight(light.center, light.u, light.v);
    const LightFrame f = lightFrame(light);
    const vec3 p(0.0f, 0.0f, -1.0f);
    const std::vector<std::vector<glm::vec2>> loops = {
        {{1, 0}, {1, 1}, {0, 1}, {0.5f, 0.5f}},
        {{1, -1}, {1, 1}, {-1, 1}, {-1, -1}},
        {{0.5f, -0.5f}, {1, 0}, {0.5f, 1.5f}, {-1, 0}},
        {{0.25f, 0.25f}, {1.5f, 0.25f}, {1.5f, 1.0f}, {0.25f, 1.0f}},
        {{0.5f, 0.5f}, {1.5f, 0.5f}, {1, 1}, {0.5f, 1.5f}},           // through the diagonal's end
        {{-0.5f, -0.5f}, {1.5f, -1.5f}, {1.5f, 1.5f}, {-1.5f, 1.5f}}, // around three corners
    };
    int checked = 0;
    for (const int parts : {1, 4, 8}) {
        for (std::size_t l = 0; l < loops.size(); ++l) {
            const auto& loop = loops[l];
            for (int set = 0; set < (parts == 8 ? 2 : 1); ++set) {
                for (int kk = 0; kk < (parts == 1 ? 1 : 4); ++kk) {
                    const Part part = radialPart(parts, 4 * set + kk);
                    const int first = parts == 1 ? 0 : 1;
                    std::array<int, 4> sumModel{}, sumTwin{};
                    for (std::size_t i = 0; i < loop.size(); ++i) {
                        const glm::vec2 a = loop[i], b = loop[(i + 1) % loop.size()];
                        const vec3 e0(0.5f * a.x, 0.5f * a.y, -0.5f);
                        const vec3 e1(0.5f * b.x, 0.5f * b.y, -0.5f);
                        const geometry::EdgePartSet twin =
                            geometry::edgePartSet(p, e0, e1, cl, parts, set);
                        const ProjectedEdge edge = projectEdge(f, dvec3(p), dvec3(e0), dvec3(e1));
                        const std::array<int, 4> w =
                            decodeWindings(twin.windings[kk], part.cornerCount - first);
                        for (int c = first; c < part.cornerCount; ++c) {
                            EXPECT_EQ(cornerWinding(edge, part, c), w[c - first])
                                << "R " << parts << " loop " << l << " edge " << i << " part "
                                << 4 * set + kk << " corner " << c;
                            sumModel[c] += cornerWinding(edge, part, c);
                            sumTwin[c] += w[c - first];
                            ++checked;
                        }
                    }
                    for (int c = 0; c < 4; ++c)
                        EXPECT_LE(std::abs(sumTwin[c]), 1);
                    EXPECT_EQ(sumModel, sumTwin);
                }
            }
        }
    }
    EXPECT_EQ(checked, 6 * 4 * (4 + 3 * 4 + 2 * 8));
}

// wedges-bitmask's estimate=quadrants and moments: the wedges add regionQuadrantCoverage of the
// R their light-sample masks take (shared/LightMask.h edgeRegion: ends projected exactly, no R
// where the projected edge misses the light), edgeParts4's coverage unsigned, summed in one walk
// along R's boundary (split at the axes) instead of one per quadrant: the same areas up to float
// rounding, and within FloatPartsMatchTheDoubleModel's tolerance of the double model.
TEST(PartsTest, QuadrantCoverageIsEdgePartsCoverage) {
    constexpr double kMaxMagnification = 1e3; // as FloatPartsMatchTheDoubleModel
    Rng rng(0x51ab);
    int nonZero = 0, split = 0;
    double maxTwin = 0.0, maxModel = 0.0;
    for (int n = 0; n < 20000; ++n) {
        const Case k = randomCase(rng);
        const geometry::CoverageLight cl =
            geometry::coverageLight(k.light.center, k.light.u, k.light.v);
        glm::vec3 h0, h1, h2;
        float sg = 0.0f;
        const glm::vec4 q = shader::edgeRegion(k.p, k.e0, k.e1, cl, h0, h1, h2, sg)
                                ? shader::regionQuadrantCoverage(h0, h1, h2)
                                : glm::vec4(0.0f);
        const geometry::EdgeParts4 parts = geometry::edgeParts4(k.p, k.e0, k.e1, cl);
        const ProjectedEdge edge =
            projectEdge(lightFrame(k.light), dvec3(k.p), dvec3(k.e0), dvec3(k.e1));
        int reached = 0;
        for (int i = 0; i < 4; ++i) {
            nonZero += q[i] != 0.0f;
            reached += q[i] != 0.0f;
            if (k.magnification > kMaxMagnification) continue; // ill-conditioned projection
            // Both sum the same terms in another order and cut, from ends projected apart: float
            // rounding, of the light's size times the magnification. Over 10^6 cases (this seed,
            // 4x10^6 quadrants) the largest difference is 8.2e-6 x magnification (99.99 % below
            // 5e-7); these 20 000 reach 1.6e-6 with GCC's draws, 2.0e-6 with clang's (which
            // evaluates randomCase's call arguments in another order). Each is within 3.5e-5 x
            // magnification of the double model over those 10^6 cases: the error is edgeParts4's
            // as often as the one walk's.
            const double twin = std::abs(double(q[i]) - std::abs(parts.coverage[i]));
            maxTwin = std::max(maxTwin, twin / k.magnification);
            EXPECT_LE(twin, 2e-5 * k.magnification) << n << " quadrant " << i;
            const double model =
                std::abs(double(q[i]) - std::abs(partCoverage(edge, radialPart(4, i))));
            maxModel = std::max(maxModel, model / k.magnification);
            EXPECT_LE(model, 1e-4 * k.magnification) << n << " quadrant " << i;
        }
        split += reached >= 2;
    }
    std::printf("[ parts    ] one walk against four: max |diff| / magnification %.2g; against "
                "the double model %.2g\n",
                maxTwin, maxModel);
    EXPECT_GT(nonZero, 20000); // the edges reach the light's quadrants, not only miss them
    EXPECT_GT(split, 5000);    // and R is often cut by an axis
}

TEST(PartsTest, EveryRunOfEightLightSamplesLiesInOneQuadrant) {
    for (const int n : geometry::kLightMaskSampleCounts)
        for (std::uint32_t seed = 1; seed <= 40; ++seed) {
            const std::vector<glm::vec2> pattern = geometry::lightMaskPattern(n, seed);
            const std::vector<int> runs = geometry::lightMaskRunQuadrants(pattern);
            ASSERT_EQ(runs.size(), pattern.size() / 8);
            int perQuadrant[4] = {0, 0, 0, 0};
            for (std::size_t i = 0; i < pattern.size(); ++i) {
                const int q = shader::partsQuadrantOf(pattern[i]);
                EXPECT_EQ(q, runs[i / 8]) << "n " << n << " seed " << seed << " sample " << i;
                // The quadrant's signs (shared/Parts.h): (+,+), (-,+), (-,-), (+,-).
                EXPECT_EQ(pattern[i].x >= 0.0f, q == 0 || q == 3);
                EXPECT_EQ(pattern[i].y >= 0.0f, q < 2);
                ++perQuadrant[q];
            }
            for (const int c : perQuadrant) EXPECT_EQ(c, n / 4) << "n " << n << " seed " << seed;
        }
    // A run that straddles two quadrants is refused, not summed into one.
    std::vector<glm::vec2> mixed(8, glm::vec2(0.5f, 0.5f));
    mixed[3] = glm::vec2(-0.5f, 0.5f);
    EXPECT_THROW(geometry::lightMaskRunQuadrants(mixed), std::logic_error);
    EXPECT_THROW(geometry::lightMaskRunQuadrants(std::vector<glm::vec2>(7)), std::logic_error);
}

namespace {

// Twice the signed area of the light's square [-1, 1]^2 clipped to half-planes dot(h, (s, t,
// 1)) >= 0, in double: the polygon built and clipped corner by corner (what the shared code
// avoids building).
double clippedSquareArea(const std::vector<glm::dvec3>& halves) {
    std::vector<glm::dvec2> poly = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
    for (const glm::dvec3& h : halves) {
        std::vector<glm::dvec2> out;
        for (std::size_t i = 0; i < poly.size(); ++i) {
            const glm::dvec2 a = poly[i], b = poly[(i + 1) % poly.size()];
            const double fa = glm::dot(h, glm::dvec3(a, 1.0)), fb = glm::dot(h, glm::dvec3(b, 1.0));
            if (fa >= 0.0) out.push_back(a);
            if ((fa >= 0.0) != (fb >= 0.0)) out.push_back(a + (fa / (fa - fb)) * (b - a));
        }
        poly = out;
    }
    double twice = 0.0;
    for (std::size_t i = 0; i < poly.size(); ++i) {
        const glm::dvec2 a = poly[i], b = poly[(i + 1) % poly.size()];
        twice += a.x * b.y - a.y * b.x;
    }
    return twice;
}

// R of edge e0 e1 seen from p as the wedges take it (shared/LightMask.h edgeRegion; none where
// the projected edge misses the light): its half-planes, and its sector and line as
// partsRegionsOverlap takes them.
struct Region {
    bool any = false;
    glm::vec3 h0{}, h1{}, h2{};
    glm::vec2 from{}, to{};
};
Region areaRegion(vec3 p, vec3 e0, vec3 e1, const geometry::CoverageLight& light) {
    Region r;
    float sg = 0.0f;
    r.any = shader::edgeRegion(p, e0, e1, light, r.h0, r.h1, r.h2, sg);
    if (r.any) {
        r.from = shader::partsSectorFrom(r.h0, r.h1, sg);
        r.to = shader::partsSectorTo(r.h0, r.h1, sg);
    }
    return r;
}

} // namespace

// wedges-bitmask's estimate=moments: the overlap of two edges' regions (seen from the same p)
// within the light, partsRegionsOverlap's sector-and-farther-line walk, against the double
// polygon of the square clipped to both regions' six half-planes; and R with itself is R's own
// share (coverageRegionShare, what edgeCoverage returns unsigned).
TEST(PartsTest, RegionsOverlapIsTheClippedPolygonsArea) {
    constexpr double kTolerance = 1e-4; // of the light's area, for unmagnified ends (as above)
    constexpr double kMaxMagnification = 1e3;
    constexpr int kItems = 20000;
    Rng rng(0x0e1a);
    double maxError = 0.0, maxSelf = 0.0;
    int overlapping = 0, disjoint = 0, checked = 0;
    for (int n = 0; n < kItems; ++n) {
        const Case k = randomCase(rng);
        // A second edge for the same light and p: the first case's ends from another case's
        // light points, re-expressed for this light.
        Case other = randomCase(rng);
        const LightFrame f = lightFrame(k.light), g = lightFrame(other.light);
        auto moved = [&](vec3 e) {
            // e's place relative to the other case's light and p, moved onto this one's.
            const dvec3 d = dvec3(e) - g.c;
            const double s = glm::dot(d, g.u) / glm::dot(g.u, g.u);
            const double t = glm::dot(d, g.v) / glm::dot(g.v, g.v);
            const double lambda = glm::dot(d, g.n) / glm::dot(dvec3(other.p) - g.c, g.n);
            const dvec3 y = f.c + s * f.u + t * f.v;
            return vec3(y + lambda * (dvec3(k.p) - y));
        };
        const double magnification = std::max(k.magnification, other.magnification);
        if (magnification > kMaxMagnification) continue;
        const geometry::CoverageLight cl =
            geometry::coverageLight(k.light.center, k.light.u, k.light.v);
        const Region a = areaRegion(k.p, k.e0, k.e1, cl);
        const Region b = areaRegion(k.p, moved(other.e0), moved(other.e1), cl);
        if (!a.any || !b.any) continue;
        ++checked;
        const double got = shader::partsRegionsOverlap(a.from, a.to, a.h2, b.from, b.to, b.h2);
        const double want = 0.125 * std::abs(clippedSquareArea(
                                        {glm::dvec3(a.h0), glm::dvec3(a.h1), glm::dvec3(a.h2),
                                         glm::dvec3(b.h0), glm::dvec3(b.h1), glm::dvec3(b.h2)}));
        const double error = std::abs(got - want);
        maxError = std::max(maxError, error / magnification);
        EXPECT_LE(error, kTolerance * magnification) << n << ": " << got << " vs " << want;
        (want > 1e-3 ? overlapping : disjoint) += 1;
        const double self = shader::partsRegionsOverlap(a.from, a.to, a.h2, a.from, a.to, a.h2);
        const double own = shader::coverageRegionShare(a.h0, a.h1, a.h2);
        maxSelf = std::max(maxSelf, std::abs(self - own) / k.magnification);
        EXPECT_LE(std::abs(self - own), kTolerance * k.magnification) << n;
    }
    std::printf("  %d pairs (%d overlapping by > 0.1%% of the light): max error %.2g, with "
                "itself %.2g (over the magnification)\n",
                checked, overlapping, maxError, maxSelf);
    EXPECT_GT(overlapping, 1000); // the cases overlap, not only miss each other
    EXPECT_GT(disjoint, 1000);
}
