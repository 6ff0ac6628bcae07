// Simplified stand-ins (geometry/shadow/Simplify.h): the vertices removed stay within the
// tolerance of the new surface, kept vertices do not move, closed meshes stay closed, what cannot
// be simplified is left alone with its reason, and bad options are refused.
#include "TestErrors.h"

#include <geometry/core/Error.h>
#include <geometry/scene/Primitives.h>
#include <geometry/scene/Scene.h>
#include <geometry/shadow/Simplify.h>
#include <geometry/shadow/Topology.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <tuple>

namespace geometry {
namespace {

// Distance from p to triangle abc (closest point by the triangle's Voronoi regions).
double pointTriangleDistance(glm::dvec3 p, glm::dvec3 a, glm::dvec3 b, glm::dvec3 c) {
    const glm::dvec3 ab = b - a, ac = c - a, ap = p - a;
    const double d1 = glm::dot(ab, ap), d2 = glm::dot(ac, ap);
    if (d1 <= 0 && d2 <= 0) return glm::length(p - a);
    const glm::dvec3 bp = p - b;
    const double d3 = glm::dot(ab, bp), d4 = glm::dot(ac, bp);
    if (d3 >= 0 && d4 <= d3) return glm::length(p - b);
    const double vc = d1 * d4 - d3 * d2;
    if (vc <= 0 && d1 >= 0 && d3 <= 0) return glm::length(p - (a + ab * (d1 / (d1 - d3))));
    const glm::dvec3 cp = p - c;
    const double d5 = glm::dot(ab, cp), d6 = glm::dot(ac, cp);
    if (d6 >= 0 && d5 <= d6) return glm::length(p - c);
    const double vb = d5 * d2 - d1 * d6;
    if (vb <= 0 && d2 >= 0 && d6 <= 0) return glm::length(p - (a + ac * (d2 / (d2 - d6))));
    const double va = d3 * d6 - d5 * d4;
    if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0)
        return glm::length(p - (b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)))));
    const double denom = 1.0 / (va + vb + vc);
    return glm::length(p - (a + ab * (vb * denom) + ac * (vc * denom)));
}

// The largest distance from a vertex of `from` to the surface of `to` (brute force).
double largestVertexDistance(const MeshData& from, const MeshData& to) {
    double worst = 0.0;
    for (const glm::vec3& p : from.positions) {
        double best = std::numeric_limits<double>::infinity();
        for (const glm::uvec3& t : to.triangles)
            best = std::min(best, pointTriangleDistance(p, to.positions[t.x], to.positions[t.y],
                                                        to.positions[t.z]));
        worst = std::max(worst, best);
    }
    return worst;
}

TEST(Simplify, ASphereKeepsItsShapeWithinTheToleranceAndStaysClosed) {
    MeshData sphere = makeSphere({0, 1, 0}, 0.5f, 96);
    for (const glm::vec3& p : sphere.positions)
        sphere.normals.push_back(glm::normalize(p - glm::vec3(0, 1, 0)));
    const float tolerance = 0.002f;
    const SimplifiedMesh s = simplifyMesh(sphere, {tolerance});
    ASSERT_TRUE(s.skipped.empty()) << s.skipped;
    // A 96-segment sphere is far finer than 2 mm at r = 0.5 needs (about 30 segments).
    EXPECT_LT(s.mesh.triangles.size(), sphere.triangles.size() / 4)
        << sphere.triangles.size() << " -> " << s.mesh.triangles.size();
    EXPECT_GT(s.mesh.triangles.size(), 200u);
    const Topology topo(s.mesh);
    EXPECT_EQ(topo.manifoldness(), Manifoldness::Closed);
    EXPECT_EQ(topo.stats().degenerateTriangles, 0u);
    // The bound the decimater keeps (on the removed vertices), checked independently; float
    // rounding of the distances is far below the 1e-5 slack.
    EXPECT_LE(largestVertexDistance(sphere, s.mesh), tolerance + 1e-5);
    // Kept vertices did not move (on the sphere), and kept their (radial) normals.
    ASSERT_EQ(s.mesh.normals.size(), s.mesh.positions.size());
    for (std::size_t i = 0; i < s.mesh.positions.size(); ++i) {
        const glm::vec3 d = s.mesh.positions[i] - glm::vec3(0, 1, 0);
        EXPECT_NEAR(glm::length(d), 0.5f, 1e-5f);
        EXPECT_GT(glm::dot(s.mesh.normals[i], glm::normalize(d)), 0.999f) << i;
    }
    // Outward winding survives: the signed volume is still that of a (slightly smaller) ball.
    double volume = 0.0;
    for (const glm::uvec3& t : s.mesh.triangles)
        volume += glm::dot(glm::dvec3(s.mesh.positions[t.x]) - glm::dvec3(0, 1, 0),
                           glm::cross(glm::dvec3(s.mesh.positions[t.y]) - glm::dvec3(0, 1, 0),
                                      glm::dvec3(s.mesh.positions[t.z]) - glm::dvec3(0, 1, 0))) /
                  6.0;
    const double ball = 4.0 / 3.0 * 3.14159265358979 * 0.125;
    EXPECT_GT(volume, 0.97 * ball);
    EXPECT_LT(volume, ball);
}

