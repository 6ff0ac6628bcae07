// Hard shadow-volume geometry (geometry/shadow/ShadowVolume.h): facing, edge multiplicities, closure and
// orientation of the volumes, and the property everything rests on: the signed crossing count of
// the volume along any ray from P equals the number of triangles between P and the light, for
// closed, open and non-manifold meshes alike.
#include "geometry/TestMeshes.h"
#include "TestRandom.h"

#include <geometry/scene/GltfLoader.h>
#include <geometry/shadow/ShadowVolume.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <map>
#include <random>

namespace geometry {
namespace {

// --- Meshes --------------------------------------------------------------------------------------

using testmeshes::cube;
using testmeshes::edgeFan;
using testmeshes::quad;

// Closed, non-convex "blob": a UV sphere with jittered radii.
MeshData blob(std::mt19937& rng, int segments = 10, int rings = 6) {
    std::uniform_real_distribution<float> radius(0.6f, 1.4f);
    return testmeshes::uvSphere(segments, rings, [&] { return radius(rng); });
}

// Independent random triangles (they may intersect each other).
MeshData soup(std::mt19937& rng, int count) {
    std::uniform_real_distribution<float> coord(-1.5f, 1.5f);
    MeshData mesh;
    for (int i = 0; i < count; ++i) {
        for (int k = 0; k < 3; ++k)
            mesh.positions.push_back({coord(rng), coord(rng), coord(rng)});
        const auto b = static_cast<std::uint32_t>(3 * i);
        mesh.triangles.emplace_back(b, b + 1, b + 2);
    }
    return mesh;
}

// Random triangles over a small vertex pool: many edges with 3+ uses in random orientations.
MeshData pooledSoup(std::mt19937& rng, int poolSize, int count) {
    std::uniform_real_distribution<float> coord(-1.5f, 1.5f);
    std::uniform_int_distribution<std::uint32_t> pick(0, static_cast<std::uint32_t>(poolSize) - 1);
    MeshData mesh;
    for (int i = 0; i < poolSize; ++i)
        mesh.positions.push_back({coord(rng), coord(rng), coord(rng)});
    while (static_cast<int>(mesh.triangles.size()) < count) {
        const glm::uvec3 t(pick(rng), pick(rng), pick(rng));
        if (t.x != t.y && t.y != t.z && t.z != t.x) mesh.triangles.push_back(t);
    }
    return mesh;
}

// --- Helpers -------------------------------------------------------------------------------------

std::vector<std::int32_t> multiplicities(const Topology& topo, const glm::vec3& light) {
    std::vector<std::int8_t> facing(topo.triangles().size());
    classifyFacing(topo, light, facing);
    std::vector<std::int32_t> m(topo.edges().size());
    edgeMultiplicities(topo, facing, m);
    return m;
}

std::size_t findEdge(const Topology& topo, std::uint32_t a, std::uint32_t b) {
    const auto edges = topo.edges();
    for (std::size_t e = 0; e < edges.size(); ++e) {
        if (edges[e].v0 == std::min(a, b) && edges[e].v1 == std::max(a, b)) return e;
    }
    ADD_FAILURE() << "no edge " << a << "-" << b;
    return 0;
}

// The volume as a 2-chain has no boundary: every directed edge u -> v (vertices compared
// bit-exactly, w included) is matched by as many v -> u.
void expectClosed(const ShadowVolumeGeometry& volume) {
    using Key = std::array<float, 4>;
    const auto key = [](const glm::vec4& v) { return Key{v.x, v.y, v.z, v.w}; };
    std::map<std::pair<Key, Key>, int> directed;
    ASSERT_EQ(volume.vertices.size() % 3, 0u);
    for (std::size_t i = 0; i < volume.vertices.size(); i += 3) {
        for (int k = 0; k < 3; ++k) {
            const Key a = key(volume.vertices[i + k]), b = key(volume.vertices[i + (k + 1) % 3]);
            ++directed[{a, b}];
            --directed[{b, a}];
        }
    }
    std::size_t unmatched = 0;
    for (const auto& [edge, count] : directed)
        unmatched += count != 0;
    EXPECT_EQ(unmatched, 0u) << "the volume has open edges";
}

// Infinite vertices made finite: light + k * (x - light).
glm::dvec3 finite(const glm::vec4& v, const glm::vec3& light, double k) {
    return v.w != 0.0f ? glm::dvec3(v) / static_cast<double>(v.w)
                       : glm::dvec3(light) + k * glm::dvec3(v);
}

double det3(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c) {
    return glm::dot(a, glm::cross(b, c));
}

double det4(const glm::dvec4& a, const glm::dvec4& b, const glm::dvec4& c, const glm::dvec4& d) {
    return glm::determinant(glm::dmat4(a, b, c, d));
}

// Outcome of a crossing count: a value, or a tie (some test too close to zero to trust).
struct Count {
    int value = 0;
    bool tie = false;
};

// Signed crossing count of the (homogeneous) volume along the ray P + t*D, t in [0, inf].
//
// Exact for infinite geometry, in oriented projective terms: the ray is the set of positive
// combinations of P~ = (P, 1) and D~ = (D, 0); a triangle with vertices (x, w), w in {0, 1}, is the
// set of positive combinations of its vertices (for (a, b, c∞) the strip, for (q, p∞, q∞) the
// wedge it stands for). The ray meets it iff det(P~,ABC) and det(D~,ABC) have opposite signs and
// det(P~,D~,A,B), det(P~,D~,B,C), det(P~,D~,C,A) agree; the crossing counts -sign det(P~,ABC)
// (+1 leaving through a face whose normal points along D). A triangle entirely at infinity (back
// cap) is reached at the ray's end: it counts sign det(U,V,W) if D lies inside the cone of its
// directions U, V, W. The result is the winding number of P: the number of (light-oriented)
// triangles whose shadow frustum contains P.
Count volumeCrossings(const ShadowVolumeGeometry& volume, const glm::dvec3& p,
                      const glm::dvec3& d) {
    constexpr double kRelEps = 1e-10;
    Count count;
    const glm::dvec4 pt(p, 1.0), dt(d, 0.0);
    for (std::size_t i = 0; i < volume.vertices.size(); i += 3) {
        const glm::dvec4 a(volume.vertices[i]), b(volume.vertices[i + 1]),
            c(volume.vertices[i + 2]);
        if (a.w == 0.0 && b.w == 0.0 && c.w == 0.0) {
            const glm::dvec3 u(a), v(b), w(c);
            const double scale = glm::length(u) * glm::length(v) * glm::length(w);
            const double det = det3(u, v, w);
            if (std::abs(det) <= kRelEps * scale) continue; // flat cone: never strictly inside
            const double s = det > 0 ? 1.0 : -1.0;
            const double alpha = s * det3(d, v, w), beta = s * det3(u, d, w),
                         gamma = s * det3(u, v, d);
            const double eps = kRelEps * scale * 10.0;
            if (std::abs(alpha) < eps || std::abs(beta) < eps || std::abs(gamma) < eps) {
                count.tie = true;
                continue;
            }
            if (alpha > 0 && beta > 0 && gamma > 0) count.value += static_cast<int>(s);
            continue;
        }
        // Plane of the triangle: det(X, A, B, C) = dot(plane, X).
        glm::dvec4 plane;
        for (int j = 0; j < 4; ++j) {
            glm::dvec4 e(0.0);
            e[j] = 1.0;
            plane[j] = det4(e, a, b, c);
        }
        const double scale = glm::length(a) * glm::length(b) * glm::length(c);
        if (glm::length(plane) <= kRelEps * scale) continue; // degenerate: covers nothing
        const double s0 = glm::dot(plane, pt), s1 = glm::dot(plane, dt);
        const double eps0 = kRelEps * scale * glm::length(pt), eps1 = kRelEps * scale;
        if (std::abs(s0) < eps0 || std::abs(s1) < eps1) {
            count.tie = true;
            continue;
        }
        if ((s0 > 0) == (s1 > 0)) continue;
        const double e0 = det4(pt, dt, a, b), e1 = det4(pt, dt, b, c), e2 = det4(pt, dt, c, a);
        const double epsE = kRelEps * glm::length(pt) * scale;
        if (std::abs(e0) < epsE || std::abs(e1) < epsE || std::abs(e2) < epsE) {
            count.tie = true;
            continue;
        }
        if ((e0 > 0) == (e1 > 0) && (e1 > 0) == (e2 > 0)) count.value += s0 > 0 ? -1 : 1;
    }
    return count;
}

// Brute force: mesh triangles that the open segment P -> light crosses.
Count trianglesBetween(const Topology& topo, const glm::dvec3& p, const glm::dvec3& light) {
    constexpr double kRelEps = 1e-9;
    Count count;
    for (const glm::uvec3& tri : topo.triangles()) {
        const glm::dvec3 a(topo.positions()[tri.x]), b(topo.positions()[tri.y]),
            c(topo.positions()[tri.z]);
        const double scale = glm::length(b - a) * glm::length(c - a);
        const double sp = det3(a - p, b - p, c - p), sl = det3(a - light, b - light, c - light);
        const double epsP = kRelEps * scale * glm::length(a - p);
        if (std::abs(sp) < epsP) {
            count.tie = true;
            continue;
        }
        if (sl == 0.0) continue; // light in the plane: the segment only touches it at the light
        if ((sp > 0) == (sl > 0)) continue;
        const glm::dvec3 pl = light - p;
        const double e0 = det3(pl, a - p, b - p), e1 = det3(pl, b - p, c - p),
                     e2 = det3(pl, c - p, a - p);
        const double epsE = kRelEps * glm::length(pl) * scale * glm::length(a - p);
        if (std::abs(e0) < epsE || std::abs(e1) < epsE || std::abs(e2) < epsE) {
            count.tie = true;
            continue;
        }
        if ((e0 > 0) == (e1 > 0) && (e1 > 0) == (e2 > 0)) ++count.value;
    }
    return count;
}

// Whether the light is too close to some triangle's plane for the brute force to be trusted
// (those frusta are slivers; the exact in-plane case has its own test).
bool lightNearPlanes(const Topology& topo, const glm::dvec3& light) {
    for (const glm::uvec3& tri : topo.triangles()) {
        const glm::dvec3 a(topo.positions()[tri.x]), b(topo.positions()[tri.y]),
            c(topo.positions()[tri.z]);
        const glm::dvec3 n = glm::normalize(glm::cross(b - a, c - a));
        if (std::abs(glm::dot(n, light - a)) < 1e-3) return true;
    }
    return false;
}

struct PropertyStats {
    int checked = 0, ties = 0, shadowed = 0, multiplyShadowed = 0;
};

// Checks the point-in-volume property for one mesh and one light at `queries` points: half
// uniform in a box, half behind random triangles (so that shadowed points are well represented).
void checkPointInVolume(const Topology& topo, const glm::vec3& light, std::mt19937& rng,
                        int queries, PropertyStats& stats, const std::string& what) {
    ShadowVolumeGeometry volume;
    appendHardShadowVolume(topo, light, volume);
    std::uniform_real_distribution<double> box(-4.0, 4.0), unit(0.0, 1.0), behind(1.05, 3.0);
    std::uniform_int_distribution<std::size_t> pickTri(0, topo.triangles().size() - 1);
    const glm::dvec3 l(light);
    for (int q = 0, attempts = 0; q < queries && attempts < 20 * queries; ++attempts) {
        glm::dvec3 p;
        if (attempts % 2 == 0) {
            p = glm::dvec3(box(rng), box(rng), box(rng));
        } else {
            const glm::uvec3 tri = topo.triangles()[pickTri(rng)];
            double s = unit(rng), t = unit(rng);
            if (s + t > 1.0) s = 1.0 - s, t = 1.0 - t;
            const glm::dvec3 a(topo.positions()[tri.x]), b(topo.positions()[tri.y]),
                c(topo.positions()[tri.z]);
            const glm::dvec3 x = a + s * (b - a) + t * (c - a);
            p = l + behind(rng) * (x - l);
        }
        const Count expected = trianglesBetween(topo, p, l);
        const Count actual = volumeCrossings(volume, p, testutil::gaussianDirection(rng));
        if (expected.tie || actual.tie) {
            ++stats.ties;
            continue;
        }
        ++q;
        ++stats.checked;
        stats.shadowed += expected.value > 0;
        stats.multiplyShadowed += expected.value > 1;
        ASSERT_EQ(actual.value, expected.value)
            << what << ": light (" << light.x << ", " << light.y << ", " << light.z << "), P ("
            << p.x << ", " << p.y << ", " << p.z << ")";
    }
}

// --- Tests ---------------------------------------------------------------------------------------

TEST(ShadowVolume, FacingFollowsTheLightSide) {
    const Topology topo(quad());
    std::vector<std::int8_t> facing(2);
    classifyFacing(topo, {0.3f, 0.2f, 2.0f}, facing);
    EXPECT_EQ(facing[0], 1);
    EXPECT_EQ(facing[1], 1);
    classifyFacing(topo, {0.3f, 0.2f, -2.0f}, facing);
    EXPECT_EQ(facing[0], -1);
    EXPECT_EQ(facing[1], -1);
    classifyFacing(topo, {5.0f, 0.2f, 0.0f}, facing); // in the plane: +1 by the >= rule
    EXPECT_EQ(facing[0], 1);
    EXPECT_EQ(facing[1], 1);
    std::vector<std::int8_t> wrongSize(3);
    EXPECT_THROW(classifyFacing(topo, {0, 0, 1}, wrongSize), std::invalid_argument);
}

TEST(ShadowVolume, ClosedCubeMultiplicitiesCancelInside) {
    const Topology topo(cube());
    ASSERT_EQ(topo.manifoldness(), Manifoldness::Closed);
    for (const glm::vec3 light :
         {glm::vec3(3, 5, 2), glm::vec3(0.5f, 4, 0.2f), glm::vec3(-7, 1.5f, -3)}) {
        std::vector<std::int8_t> facing(topo.triangles().size());
        classifyFacing(topo, light, facing);
        const std::vector<std::int32_t> m = multiplicities(topo, light);
        std::vector<int> outDegree(topo.positions().size()), inDegree(topo.positions().size());
        int silhouette = 0;
        for (std::size_t e = 0; e < m.size(); ++e) {
            const std::uint32_t u = topo.edgeUseOffsets()[e];
            const std::uint32_t t0 = topo.edgeUses()[u].triangle,
                                t1 = topo.edgeUses()[u + 1].triangle;
            // Two-sided rule: the flipped back faces cast too, so a silhouette edge of a closed
            // mesh separates a light-facing and a flipped triangle and gets |m| = 2 (points
            // behind the cube are behind two of its triangles).
            if (facing[t0] == facing[t1]) {
                EXPECT_EQ(m[e], 0) << "interior edge " << e;
            } else {
                EXPECT_EQ(std::abs(m[e]), 2) << "silhouette edge " << e;
            }
            if (m[e] == 0) continue;
            ++silhouette;
            const Edge edge = topo.edges()[e];
            const std::uint32_t p = m[e] > 0 ? edge.v0 : edge.v1, q = m[e] > 0 ? edge.v1 : edge.v0;
            ++outDegree[p];
            ++inDegree[q];
        }
        EXPECT_GE(silhouette, 4);
        // The directed silhouette edges of a closed mesh form closed loops.
        EXPECT_EQ(inDegree, outDegree);
        ShadowVolumeGeometry volume;
        appendHardShadowVolume(topo, light, volume);
        EXPECT_EQ(volume.silhouetteEdges, static_cast<std::size_t>(silhouette));
        EXPECT_EQ(volume.sideTriangles, 4u * silhouette);
        EXPECT_EQ(volume.capTriangles, 24u);
        EXPECT_EQ(volume.vertices.size(), 3 * (volume.capTriangles + volume.sideTriangles));
        expectClosed(volume);
    }
}

TEST(ShadowVolume, QuadBoundaryEdgesHaveMultiplicityOne) {
    const Topology topo(quad());
    for (const float z : {3.0f, -3.0f}) { // from either side: a two-sided occluder
        const glm::vec3 light(0.4f, -0.3f, z);
        const std::vector<std::int32_t> m = multiplicities(topo, light);
        ASSERT_EQ(m.size(), 5u);
        EXPECT_EQ(m[findEdge(topo, 0, 2)], 0); // the diagonal
        const std::array<std::pair<std::uint32_t, std::uint32_t>, 4> outline = {
            {{0, 1}, {1, 2}, {2, 3}, {0, 3}}};
        for (const auto& [a, b] : outline) {
            EXPECT_EQ(std::abs(m[findEdge(topo, a, b)]), 1) << a << "-" << b;
        }
        ShadowVolumeGeometry volume;
        appendHardShadowVolume(topo, light, volume);
        EXPECT_EQ(volume.silhouetteEdges, 4u);
        EXPECT_EQ(volume.sideTriangles, 8u);
        expectClosed(volume);
    }
}

TEST(ShadowVolume, FoldedQuadSharedEdgeHasMultiplicityTwo) {
    // Two consistently oriented triangles sharing B-C, folded like a book closing: one faces the
    // light, the other is flipped, so both light-oriented triangles run the edge the same way.
    MeshData mesh;
    mesh.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0.2f, 0.2f, 1}};
    mesh.triangles = {{0, 1, 2}, {2, 1, 3}};
    const Topology topo(mesh);
    ASSERT_EQ(topo.manifoldness(), Manifoldness::Open);
    const glm::vec3 light(0.3f, 0.3f, 5);
    std::vector<std::int8_t> facing(2);
    classifyFacing(topo, light, facing);
    ASSERT_EQ(facing[0], 1);
    ASSERT_EQ(facing[1], -1);
    const std::vector<std::int32_t> m = multiplicities(topo, light);
    EXPECT_EQ(std::abs(m[findEdge(topo, 1, 2)]), 2);
    ShadowVolumeGeometry volume;
    appendHardShadowVolume(topo, light, volume);
    EXPECT_EQ(volume.silhouetteEdges, 5u);
    EXPECT_EQ(volume.sideTriangles, 2u * (4 + 2));
    expectClosed(volume);
}

