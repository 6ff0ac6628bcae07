#include <geometry/core/Error.h>
#include <geometry/scene/Primitives.h>
#include <geometry/shadow/Topology.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <utility>

namespace {

using geometry::MeshData;

// Divergence theorem: sum of signed tetrahedra (origin, triangle). Positive when every triangle
// is counter-clockwise seen from outside.
double signedVolume(const MeshData& m) {
    double v = 0.0;
    for (const auto& t : m.triangles) {
        const glm::dvec3 a(m.positions[t.x]), b(m.positions[t.y]), c(m.positions[t.z]);
        v += glm::dot(a, glm::cross(b, c)) / 6.0;
    }
    return v;
}

// Closed, consistently oriented 2-manifold: every directed edge occurs once and its reverse
// occurs once (so the seam and poles of the sphere must share vertices).
void expectClosedOriented(const MeshData& m) {
    std::map<std::pair<unsigned, unsigned>, int> directed;
    for (const auto& t : m.triangles) {
        ASSERT_LT(t.x, m.positions.size());
        ASSERT_LT(t.y, m.positions.size());
        ASSERT_LT(t.z, m.positions.size());
        ++directed[{t.x, t.y}];
        ++directed[{t.y, t.z}];
        ++directed[{t.z, t.x}];
    }
    for (const auto& [edge, count] : directed) {
        EXPECT_EQ(count, 1) << "edge " << edge.first << "-" << edge.second;
        const auto rev = directed.find({edge.second, edge.first});
        EXPECT_TRUE(rev != directed.end() && rev->second == 1)
            << "edge " << edge.first << "-" << edge.second << " has no single reverse";
    }
}

TEST(PrimitivesTest, BoxCountsVolumeBounds) {
    const MeshData box = geometry::makeBox({1.0f, 2.0f, 3.0f}, {2.0f, 0.5f, 4.0f});
    EXPECT_EQ(box.positions.size(), 8u);
    EXPECT_EQ(box.triangles.size(), 12u);
    EXPECT_NEAR(signedVolume(box), 2.0 * 0.5 * 4.0, 1e-5); // positive: outward CCW
    expectClosedOriented(box);
    const geometry::Aabb b = box.bounds();
    EXPECT_FLOAT_EQ(b.min.x, 0.0f);
    EXPECT_FLOAT_EQ(b.max.x, 2.0f);
    EXPECT_FLOAT_EQ(b.min.y, 1.75f);
    EXPECT_FLOAT_EQ(b.max.y, 2.25f);
    EXPECT_FLOAT_EQ(b.min.z, 1.0f);
    EXPECT_FLOAT_EQ(b.max.z, 5.0f);
}

TEST(PrimitivesTest, BoxFacesPointAwayFromCentre) {
    const glm::vec3 c(0.5f, -1.0f, 2.0f);
    const MeshData box = geometry::makeBox(c, {1.0f, 1.0f, 1.0f});
    for (const auto& t : box.triangles) {
        const glm::vec3 a = box.positions[t.x], b = box.positions[t.y], d = box.positions[t.z];
        const glm::vec3 n = glm::cross(b - a, d - a);
        EXPECT_GT(glm::dot(n, (a + b + d) / 3.0f - c), 0.0f);
    }
}

TEST(PrimitivesTest, QuadCountsNormalBounds) {
    const glm::vec3 u(0.5f, 0.0f, 0.0f), v(0.0f, 0.0f, 0.25f);
    const MeshData q = geometry::makeQuad({0.0f, 2.0f, 0.0f}, u, v);
    EXPECT_EQ(q.positions.size(), 4u);
    ASSERT_EQ(q.triangles.size(), 2u);
    const glm::vec3 expected = glm::normalize(glm::cross(u, v)); // -y here
    double area = 0.0;
    for (const auto& t : q.triangles) {
        const glm::vec3 n =
            glm::cross(q.positions[t.y] - q.positions[t.x], q.positions[t.z] - q.positions[t.x]);
        EXPECT_NEAR(glm::dot(glm::normalize(n), expected), 1.0f, 1e-6f);
        area += 0.5 * glm::length(n);
    }
    EXPECT_NEAR(area, 4.0 * 0.5 * 0.25, 1e-6);
    const geometry::Aabb b = q.bounds();
    EXPECT_FLOAT_EQ(b.min.x, -0.5f);
    EXPECT_FLOAT_EQ(b.max.z, 0.25f);
    EXPECT_FLOAT_EQ(b.min.y, 2.0f);
    EXPECT_FLOAT_EQ(b.max.y, 2.0f);
}

TEST(PrimitivesTest, SphereCountsAndWatertight) {
    const int segments = 32;
    const MeshData s = geometry::makeSphere({0.0f, 1.0f, 0.0f}, 0.5f, segments);
    const int bands = segments / 2;
    EXPECT_EQ(s.positions.size(), std::size_t(2 + (bands - 1) * segments));
    EXPECT_EQ(s.triangles.size(), std::size_t(2 * segments * (bands - 1)));
    expectClosedOriented(s);
    EXPECT_GT(signedVolume(s), 0.0);
    for (const auto& p : s.positions) {
        EXPECT_NEAR(glm::length(p - glm::vec3(0.0f, 1.0f, 0.0f)), 0.5f, 1e-5f);
    }
    const geometry::Aabb b = s.bounds();
    EXPECT_NEAR(b.min.y, 0.5f, 1e-6f);
    EXPECT_NEAR(b.max.y, 1.5f, 1e-6f);
    EXPECT_NEAR(b.max.x, 0.5f, 1e-5f);
    EXPECT_NEAR(b.min.x, -0.5f, 1e-5f);
}

TEST(PrimitivesTest, FineSphereVolumeApproachesAnalytic) {
    const float r = 2.0f;
    // Shift the centre away from the origin: the volume formula must not depend on it.
    const MeshData s = geometry::makeSphere({3.0f, -2.0f, 1.0f}, r, 256);
    const double exact = 4.0 / 3.0 * std::numbers::pi * r * r * r;
    // A 256 x 128 tessellation loses ~0.07% of the volume; 0.2% leaves room for float rounding.
    EXPECT_NEAR(signedVolume(s) / exact, 1.0, 2e-3);
    EXPECT_LT(signedVolume(s), exact); // an inscribed polyhedron is strictly smaller
}

TEST(PrimitivesTest, SmallestSphereIsStillClosed) {
    const MeshData s = geometry::makeSphere({0.0f, 0.0f, 0.0f}, 1.0f, 3);
    expectClosedOriented(s);
    EXPECT_GT(signedVolume(s), 0.0);
}

TEST(PrimitivesTest, InvalidArgumentsThrow) {
    EXPECT_THROW(geometry::makeBox({0, 0, 0}, {1, 0, 1}), geometry::InputError);
    EXPECT_THROW(geometry::makeBox({0, 0, 0}, {1, -1, 1}), geometry::InputError);
    EXPECT_THROW(geometry::makeBox({0, 0, 0}, {1, NAN, 1}), geometry::InputError);
    EXPECT_THROW(geometry::makeQuad({0, 0, 0}, {0, 0, 0}, {0, 0, 1}), geometry::InputError);
    EXPECT_THROW(geometry::makeQuad({0, 0, 0}, {1, 0, 0}, {2, 0, 0}), geometry::InputError);
    EXPECT_THROW(geometry::makeSphere({0, 0, 0}, 1.0f, 2), geometry::InputError);
    EXPECT_THROW(geometry::makeSphere({0, 0, 0}, 0.0f, 16), geometry::InputError);
    EXPECT_THROW(geometry::makeSphere({0, 0, 0}, -1.0f, 16), geometry::InputError);
}

// Welded topology agrees: a closed 2-manifold with nothing dropped or merged by the welder.
void expectClosedTopology(const MeshData& m) {
    const geometry::Topology topo(m);
    EXPECT_EQ(topo.manifoldness(), geometry::Manifoldness::Closed)
        << geometry::toString(topo.manifoldness());
    EXPECT_EQ(topo.stats().degenerateTriangles, 0u);
    EXPECT_EQ(topo.stats().boundaryEdges, 0u);
    EXPECT_EQ(topo.stats().triangles, m.triangles.size());
}

// Every triangle faces away from `c` (stronger than a positive total volume: a star-shaped mesh
// seen from its centre has no inverted triangle).
void expectFacesAwayFrom(const MeshData& m, const glm::vec3& c) {
    int inverted = 0;
    for (const auto& t : m.triangles) {
        const glm::dvec3 a(m.positions[t.x]), b(m.positions[t.y]), d(m.positions[t.z]);
        const glm::dvec3 n = glm::cross(b - a, d - a);
        if (!(glm::dot(n, (a + b + d) / 3.0 - glm::dvec3(c)) > 0.0)) ++inverted;
    }
    EXPECT_EQ(inverted, 0);
}

TEST(PrimitivesTest, IcosphereCountsClosedOutward) {
    const glm::vec3 c(1.0f, -2.0f, 0.5f);
    for (int s = 0; s <= 4; ++s) {
        SCOPED_TRACE("subdivisions " + std::to_string(s));
        const MeshData m = geometry::makeIcosphere(c, 1.5f, s);
        const std::size_t pow4 = std::size_t(1) << (2 * s);
        EXPECT_EQ(m.triangles.size(), 20 * pow4);
        EXPECT_EQ(m.positions.size(), 10 * pow4 + 2);
        expectClosedOriented(m);
        expectClosedTopology(m);
        expectFacesAwayFrom(m, c);
        EXPECT_GT(signedVolume(m), 0.0);
        for (const auto& p : m.positions) EXPECT_NEAR(glm::length(p - c), 1.5f, 1e-5f);
    }
}

TEST(PrimitivesTest, IcosphereVolumeApproachesAnalytic) {
    const float r = 2.0f;
    const double exact = 4.0 / 3.0 * std::numbers::pi * r * r * r;
    double previous = 0.0;
    for (int s = 2; s <= 6; ++s) {
        const double v = signedVolume(geometry::makeIcosphere({0.5f, 0.0f, -1.0f}, r, s));
        EXPECT_LT(v, exact);     // inscribed
        EXPECT_GT(v, previous);  // each subdivision adds volume
        previous = v;
    }
    // 81,920 triangles lose ~0.01% of the volume; 0.1% leaves room for float rounding.
    EXPECT_NEAR(previous / exact, 1.0, 1e-3);
}

TEST(PrimitivesTest, TorusCountsClosedOutwardVolume) {
    const glm::vec3 c(0.0f, 1.0f, -3.0f);
    const float R = 2.0f, r = 0.5f;
    const int major = 256, minor = 128;
    const MeshData t = geometry::makeTorus(c, R, r, major, minor);
    EXPECT_EQ(t.positions.size(), std::size_t(major * minor));
    EXPECT_EQ(t.triangles.size(), std::size_t(2 * major * minor));
    expectClosedOriented(t);
    expectClosedTopology(t);
    // Genus 1: Euler characteristic V - E + F = 0.
    const geometry::Topology topo(t);
    EXPECT_EQ(std::int64_t(topo.stats().vertices) - std::int64_t(topo.stats().edges) +
                  std::int64_t(topo.stats().triangles),
              0);
    const double exact = 2.0 * std::numbers::pi * std::numbers::pi * R * r * r;
    const double v = signedVolume(t);
    EXPECT_GT(v, 0.0);
    EXPECT_LT(v, exact); // inscribed in both directions
    // The polygonal tube and ring lose ~(2pi/128)^2/6 + (2pi/256)^2/6 ~ 0.05%.
    EXPECT_NEAR(v / exact, 1.0, 2e-3);
    const geometry::Aabb b = t.bounds();
    EXPECT_NEAR(b.max.x, c.x + R + r, 1e-5f);
    EXPECT_NEAR(b.min.y, c.y - r, 1e-4f);
    EXPECT_NEAR(b.max.y, c.y + r, 1e-4f);
}

TEST(PrimitivesTest, CoarsestTorusIsStillClosed) {
    const MeshData t = geometry::makeTorus({0.0f, 0.0f, 0.0f}, 1.0f, 0.25f, 3, 3);
    EXPECT_EQ(t.triangles.size(), 18u);
    expectClosedOriented(t);
    expectClosedTopology(t);
    EXPECT_GT(signedVolume(t), 0.0);
}

TEST(PrimitivesTest, NoisySphereStaysClosedOutwardAndBounded) {
    const glm::vec3 c(0.0f, 2.0f, 1.0f);
    const float radius = 1.0f, amplitude = 0.15f;
    const MeshData base = geometry::makeIcosphere(c, radius, 4);
    MeshData noisy = base;
    geometry::displaceRadially(noisy, c, amplitude, 7u);
    ASSERT_EQ(noisy.positions.size(), base.positions.size());
    EXPECT_EQ(noisy.triangles, base.triangles);
    expectClosedOriented(noisy);
    expectClosedTopology(noisy);
    expectFacesAwayFrom(noisy, c);
    EXPECT_GT(signedVolume(noisy), 0.0);

    // Each vertex moves along its own direction, by at most the amplitude, and the offsets spread
    // over the whole range (the noise is not stuck at a constant).
    double lo = 1.0, hi = -1.0, sum = 0.0;
    for (std::size_t i = 0; i < base.positions.size(); ++i) {
        const glm::vec3 d0 = base.positions[i] - c, d1 = noisy.positions[i] - c;
        EXPECT_NEAR(glm::dot(glm::normalize(d0), glm::normalize(d1)), 1.0f, 1e-5f);
        const double offset = glm::length(d1) - radius;
        EXPECT_LE(std::abs(offset), amplitude + 1e-5);
        lo = std::min(lo, offset);
        hi = std::max(hi, offset);
        sum += offset;
    }
    EXPECT_LT(lo, -0.9 * amplitude);
    EXPECT_GT(hi, 0.9 * amplitude);
    // 2,562 uniform offsets: the mean is within ~4 standard errors (0.087 a / sqrt(n) * 4).
    EXPECT_NEAR(sum / double(base.positions.size()), 0.0, 0.01);
}

TEST(PrimitivesTest, NoisySphereIsDeterministicPerSeed) {
    const MeshData base = geometry::makeIcosphere({0.0f, 0.0f, 0.0f}, 1.0f, 2);
    MeshData a = base, b = base, other = base, none = base;
    geometry::displaceRadially(a, {0.0f, 0.0f, 0.0f}, 0.2f, 42u);
    geometry::displaceRadially(b, {0.0f, 0.0f, 0.0f}, 0.2f, 42u);
    geometry::displaceRadially(other, {0.0f, 0.0f, 0.0f}, 0.2f, 43u);
    geometry::displaceRadially(none, {0.0f, 0.0f, 0.0f}, 0.0f, 42u);
    EXPECT_EQ(a.positions, b.positions);
    EXPECT_NE(a.positions, other.positions);
    EXPECT_EQ(none.positions, base.positions);
}

TEST(PrimitivesTest, NoisyUnweldedMeshStaysClosedAfterWelding) {
    // glTF-style split vertices: every triangle has its own three. The noise depends on the
    // position only, so the copies of a vertex move together and welding closes the mesh again.
    const MeshData base = geometry::makeIcosphere({0.0f, 0.0f, 0.0f}, 1.0f, 3);
    MeshData split;
    for (const auto& t : base.triangles) {
        const auto first = static_cast<unsigned>(split.positions.size());
        split.positions.push_back(base.positions[t.x]);
        split.positions.push_back(base.positions[t.y]);
        split.positions.push_back(base.positions[t.z]);
        split.triangles.emplace_back(first, first + 1, first + 2);
    }
    geometry::displaceRadially(split, {0.0f, 0.0f, 0.0f}, 0.1f, 3u);
    expectClosedTopology(split);
    EXPECT_EQ(geometry::Topology(split).stats().vertices, base.positions.size());
    EXPECT_GT(signedVolume(split), 0.0);
}

TEST(PrimitivesTest, NewShapesRejectInvalidArguments) {
    using geometry::InputError;
    EXPECT_THROW(geometry::makeIcosphere({0, 0, 0}, 0.0f, 2), InputError);
    EXPECT_THROW(geometry::makeIcosphere({0, 0, 0}, NAN, 2), InputError);
    EXPECT_THROW(geometry::makeIcosphere({0, 0, 0}, 1.0f, -1), InputError);
    EXPECT_THROW(geometry::makeIcosphere({0, 0, 0}, 1.0f, 10), InputError);
    EXPECT_THROW(geometry::makeTorus({0, 0, 0}, 1.0f, 1.0f, 8, 8), InputError);  // horn torus
    EXPECT_THROW(geometry::makeTorus({0, 0, 0}, 1.0f, 0.0f, 8, 8), InputError);
    EXPECT_THROW(geometry::makeTorus({0, 0, 0}, 1.0f, 0.5f, 2, 8), InputError);
    EXPECT_THROW(geometry::makeTorus({0, 0, 0}, 1.0f, 0.5f, 8, 2), InputError);
    EXPECT_THROW(geometry::makeTorus({0, INFINITY, 0}, 1.0f, 0.5f, 8, 8), InputError);

    MeshData m = geometry::makeIcosphere({0, 0, 0}, 1.0f, 1);
    const MeshData before = m;
    EXPECT_THROW(geometry::displaceRadially(m, {0, 0, 0}, -0.1f, 1u), InputError);
    EXPECT_THROW(geometry::displaceRadially(m, {0, 0, 0}, NAN, 1u), InputError);
    // Amplitude reaching the centre could push a vertex through it.
    EXPECT_THROW(geometry::displaceRadially(m, {0, 0, 0}, 1.0f, 1u), InputError);
    EXPECT_THROW(geometry::displaceRadially(m, {0.9f, 0, 0}, 0.2f, 1u), InputError);
    EXPECT_EQ(m.positions, before.positions); // a rejected call changes nothing
}

} // namespace
