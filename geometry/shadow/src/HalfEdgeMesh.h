// Private to geometry/shadow: the OpenMesh half-edge view of a Topology, for algorithms that walk
// vertex fans and boundary loops (silhouette loops, issue 3).
//
// - Built from the welded triangles in the same order, so face handle idx() == topology triangle
//   index for every face (every triangle is added; see Topology.cpp for how).
// - OpenMesh cannot hold non-manifold configurations (a third triangle on an edge, a triangle that
//   reuses a half-edge in the same direction, a second fan on a closed vertex). Such corners are
//   moved to duplicated OpenMesh vertices, so one welded vertex may map to several OpenMesh
//   vertices. The welded (Topology) id of every OpenMesh vertex is in `weldedVertex`.
// - Vertex handle idx() == welded id for the first `primaryVertices` vertices (the primaries);
//   duplicates come after them.
// - The CSR edge uses of Topology remain the exact adjacency; this mesh is the walkable one.
#pragma once

#include <geometry/shadow/Topology.h>

#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>

#include <cstdint>
#include <vector>

namespace geometry {

struct Topology::HalfEdgeMesh {
    using Mesh = OpenMesh::TriMesh_ArrayKernelT<>;

    Mesh mesh;
    std::vector<std::uint32_t> weldedVertex; // OpenMesh vertex idx -> welded (Topology) vertex id
    std::size_t primaryVertices = 0;

    std::uint32_t welded(OpenMesh::VertexHandle v) const {
        return weldedVertex[static_cast<std::size_t>(v.idx())];
    }
    // Topology triangle index of an OpenMesh face.
    static std::uint32_t triangle(OpenMesh::FaceHandle f) {
        return static_cast<std::uint32_t>(f.idx());
    }
    static OpenMesh::FaceHandle face(std::uint32_t triangle) {
        return OpenMesh::FaceHandle(static_cast<int>(triangle));
    }
    bool isDuplicate(OpenMesh::VertexHandle v) const {
        return static_cast<std::size_t>(v.idx()) >= primaryVertices;
    }
};

} // namespace geometry