TEST(ShadowVolume, FanOnOneEdgeSumsAllUses) {
    for (const int count : {3, 4, 5}) {
        const Topology topo(edgeFan(count));
        ASSERT_EQ(topo.stats().nonManifoldEdges, 1u);
        std::mt19937 rng(11 + count);
        std::uniform_real_distribution<float> coord(-3.0f, 3.0f);
        for (int trial = 0; trial < 20; ++trial) {
            const glm::vec3 light(coord(rng), coord(rng), coord(rng));
            std::vector<std::int8_t> facing(topo.triangles().size());
            classifyFacing(topo, light, facing);
            const std::vector<std::int32_t> m = multiplicities(topo, light);
            // Edge (0,1): triangle i uses it as 0 -> 1 (+1) for even i, 1 -> 0 (-1) for odd i.
            int expected = 0;
            for (int i = 0; i < count; ++i)
                expected += (i % 2 ? -1 : 1) * facing[i];
            const int shared = m[findEdge(topo, 0, 1)];
            EXPECT_EQ(shared, expected);
            EXPECT_EQ(std::abs(shared) % 2, count % 2); // a sum of `count` terms of +-1
            EXPECT_LE(std::abs(shared), count);
            ShadowVolumeGeometry volume;
            appendHardShadowVolume(topo, light, volume);
            expectClosed(volume);
        }
    }
}