TEST(Simplify, ASmallerToleranceKeepsMoreTriangles) {
    const MeshData torus = makeTorus({0, 0, 0}, 1.0f, 0.3f, 96, 48);
    std::size_t previous = 0;
    for (float tolerance : {0.02f, 0.005f, 0.001f}) {
        const SimplifiedMesh s = simplifyMesh(torus, {tolerance});
        ASSERT_TRUE(s.skipped.empty()) << s.skipped;
        EXPECT_GT(s.mesh.triangles.size(), previous) << tolerance;
        EXPECT_LE(s.mesh.triangles.size(), torus.triangles.size());
        EXPECT_EQ(Topology(s.mesh).manifoldness(), Manifoldness::Closed) << tolerance;
        EXPECT_LE(largestVertexDistance(torus, s.mesh), tolerance + 1e-5) << tolerance;
        previous = s.mesh.triangles.size();
    }
}

TEST(Simplify, AMeshWithNothingBelowTheToleranceIsUnchanged) {
    // A box's corners are all needed: any collapse moves a corner by the box's size.
    const MeshData box = makeBox({0, 0, 0}, {1, 2, 3});
    const SimplifiedMesh s = simplifyMesh(box, {0.01f});
    ASSERT_TRUE(s.skipped.empty()) << s.skipped;
    EXPECT_EQ(s.mesh.triangles.size(), box.triangles.size());
    EXPECT_EQ(Topology(s.mesh).manifoldness(), Manifoldness::Closed);
    // Tiny meshes are not touched at all.
    const MeshData quad = makeQuad({0, 0, 0}, {1, 0, 0}, {0, 0, 1});
    const SimplifiedMesh q = simplifyMesh(quad, {10.0f});
    EXPECT_TRUE(q.skipped.empty());
    EXPECT_EQ(q.mesh.triangles.size(), 2u);
}

TEST(Simplify, CreasesLoseTheirVertexNormalsAndSmoothVerticesKeepThem) {
    // A finely split flat square with one smooth normal everywhere, folded along x = 0 into a
    // roof: vertices on the fold carry two normals (a crease), the others one.
    MeshData roof;
    const int n = 16;
    for (int side = 0; side < 2; ++side) {
        const glm::vec3 normal = glm::normalize(glm::vec3(side == 0 ? -1 : 1, 1, 0));
        const auto base = static_cast<std::uint32_t>(roof.positions.size());
        for (int j = 0; j <= n; ++j)
            for (int i = 0; i <= n; ++i) {
                const float x = (side == 0 ? -1.0f : 1.0f) * float(i) / n; // i = 0 on the fold
                roof.positions.emplace_back(x, 1.0f - std::abs(x), float(j) / n);
                roof.normals.push_back(normal);
            }
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i) {
                const std::uint32_t a = base + j * (n + 1) + i, b = a + 1, c = a + (n + 1), d = c + 1;
                if (side == 0) {
                    roof.triangles.emplace_back(a, c, b);
                    roof.triangles.emplace_back(b, c, d);
                } else {
                    roof.triangles.emplace_back(a, b, c);
                    roof.triangles.emplace_back(b, d, c);
                }
            }
    }
    const SimplifiedMesh s = simplifyMesh(roof, {0.001f});
    ASSERT_TRUE(s.skipped.empty()) << s.skipped;
    EXPECT_LT(s.mesh.triangles.size(), roof.triangles.size() / 4);
    EXPECT_LE(largestVertexDistance(roof, s.mesh), 0.001 + 1e-5);
    ASSERT_EQ(s.mesh.normals.size(), s.mesh.positions.size());
    int fold = 0;
    for (std::size_t i = 0; i < s.mesh.positions.size(); ++i) {
        const glm::vec3 p = s.mesh.positions[i];
        if (std::abs(p.x) < 1e-6f) {
            ++fold;
            EXPECT_EQ(s.mesh.normals[i], glm::vec3(0.0f)) << "fold vertex " << i;
        } else {
            EXPECT_NEAR(glm::length(s.mesh.normals[i]), 1.0f, 1e-5f) << i;
        }
    }
    EXPECT_GE(fold, 2); // the fold's two ends at least
}

