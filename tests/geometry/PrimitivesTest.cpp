#include <geometry/Error.h>
#include <geometry/Primitives.h>

#include <gtest/gtest.h>

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

} // namespace