TEST(ShadowVolume, SingleTriangleVolumeIsClosedAndOutward) {
    MeshData mesh;
    mesh.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    mesh.triangles = {{0, 1, 2}};
    const Topology topo(mesh);
    constexpr double k = 100.0; // far points light + k (x - light)
    for (const glm::vec3 light : {glm::vec3(0.2f, 0.2f, 1.0f), glm::vec3(0.2f, 0.3f, -2.0f),
                                  glm::vec3(-3.0f, 2.0f, 0.5f)}) {
        ShadowVolumeGeometry volume;
        appendHardShadowVolume(topo, light, volume);
        EXPECT_EQ(volume.capTriangles, 2u);
        EXPECT_EQ(volume.sideTriangles, 6u);
        EXPECT_EQ(volume.silhouetteEdges, 3u);
        expectClosed(volume);
        // Finite version: a truncated pyramid (frustum) between the triangle and k times it.
        std::vector<glm::dvec3> v;
        for (const glm::vec4& x : volume.vertices)
            v.push_back(finite(x, light, k));
        glm::dvec3 centroid(0.0);
        for (const glm::dvec3& x : v)
            centroid += x / static_cast<double>(v.size());
        double signedVolume = 0.0;
        for (std::size_t i = 0; i < v.size(); i += 3) {
            signedVolume += det3(v[i], v[i + 1], v[i + 2]) / 6.0;
            // Convex: every outward face has the centroid behind it.
            const glm::dvec3 n = glm::cross(v[i + 1] - v[i], v[i + 2] - v[i]);
            EXPECT_LT(glm::dot(n, centroid - v[i]), 0.0) << "face " << i / 3 << " faces inward";
        }
        const double height = std::abs(static_cast<double>(light.z)); // triangle in z = 0
        const double pyramid = 0.5 /* area */ * height / 3.0;
        // Relative 1e-6: the vertices are floats (x - light is rounded to float).
        EXPECT_NEAR(signedVolume, (k * k * k - 1.0) * pyramid, 1e-6 * k * k * k * pyramid);
    }
}

