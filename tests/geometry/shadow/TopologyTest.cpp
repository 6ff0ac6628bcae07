// Welding, degenerate-triangle removal, edge/use arrays and manifold classification
// (geometry/shadow/Topology.h), on hand-built meshes and on a real game level.
#include "geometry/TestMeshes.h"

#include <geometry/core/Error.h>
#include <geometry/scene/GltfLoader.h>
#include <geometry/scene/Primitives.h>
#include <geometry/shadow/Topology.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <random>

namespace geometry {
namespace {

// Axis-aligned cube [-1, 1]^3 as glTF stores it: 4 own vertices per face (split by normal), two
// counter-clockwise outward triangles per face. `skipFace` (0..5) leaves one face out.
MeshData splitCube(int skipFace = -1) {
    struct Face {
        glm::vec3 n, u, v; // cross(u, v) == n
    };
    const Face faces[6] = {
        {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}, {{-1, 0, 0}, {0, 0, 1}, {0, 1, 0}},
        {{0, 1, 0}, {0, 0, 1}, {1, 0, 0}}, {{0, -1, 0}, {1, 0, 0}, {0, 0, 1}},
        {{0, 0, 1}, {1, 0, 0}, {0, 1, 0}}, {{0, 0, -1}, {0, 1, 0}, {1, 0, 0}},
    };
    MeshData mesh;
    mesh.name = "split-cube";
    for (int f = 0; f < 6; ++f) {
        if (f == skipFace) continue;
        const Face& face = faces[f];
        const auto base = static_cast<std::uint32_t>(mesh.positions.size());
        mesh.positions.push_back(face.n - face.u - face.v);
        mesh.positions.push_back(face.n + face.u - face.v);
        mesh.positions.push_back(face.n + face.u + face.v);
        mesh.positions.push_back(face.n - face.u + face.v);
        mesh.triangles.emplace_back(base, base + 1, base + 2);
        mesh.triangles.emplace_back(base, base + 2, base + 3);
    }
    return mesh;
}

// Unit square [0, 1]^2 facing +z, named "quad": corners (0,0) (1,0) (1,1) (0,1), triangles
// (0,1,2) (0,2,3), every coordinate exact.
MeshData quad() {
    return makeQuad({0.5f, 0.5f, 0.0f}, {0.5f, 0.0f, 0.0f}, {0.0f, 0.5f, 0.0f});
}

// Checks the internal consistency every Topology must have, whatever the input.
void expectConsistent(const Topology& topo) {
    const auto tris = topo.triangles();
    const auto edges = topo.edges();
    const auto offsets = topo.edgeUseOffsets();
    const auto uses = topo.edgeUses();
    const auto triEdges = topo.triangleEdges();
    ASSERT_EQ(offsets.size(), edges.size() + 1);
    ASSERT_EQ(uses.size(), 3 * tris.size());
    ASSERT_EQ(triEdges.size(), tris.size());
    ASSERT_EQ(topo.sourceTriangle().size(), tris.size());
    EXPECT_EQ(topo.stats().edges, edges.size());
    EXPECT_EQ(topo.stats().vertices, topo.positions().size());
    EXPECT_EQ(topo.stats().triangles, tris.size());
    for (std::size_t e = 0; e < edges.size(); ++e) {
        EXPECT_LT(edges[e].v0, edges[e].v1);
        if (e > 0) { // sorted, hence unique
            EXPECT_TRUE(edges[e - 1].v0 < edges[e].v0 ||
                        (edges[e - 1].v0 == edges[e].v0 && edges[e - 1].v1 < edges[e].v1));
        }
        EXPECT_LT(offsets[e], offsets[e + 1]) << "edge without uses";
        for (std::uint32_t u = offsets[e]; u < offsets[e + 1]; ++u) {
            const glm::uvec3 tri = tris[uses[u].triangle];
            bool found = false;
            for (int k = 0; k < 3; ++k) {
                if (tri[k] == edges[e].v0 && tri[(k + 1) % 3] == edges[e].v1) {
                    found = uses[u].sign == 1;
                }
                if (tri[k] == edges[e].v1 && tri[(k + 1) % 3] == edges[e].v0) {
                    found = uses[u].sign == -1;
                }
            }
            EXPECT_TRUE(found) << "edge " << e << " use " << u;
        }
    }
    for (std::size_t t = 0; t < tris.size(); ++t) {
        for (int k = 0; k < 3; ++k) {
            const Edge edge = edges[triEdges[t][k]];
            const std::uint32_t a = tris[t][k], b = tris[t][(k + 1) % 3];
            EXPECT_EQ(edge.v0, std::min(a, b));
            EXPECT_EQ(edge.v1, std::max(a, b));
        }
    }
}

// The triangles of a topology's stats: read, dropped as degenerate and kept; and the vertices
// kept after welding.
void expectTriangleCounts(const TopologyStats& s, std::size_t input, std::size_t degenerate,
                          std::size_t kept, std::size_t vertices) {
    EXPECT_EQ(s.inputTriangles, input);
    EXPECT_EQ(s.degenerateTriangles, degenerate);
    EXPECT_EQ(s.triangles, kept);
    EXPECT_EQ(s.vertices, vertices);
}

// The edges of a topology's stats: all of them, and among them the boundary (one use),
// non-manifold (three or more uses) and inconsistent (two uses in one direction) ones.
void expectEdgeCounts(const TopologyStats& s, std::size_t edges, std::size_t boundary,
                      std::size_t nonManifold, std::size_t inconsistent) {
    EXPECT_EQ(s.edges, edges);
    EXPECT_EQ(s.boundaryEdges, boundary);
    EXPECT_EQ(s.nonManifoldEdges, nonManifold);
    EXPECT_EQ(s.inconsistentEdges, inconsistent);
}

TEST(Topology, ManifoldnessNames) {
    EXPECT_STREQ(toString(Manifoldness::Closed), "closed");
    EXPECT_STREQ(toString(Manifoldness::Open), "open");
    EXPECT_STREQ(toString(Manifoldness::NonManifold), "non-manifold");
}

TEST(Topology, SplitCubeWeldsToClosedManifold) {
    const MeshData mesh = splitCube();
    ASSERT_EQ(mesh.positions.size(), 24u);
    const Topology topo(mesh);
    expectConsistent(topo);
    const TopologyStats& s = topo.stats();
    EXPECT_EQ(s.inputVertices, 24u);
    expectTriangleCounts(s, 12, 0, 12, 8);
    expectEdgeCounts(s, 18, 0, 0, 0); // 12 cube edges + 6 face diagonals
    EXPECT_EQ(s.nonManifoldVertices, 0u);
    EXPECT_EQ(topo.manifoldness(), Manifoldness::Closed);
    for (std::size_t t = 0; t < 12; ++t)
        EXPECT_EQ(topo.sourceTriangle()[t], t);
    // Every edge of a closed oriented mesh: two uses, opposite signs.
    for (std::size_t e = 0; e < topo.edges().size(); ++e) {
        const std::uint32_t u = topo.edgeUseOffsets()[e];
        ASSERT_EQ(topo.edgeUseOffsets()[e + 1] - u, 2u);
        EXPECT_EQ(topo.edgeUses()[u].sign + topo.edgeUses()[u + 1].sign, 0);
    }
}

TEST(Topology, WeldingIsDeterministicAndPositionPreserving) {
    const MeshData mesh = splitCube();
    const Topology a(mesh), b(mesh);
    ASSERT_EQ(a.positions().size(), b.positions().size());
    for (std::size_t i = 0; i < a.positions().size(); ++i) {
        EXPECT_EQ(a.positions()[i], b.positions()[i]);
    }
    // Welded triangles keep their input corners' positions (exact duplicates here).
    for (std::size_t t = 0; t < a.triangles().size(); ++t) {
        const glm::uvec3 src = mesh.triangles[a.sourceTriangle()[t]];
        for (int k = 0; k < 3; ++k) {
            EXPECT_EQ(a.positions()[a.triangles()[t][k]], mesh.positions[src[k]]);
        }
    }
}

TEST(Topology, OpenBoxHasFourBoundaryEdges) {
    const Topology topo(splitCube(/*skipFace=*/2)); // no +y face
    expectConsistent(topo);
    const TopologyStats& s = topo.stats();
    EXPECT_EQ(s.triangles, 10u);
    EXPECT_EQ(s.vertices, 8u);
    expectEdgeCounts(s, 17, 4, 0, 0);
    EXPECT_EQ(s.nonManifoldVertices, 0u);
    EXPECT_EQ(topo.manifoldness(), Manifoldness::Open);
}

TEST(Topology, SinglePlaneIsOpen) {
    const Topology topo(quad());
    expectConsistent(topo);
    EXPECT_EQ(topo.stats().edges, 5u);
    EXPECT_EQ(topo.stats().boundaryEdges, 4u);
    EXPECT_EQ(topo.manifoldness(), Manifoldness::Open);
}

TEST(Topology, ThreeTrianglesOnOneEdgeAreNonManifold) {
    MeshData mesh;
    mesh.positions = {{0, 0, 0}, {1, 0, 0}, {0.5f, 1, 0}, {0.5f, -1, 0}, {0.5f, 0, 1}};
    mesh.triangles = {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}};
    const Topology topo(mesh);
    expectConsistent(topo);
    const TopologyStats& s = topo.stats();
    expectEdgeCounts(s, 7, 6, 1, 0); // inconsistent: only counted on two-use edges
    EXPECT_EQ(topo.manifoldness(), Manifoldness::NonManifold);
    // The shared edge lists all three triangles, in triangle order, with their orientations.
    const auto edges = topo.edges();
    const auto it = std::find_if(edges.begin(), edges.end(),
                                 [](const Edge& e) { return e.v0 == 0 && e.v1 == 1; });
    ASSERT_NE(it, edges.end());
    const auto e = static_cast<std::size_t>(it - edges.begin());
    const std::uint32_t u = topo.edgeUseOffsets()[e];
    ASSERT_EQ(topo.edgeUseOffsets()[e + 1] - u, 3u);
    EXPECT_EQ(topo.edgeUses()[u].triangle, 0u);
    EXPECT_EQ(topo.edgeUses()[u].sign, 1);
    EXPECT_EQ(topo.edgeUses()[u + 1].sign, -1);
    EXPECT_EQ(topo.edgeUses()[u + 2].sign, 1);
}

TEST(Topology, FiveTrianglesOnOneEdge) {
    // Up to 5 uses per edge occur in the game levels.
    MeshData mesh;
    mesh.positions = {{0, 0, 0}, {1, 0, 0}};
    for (int i = 0; i < 5; ++i) {
        const float a = 1.2566f * static_cast<float>(i);
        mesh.positions.push_back({0.5f, std::cos(a), std::sin(a)});
        mesh.triangles.emplace_back(i % 2 ? 1 : 0, i % 2 ? 0 : 1, 2 + i);
    }
    const Topology topo(mesh);
    expectConsistent(topo);
    EXPECT_EQ(topo.stats().nonManifoldEdges, 1u);
    EXPECT_EQ(topo.stats().boundaryEdges, 10u);
    EXPECT_EQ(topo.manifoldness(), Manifoldness::NonManifold);
}

TEST(Topology, InconsistentlyOrientedTriangleIsNonManifold) {
    MeshData mesh = splitCube();
    std::swap(mesh.triangles[4].y, mesh.triangles[4].z);
    const Topology topo(mesh);
    expectConsistent(topo);
    const TopologyStats& s = topo.stats();
    expectEdgeCounts(s, 18, 0, 0, 3); // inconsistent: all three edges of the flipped triangle
    EXPECT_EQ(topo.manifoldness(), Manifoldness::NonManifold);
}

TEST(Topology, BowtieVertexIsNonManifold) {
    // Two closed tetrahedra sharing one vertex: every edge is fine, the vertex joins two fans.
    MeshData mesh;
    mesh.positions = {{0, 0, 0},  {1, 0, 0},  {0, 1, 0}, {0, 0, 1},
                      {-1, 0, 0}, {0, -1, 0}, {0, 0, -1}};
    auto tetra = [&](std::uint32_t a, std::uint32_t b, std::uint32_t c, std::uint32_t d) {
        // Faces oriented consistently (outward up to a global sign, which does not matter here).
        mesh.triangles.emplace_back(a, c, b);
        mesh.triangles.emplace_back(a, b, d);
        mesh.triangles.emplace_back(a, d, c);
        mesh.triangles.emplace_back(b, c, d);
    };
    tetra(0, 1, 2, 3);
    tetra(0, 4, 5, 6);
    for (int order = 0; order < 2; ++order) {
        if (order == 1) { // interleave the two fans: OpenMesh sees two open fans at vertex 0
            std::swap(mesh.triangles[1], mesh.triangles[4]);
            std::swap(mesh.triangles[2], mesh.triangles[6]);
        }
        const Topology topo(mesh);
        expectConsistent(topo);
        const TopologyStats& s = topo.stats();
        expectEdgeCounts(s, 12, 0, 0, 0);
        EXPECT_EQ(s.nonManifoldVertices, 1u) << "order " << order;
        EXPECT_EQ(topo.manifoldness(), Manifoldness::NonManifold) << "order " << order;
    }
}

TEST(Topology, ClosedManifoldInAnyFaceOrderStaysClosed) {
    // OpenMesh's add_face relinks open fans as faces arrive; a valid closed mesh must never be
    // reported non-manifold because of the order its triangles come in.
    MeshData mesh = testmeshes::uvSphere(10, 6, [] { return 1.0f; });
    std::mt19937 rng(7);
    for (int trial = 0; trial < 50; ++trial) {
        std::shuffle(mesh.triangles.begin(), mesh.triangles.end(), rng);
        const Topology topo(mesh);
        ASSERT_EQ(topo.stats().nonManifoldVertices, 0u) << "trial " << trial;
        ASSERT_EQ(topo.manifoldness(), Manifoldness::Closed) << "trial " << trial;
        ASSERT_EQ(topo.stats().edges, 3 * mesh.triangles.size() / 2);
    }
}

// A closed box with every triangle repeated (rotated, as an exporter may), plus one reversed
// twin: the repeats are dropped and counted, so the box stays closed; the reversed twin is kept.
TEST(Topology, DuplicateTrianglesAreDroppedAndCounted) {
    MeshData mesh = makeBox({0, 0, 0}, {1, 1, 1});
    const std::size_t n = mesh.triangles.size();
    for (std::size_t i = 0; i < n; ++i) {
        const glm::uvec3 t = mesh.triangles[i];
        mesh.triangles.emplace_back(t.y, t.z, t.x); // the same triangle, another first corner
    }
    {
        const Topology topo(mesh);
        EXPECT_EQ(topo.stats().duplicateTriangles, n);
        EXPECT_EQ(topo.stats().triangles, n);
        EXPECT_EQ(topo.manifoldness(), Manifoldness::Closed);
        EXPECT_EQ(topo.stats().nonManifoldEdges, 0u);
    }
    const glm::uvec3 t = mesh.triangles[0];
    mesh.triangles.emplace_back(t.x, t.z, t.y); // reversed: a two-sided sheet, kept
    const Topology topo(mesh);
    EXPECT_EQ(topo.stats().duplicateTriangles, n);
    EXPECT_EQ(topo.stats().triangles, n + 1);
}

TEST(Topology, DegenerateTrianglesAreDroppedAndCounted) {
    MeshData mesh = quad();
    mesh.positions.push_back({2, 0, 0});                                // 4: collinear with 0 and 1
    mesh.positions.push_back({1, 1, 1e-9f});                            // 5: welds onto 2
    mesh.triangles.insert(mesh.triangles.begin(), glm::uvec3(0, 0, 1)); // repeated index
    mesh.triangles.emplace_back(0, 1, 4);                               // zero area
    mesh.triangles.emplace_back(1, 2, 5);                               // repeated after welding
    mesh.triangles.emplace_back(1, 4, 2);                               // fine
    const Topology topo(mesh);
    expectConsistent(topo);
    const TopologyStats& s = topo.stats();
    expectTriangleCounts(s, 6, 3, 3, 5); // vertices: 5 welded into 2
    ASSERT_EQ(topo.sourceTriangle().size(), 3u);
    EXPECT_EQ(topo.sourceTriangle()[0], 1u);
    EXPECT_EQ(topo.sourceTriangle()[1], 2u);
    EXPECT_EQ(topo.sourceTriangle()[2], 5u);
}

TEST(Topology, UnreferencedVerticesAreNotKept) {
    MeshData mesh = quad();
    mesh.positions.push_back({5, 5, 5});
    const Topology topo(mesh);
    EXPECT_EQ(topo.stats().inputVertices, 5u);
    EXPECT_EQ(topo.stats().vertices, 4u);
}

TEST(Topology, WeldToleranceIsRelativeToBounds) {
    // Two triangles sharing an edge whose second copy is offset by `offset` (times the diagonal).
    const auto twoTriangles = [](float offset) {
        MeshData mesh;
        const float scale = 100.0f; // tolerance must scale with the mesh
        mesh.positions = {{0, 0, 0}, {scale, 0, 0}, {0, scale, 0}};
        const glm::vec3 d(offset * scale * std::sqrt(2.0f) / std::sqrt(3.0f));
        mesh.positions.push_back(glm::vec3(scale, 0, 0) + d);
        mesh.positions.push_back(glm::vec3(0, scale, 0) + d);
        mesh.positions.push_back({scale, scale, 0});
        mesh.triangles = {{0, 1, 2}, {4, 3, 5}};
        return mesh;
    };
    constexpr float kTolerance = 1e-4f;
    {
        const Topology topo(twoTriangles(0.3f * kTolerance), kTolerance);
        expectConsistent(topo);
        EXPECT_EQ(topo.stats().vertices, 4u);
        EXPECT_EQ(topo.stats().edges, 5u);
        EXPECT_EQ(topo.manifoldness(), Manifoldness::Open);
    }
    {
        const Topology topo(twoTriangles(3.0f * kTolerance), kTolerance);
        EXPECT_EQ(topo.stats().vertices, 6u);
        EXPECT_EQ(topo.stats().edges, 6u);
    }
    { // Tolerance 0: only exactly equal positions merge.
        const Topology topo(twoTriangles(0.3f * kTolerance), 0.0f);
        EXPECT_EQ(topo.stats().vertices, 6u);
        const Topology exact(twoTriangles(0.0f), 0.0f);
        EXPECT_EQ(exact.stats().vertices, 4u);
    }
}

TEST(Topology, WeldsAcrossGridCellBorders) {
    // Near-equal pairs straddling every possible cell border: the neighbour-cell search must find
    // them whatever side of a border each copy falls on.
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> coord(0.0f, 1.0f), sign(-1.0f, 1.0f);
    MeshData mesh;
    const float tol = 1e-4f; // relative; the diagonal is ~sqrt(3)
    for (int i = 0; i < 2000; ++i) {
        const glm::vec3 p(coord(rng), coord(rng), coord(rng));
        const glm::vec3 q = p + 0.3f * tol * glm::vec3(sign(rng), sign(rng), sign(rng));
        mesh.positions.push_back(p);
        mesh.positions.push_back(q);
    }
    // Triangles p_i p_i+1 p_i+2 and q_i q_i+1 q_i+2 reference every p and q.
    for (std::uint32_t i = 0; i + 2 < 2000; ++i) {
        mesh.triangles.emplace_back(2 * i, 2 * i + 2, 2 * i + 4);
        mesh.triangles.emplace_back(2 * i + 1, 2 * i + 3, 2 * i + 5);
    }
    mesh.positions.push_back({0, 0, 0}); // unreferenced, fixes the bounds
    mesh.positions.push_back({1, 1, 1});
    const Topology topo(mesh, tol);
    // Every q welds to its p (and no two random p are that close, with overwhelming odds).
    EXPECT_EQ(topo.stats().vertices, 2000u);
}

TEST(Topology, RejectsBadInput) {
    MeshData mesh = quad();
    mesh.positions[2].y = std::numeric_limits<float>::quiet_NaN();
    EXPECT_THROW(Topology{mesh}, InputError);
    mesh = quad();
    mesh.positions[1].x = std::numeric_limits<float>::infinity();
    EXPECT_THROW(Topology{mesh}, InputError);
    mesh = quad();
    mesh.triangles[1].z = 4;
    try {
        const Topology topo(mesh);
        FAIL() << "expected InputError";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("triangle 1"), std::string::npos) << e.what();
    }
}