TEST(Simplify, WhatCannotBeSimplifiedIsLeftAloneWithItsReason) {
    MeshData textured = makeSphere({0, 0, 0}, 1.0f, 32);
    textured.texcoords.assign(textured.positions.size(), glm::vec2(0.5f));
    SimplifiedMesh s = simplifyMesh(textured, {0.01f});
    EXPECT_NE(s.skipped.find("textured"), std::string::npos) << s.skipped;
    EXPECT_EQ(s.mesh.triangles.size(), textured.triangles.size());

    MeshData twoMaterials = makeSphere({0, 0, 0}, 1.0f, 32);
    twoMaterials.materials.resize(2);
    twoMaterials.triangleMaterial.assign(twoMaterials.triangles.size(), 0);
    twoMaterials.triangleMaterial.back() = 1;
    s = simplifyMesh(twoMaterials, {0.01f});
    EXPECT_NE(s.skipped.find("material"), std::string::npos) << s.skipped;

    // Three triangles on one edge (a fin on a fan).
    MeshData fin = makeSphere({0, 0, 0}, 1.0f, 16);
    const glm::uvec3 t = fin.triangles[40];
    fin.positions.emplace_back(3.0f, 3.0f, 3.0f);
    fin.triangles.emplace_back(t.x, t.y, static_cast<std::uint32_t>(fin.positions.size() - 1));
    s = simplifyMesh(fin, {0.01f});
    EXPECT_NE(s.skipped.find("non-manifold"), std::string::npos) << s.skipped;
    EXPECT_EQ(s.mesh.triangles.size(), fin.triangles.size());
}

TEST(Simplify, BadOptionsAreRefused) {
    const MeshData sphere = makeSphere({0, 0, 0}, 1.0f, 16);
    for (float bad : {0.0f, -0.1f, std::numeric_limits<float>::quiet_NaN(),
                      std::numeric_limits<float>::infinity()}) {
        const auto e = testutil::errorOf<InputError>([&] { simplifyMesh(sphere, {bad}); });
        ASSERT_TRUE(e.has_value()) << bad;
        EXPECT_NE(e->find("tolerance"), std::string::npos) << *e;
    }
    for (float bad : {0.0f, 181.0f, -5.0f, std::numeric_limits<float>::quiet_NaN()}) {
        const auto e = testutil::errorOf<InputError>([&] { simplifyMesh(sphere, {0.01f, bad}); });
        ASSERT_TRUE(e.has_value()) << bad;
        EXPECT_NE(e->find("normal"), std::string::npos) << *e;
    }
    for (float bad : {0.0f, 180.0f, -5.0f, std::numeric_limits<float>::quiet_NaN()}) {
        const auto e =
            testutil::errorOf<InputError>([&] { simplifyMesh(sphere, {0.01f, 180.0f, bad}); });
        ASSERT_TRUE(e.has_value()) << bad;
        EXPECT_NE(e->find("normal"), std::string::npos) << *e;
    }
}

TEST(Simplify, ANormalBoundKeepsTheSurfaceFacingWhereItFaced) {
    // Without a normal bound a 4 mm tolerance leaves 11-degree facets on a 0.5 sphere; with a
    // 2-degree bound every triangle's normal stays within 2 degrees of its corners' original
    // (radial) normals, which takes more triangles.
    const MeshData sphere = makeSphere({0, 0, 0}, 0.5f, 128);
    SimplifyOptions loose{0.004f};
    SimplifyOptions tight{0.004f, 2.0f};
    const SimplifiedMesh a = simplifyMesh(sphere, loose), b = simplifyMesh(sphere, tight);
    ASSERT_TRUE(a.skipped.empty() && b.skipped.empty());
    EXPECT_GT(b.mesh.triangles.size(), 2 * a.mesh.triangles.size())
        << a.mesh.triangles.size() << " vs " << b.mesh.triangles.size();
    auto worstDeviationDeg = [](const MeshData& m) {
        double worst = 0.0;
        for (const glm::uvec3& t : m.triangles) {
            const glm::dvec3 p0 = m.positions[t.x], p1 = m.positions[t.y], p2 = m.positions[t.z];
            const glm::dvec3 n = glm::normalize(glm::cross(p1 - p0, p2 - p0));
            for (const glm::dvec3& c : {p0, p1, p2})
                worst = std::max(worst, std::acos(std::clamp(glm::dot(n, glm::normalize(c)), -1.0, 1.0)));
        }
        return worst * 180.0 / 3.14159265358979;
    };
    // The original vertex normals are the area-weighted normals of the 128-segment sphere's
    // triangles (within 1 degree of radial), so the bound on radial normals is 2 + 1 degrees.
    EXPECT_LT(worstDeviationDeg(b.mesh), 3.0);
    EXPECT_GT(worstDeviationDeg(a.mesh), 4.0);
    EXPECT_LE(largestVertexDistance(sphere, b.mesh), 0.004 + 1e-5);
}