TEST(ShadowVolume, LightInTrianglePlaneGivesFlatClosedVolume) {
    const Topology topo(quad());
    const glm::vec3 light(3.0f, 0.4f, 0.0f);
    ShadowVolumeGeometry volume;
    appendHardShadowVolume(topo, light, volume);
    expectClosed(volume);
    double signedVolume = 0.0;
    for (std::size_t i = 0; i < volume.vertices.size(); i += 3) {
        signedVolume += det3(finite(volume.vertices[i], light, 50.0),
                             finite(volume.vertices[i + 1], light, 50.0),
                             finite(volume.vertices[i + 2], light, 50.0)) /
                        6.0;
    }
    EXPECT_NEAR(signedVolume, 0.0, 1e-6);
    // Nothing is in the shadow of an edge-on quad; and a cube lit in the plane of its top face
    // still counts right everywhere.
    std::mt19937 rng(5);
    PropertyStats stats;
    checkPointInVolume(topo, light, rng, 200, stats, "edge-on quad");
    checkPointInVolume(Topology(cube()), {3.0f, 1.0f, 0.5f}, rng, 400, stats, "cube, top plane");
    EXPECT_GT(stats.shadowed, 50);
}

TEST(ShadowVolume, PointInVolumeProperty) {
    // The property everything rests on (DESIGN.md §4), on every kind of mesh: the winding number
    // of the generated geometry at P is the number of triangles between P and the light.
    std::mt19937 rng(20240607);
    struct Case {
        std::string name;
        MeshData mesh;
    };
    std::vector<Case> cases;
    cases.push_back({"cube", cube()});
    cases.push_back({"blob", blob(rng)});
    cases.push_back({"quad", quad(0.5f)});
    cases.push_back({"open box", cube(/*skipFace=*/3)});
    cases.push_back({"fan of 3", edgeFan(3)});
    cases.push_back({"fan of 5", edgeFan(5)});
    cases.push_back({"soup", soup(rng, 12)});
    cases.push_back({"pooled soup", pooledSoup(rng, 7, 16)});
    { // A cube with one face flipped: closed but inconsistently oriented.
        MeshData flipped = cube();
        std::swap(flipped.triangles[5].y, flipped.triangles[5].z);
        cases.push_back({"flipped-face cube", flipped});
    }
    std::uniform_real_distribution<float> coord(-3.0f, 3.0f);
    PropertyStats stats;
    for (const Case& c : cases) {
        const Topology topo(c.mesh);
        for (int l = 0; l < 12; ++l) {
            glm::vec3 light(coord(rng), coord(rng), coord(rng));
            while (lightNearPlanes(topo, glm::dvec3(light))) {
                light = glm::vec3(coord(rng), coord(rng), coord(rng));
            }
            checkPointInVolume(topo, light, rng, 60, stats, c.name);
            if (HasFatalFailure()) return;
        }
    }
    std::printf("[ property ] %d points checked (%d shadowed, %d by 2+ triangles), %d ties "
                "redrawn\n",
                stats.checked, stats.shadowed, stats.multiplyShadowed, stats.ties);
    EXPECT_EQ(stats.checked, static_cast<int>(cases.size()) * 12 * 60);
    EXPECT_GT(stats.shadowed, stats.checked / 10);
    EXPECT_GT(stats.multiplyShadowed, stats.checked / 20);
    EXPECT_LT(stats.ties, stats.checked / 10);
}

