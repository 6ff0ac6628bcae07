// Welded edge topology of one triangle mesh, built once per mesh (OpenMesh inside).
//
// - Vertices are welded by position (glTF splits them by normal/UV) with a tolerance relative to
//   the mesh size; degenerate triangles (repeated or collinear corners after welding) are dropped
//   and counted.
// - Every undirected edge lists its incident triangles with the orientation in which each uses
//   it, in flat CSR arrays. This is what the two-sided multiplicity rule (DESIGN.md §4) needs, and
//   it stays exact for non-manifold edges that OpenMesh's half-edge structure cannot hold.
// - The mesh is classified as a closed 2-manifold, an open manifold or non-manifold.
#pragma once

#include <geometry/core/Types.h>

#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

namespace geometry {

enum class Manifoldness {
    Closed,      // every edge has exactly two triangles using it in opposite directions,
                 // and every vertex has a single fan (a closed oriented 2-manifold)
    Open,        // manifold with boundary: edges have one or two consistently oriented triangles
    NonManifold, // some edge has > 2 triangles, two triangles using it in the same direction,
                 // or some vertex joins separate fans
};
const char* toString(Manifoldness m);

struct Edge {
    std::uint32_t v0, v1; // welded vertex ids, v0 < v1
};

// One triangle's use of an edge: +1 if the triangle has the directed edge v0 -> v1, -1 if v1 -> v0.
struct EdgeUse {
    std::uint32_t triangle;
    std::int32_t sign;
};

struct TopologyStats {
    std::size_t inputVertices = 0;
    std::size_t inputTriangles = 0;
    std::size_t vertices = 0;            // after welding
    std::size_t triangles = 0;           // after dropping degenerate and duplicate ones
    std::size_t degenerateTriangles = 0; // dropped
    std::size_t duplicateTriangles = 0;  // dropped: same corners in the same order as an earlier one
    std::size_t edges = 0;
    std::size_t boundaryEdges = 0;       // one incident triangle
    std::size_t nonManifoldEdges = 0;    // more than two incident triangles
    std::size_t inconsistentEdges = 0;   // two triangles using the edge in the same direction
    std::size_t nonManifoldVertices = 0; // vertices OpenMesh could not take as one fan
};

class Topology {
public:
    // weldTolerance is relative to the diagonal of the mesh bounds.
    explicit Topology(const MeshData& mesh, float weldTolerance = 1e-6f);
    ~Topology();
    Topology(Topology&&) noexcept;
    Topology& operator=(Topology&&) noexcept;
    Topology(const Topology&) = delete;
    Topology& operator=(const Topology&) = delete;

    std::span<const glm::vec3> positions() const { return mPositions; }   // welded
    std::span<const glm::uvec3> triangles() const { return mTriangles; }  // welded ids
    std::span<const std::uint32_t> sourceTriangle() const { return mSourceTriangle; } // -> MeshData
    std::span<const Edge> edges() const { return mEdges; }
    // CSR: the uses of edge e are edgeUses()[edgeUseOffsets()[e] .. edgeUseOffsets()[e+1]).
    std::span<const std::uint32_t> edgeUseOffsets() const { return mEdgeUseOffsets; }
    std::span<const EdgeUse> edgeUses() const { return mEdgeUses; }
    // The edge ids of triangle t, for its directed edges (a,b), (b,c), (c,a).
    std::span<const glm::uvec3> triangleEdges() const { return mTriangleEdges; }

    Manifoldness manifoldness() const { return mManifoldness; }
    const TopologyStats& stats() const { return mStats; }

    // OpenMesh connectivity for algorithms that walk fans/loops (issue 3). Opaque here so that
    // OpenMesh types stay inside geometry/shadow/src.
    struct HalfEdgeMesh;
    const HalfEdgeMesh& halfEdgeMesh() const { return *mHalfEdge; }

private:
    std::vector<glm::vec3> mPositions;
    std::vector<glm::uvec3> mTriangles;
    std::vector<std::uint32_t> mSourceTriangle;
    std::vector<Edge> mEdges;
    std::vector<std::uint32_t> mEdgeUseOffsets;
    std::vector<EdgeUse> mEdgeUses;
    std::vector<glm::uvec3> mTriangleEdges;
    Manifoldness mManifoldness = Manifoldness::Closed;
    TopologyStats mStats;
    std::unique_ptr<HalfEdgeMesh> mHalfEdge;
};

} // namespace geometry