TEST(Simplify, BoundsFollowTheVisibilityErrorAndTheLight) {
    RectLight light;
    light.center = {0, 3, 0};
    light.u = {0.6f, 0, 0};
    light.v = {0, 0, 0.4f};
    Aabb bounds;
    bounds.extend(glm::vec3(-0.5f, 0.5f, -0.5f));
    bounds.extend(glm::vec3(0.5f, 1.5f, 0.5f));
    const SimplifyOptions o = simplifyOptionsFor(bounds, light, 0.02f);
    // Half of 0.02 times the smaller side (0.8).
    EXPECT_FLOAT_EQ(o.tolerance, 0.008f);
    // The light (0.8 across) from the farthest corner (0.5, 0.5, 0.5): 2.55 away.
    const double farthest = std::sqrt(0.25 + 6.25 + 0.25);
    const double alphaDeg = 2.0 * std::atan(0.4 / farthest) * 180.0 / 3.14159265358979;
    EXPECT_NEAR(o.maxNormalDeviationDeg, 0.02 * alphaDeg, 1e-4);
    // Twice the error, twice both bounds.
    const SimplifyOptions o2 = simplifyOptionsFor(bounds, light, 0.04f);
    EXPECT_FLOAT_EQ(o2.tolerance, 2.0f * o.tolerance);
    EXPECT_NEAR(o2.maxNormalDeviationDeg, 2.0f * o.maxNormalDeviationDeg, 1e-5);
    for (float bad : {0.0f, 1.0f, -0.1f, std::numeric_limits<float>::quiet_NaN()}) {
        const auto e = testutil::errorOf<InputError>([&] { simplifyOptionsFor(bounds, light, bad); });
        ASSERT_TRUE(e.has_value()) << bad;
        EXPECT_NE(e->find("visibility error"), std::string::npos) << *e;
    }
    RectLight flat = light;
    flat.v = glm::vec3(0.0f);
    EXPECT_TRUE(testutil::errorOf<InputError>([&] { simplifyOptionsFor(bounds, flat, 0.02f); }));
}

TEST(Simplify, ASceneCountsWhatItSimplifiedAndWhatItLeft) {
    Scene scene;
    // A big light close above: the light subtends about 57 degrees at the sphere's far corner, so
    // E = 0.1 allows 5.7-degree normal deviations (the 96-segment sphere's facets are 3.75).
    scene.light.center = {0, 2.2f, 0};
    scene.light.u = {1, 0, 0};
    scene.light.v = {0, 0, 1};
    scene.objects.push_back({"objects[0] (sphere)", ShadowMethod::Auto, makeSphere({0, 1, 0}, 0.5f, 96)});
    MeshData textured = makeSphere({2, 1, 0}, 0.5f, 32);
    textured.texcoords.assign(textured.positions.size(), glm::vec2(0.0f));
    scene.objects.push_back({"objects[1] (sphere)", ShadowMethod::Auto, textured});
    const std::size_t before = scene.objects[0].mesh.triangles.size();
    const SimplifyStats stats = simplifyScene(scene, 0.1f);
    EXPECT_EQ(stats.meshes, 1u);
    EXPECT_EQ(stats.skipped, 1u);
    EXPECT_EQ(stats.trianglesBefore, before);
    EXPECT_EQ(stats.trianglesAfter, scene.objects[0].mesh.triangles.size());
    EXPECT_LT(stats.trianglesAfter, before);
    EXPECT_NE(stats.firstSkipReason.find("objects[1]"), std::string::npos) << stats.firstSkipReason;
    EXPECT_EQ(scene.objects[1].mesh.triangles.size(), textured.triangles.size());
}

} // namespace
} // namespace geometry