TEST(ShadowVolume, AppendKeepsEarlierContent) {
    const Topology topo(quad());
    ShadowVolumeGeometry volume;
    appendHardShadowVolume(topo, {0, 0, 3}, volume);
    const std::vector<glm::vec4> first = volume.vertices;
    appendHardShadowVolume(topo, {0, 0, 3}, volume);
    ASSERT_EQ(volume.vertices.size(), 2 * first.size());
    EXPECT_TRUE(std::equal(first.begin(), first.end(), volume.vertices.begin()));
    EXPECT_TRUE(std::equal(first.begin(), first.end(), volume.vertices.begin() + first.size()));
    EXPECT_EQ(volume.capTriangles, 8u);
    EXPECT_EQ(volume.silhouetteEdges, 8u);
    volume.clear();
    EXPECT_TRUE(volume.vertices.empty());
    EXPECT_EQ(volume.capTriangles + volume.sideTriangles + volume.silhouetteEdges, 0u);
}

TEST(ShadowVolume, GameLevelVolumeIsClosed) {
    const std::filesystem::path level =
        std::filesystem::path(PENUMBRA_SHARED_DIR) / "levels" / "oa_dm1.glb";
    ASSERT_TRUE(std::filesystem::exists(level))
        << "missing " << level << " (../shared must be beside the repo)";
    const Topology topo(loadGltf(level));
    Aabb bounds;
    for (const glm::vec3& p : topo.positions())
        bounds.extend(p);
    ShadowVolumeGeometry volume;
    appendHardShadowVolume(topo, bounds.center() + glm::vec3(0.37f, 2.1f, -0.23f), volume);
    std::printf("[ level    ] oa_dm1 volume: %zu cap + %zu side triangles, %zu silhouette edges\n",
                volume.capTriangles, volume.sideTriangles, volume.silhouetteEdges);
    EXPECT_GE(volume.silhouetteEdges, topo.stats().boundaryEdges); // those always have |m| = 1
    expectClosed(volume);
}

// An open 100k-triangle height field (testmeshes::heightField): the two-sided rule caps every
// triangle twice, whatever the light. The cost per light sample is geometry_bench's
// shadow_volume/height_field_100k (the reference method calls this up to 1024 times per image).
TEST(ShadowVolume, LargeOpenHeightFieldCapsEveryTriangleTwice) {
    const Topology topo(testmeshes::heightField(224));
    ShadowVolumeGeometry volume;
    for (int run = 0; run < 15; ++run) {
        volume.clear();
        const glm::vec3 light(0.5f + 0.01f * static_cast<float>(run), 1.0f, 0.4f);
        appendHardShadowVolume(topo, light, volume);
        EXPECT_EQ(volume.capTriangles, 2 * topo.triangles().size()) << "light " << run;
    }
}

} // namespace
} // namespace geometry