TEST(Topology, EmptyMesh) {
    const Topology topo(MeshData{});
    EXPECT_EQ(topo.stats().triangles, 0u);
    EXPECT_EQ(topo.stats().edges, 0u);
    EXPECT_EQ(topo.edgeUseOffsets().size(), 1u);
}

// 320k triangles split per quad (testmeshes::splitGrid): welding joins the 4 n^2 positions into
// the (n + 1)^2 grid vertices, leaving an open mesh bounded by its 4 n rim edges. Its build time
// is geometry_bench's topology/split_grid_320k.
TEST(Topology, LargeGridIsWeldedAndOpen) {
    const int n = 400;
    const MeshData mesh = testmeshes::splitGrid(n);
    const Topology topo(mesh);
    EXPECT_EQ(topo.stats().vertices, static_cast<std::size_t>((n + 1) * (n + 1)));
    EXPECT_EQ(topo.stats().boundaryEdges, static_cast<std::size_t>(4 * n));
    EXPECT_EQ(topo.manifoldness(), Manifoldness::Open);
}

TEST(Topology, GameLevelIsNonManifold) {
    // Real data (../shared/levels/README.md): ~12% boundary edges, some edges with 3-5 uses.
    const std::filesystem::path level =
        std::filesystem::path(PENUMBRA_SHARED_DIR) / "levels" / "oa_dm1.glb";
    ASSERT_TRUE(std::filesystem::exists(level))
        << "missing " << level << " (../shared must be beside the repo)";
    const MeshData mesh = loadGltf(level);
    const Topology topo(mesh); // its build time: silhouette_bench's topology_build/level/oa_dm1
    expectConsistent(topo);
    const TopologyStats& s = topo.stats();
    const double boundaryShare = static_cast<double>(s.boundaryEdges) / s.edges;
    std::printf("[ level    ] oa_dm1: %zu -> %zu vertices, %zu triangles (%zu degenerate), %zu "
                "edges, %.1f%% boundary, %zu non-manifold edges, %zu inconsistent, %zu "
                "non-manifold vertices\n",
                s.inputVertices, s.vertices, s.triangles, s.degenerateTriangles, s.edges,
                100.0 * boundaryShare, s.nonManifoldEdges, s.inconsistentEdges,
                s.nonManifoldVertices);
    EXPECT_EQ(s.inputTriangles, 7502u);
    EXPECT_LT(s.degenerateTriangles, s.inputTriangles / 20);
    EXPECT_LT(s.vertices, s.inputVertices); // primitives share positions: welding merged some
    EXPECT_GT(boundaryShare, 0.05);
    EXPECT_LT(boundaryShare, 0.25);
    EXPECT_GT(s.nonManifoldEdges, 0u);
    EXPECT_EQ(topo.manifoldness(), Manifoldness::NonManifold);
    // Edges with more than 5 uses would mean welding merged what it should not.
    std::size_t maxUses = 0;
    for (std::size_t e = 0; e < s.edges; ++e) {
        maxUses =
            std::max<std::size_t>(maxUses, topo.edgeUseOffsets()[e + 1] - topo.edgeUseOffsets()[e]);
    }
    EXPECT_LE(maxUses, 8u);
}

} // namespace
} // namespace geometry
