// Small hand-built meshes shared by the geometry tests (shadow volumes, silhouettes, topology).
// geometry/Primitives.h is used where it yields the very same mesh; the builders kept here differ
// from it in vertex or triangle order, or in how coordinates are computed, which the tests rely on.
#pragma once

#include <geometry/Primitives.h>
#include <geometry/Types.h>

#include <cmath>
#include <cstdint>

namespace testmeshes {

// Cube [-1, 1]^3, 8 shared corners (corner i on the + side of x/y/z for bit 0/1/2), outward
// counter-clockwise; without face `skipFace` (0..5 = -x, +x, -y, +y, -z, +z). Not makeBox: it
// cannot skip a face, and it starts some quads at another corner, so their triangles and diagonals
// differ (-x split along 2-4, not 0-6): not the mesh these tests were written against.
inline geometry::MeshData cube(int skipFace = -1) {
    geometry::MeshData mesh;
    for (int i = 0; i < 8; ++i) {
        mesh.positions.push_back(
            {i & 1 ? 1.0f : -1.0f, i & 2 ? 1.0f : -1.0f, i & 4 ? 1.0f : -1.0f});
    }
    // Quads listed counter-clockwise from outside: -x, +x, -y, +y, -z, +z.
    const std::uint32_t quads[6][4] = {{0, 4, 6, 2}, {1, 3, 7, 5}, {0, 1, 5, 4},
                                       {2, 6, 7, 3}, {0, 2, 3, 1}, {4, 5, 7, 6}};
    for (int f = 0; f < 6; ++f) {
        if (f == skipFace) continue;
        const auto& q = quads[f];
        mesh.triangles.emplace_back(q[0], q[1], q[2]);
        mesh.triangles.emplace_back(q[0], q[2], q[3]);
    }
    return mesh;
}

// Square [-1, 1]^2 at height z facing +z: corners (-1,-1) (1,-1) (1,1) (-1,1), triangles
// (0,1,2) (0,2,3); makeQuad builds exactly this (all coordinates are exact in float).
inline geometry::MeshData quad(float z = 0.0f) {
    return geometry::makeQuad({0.0f, 0.0f, z}, {1.0f, 0.0f, 0.0f}, {0.0f, 1.0f, 0.0f});
}

// Closed UV sphere around the origin with `segments` around and `rings` bands, each vertex at the
// distance radius() (called once per vertex: north pole, rings top-down, south pole), outward CCW.
// Not makeSphere: that fixes rings = segments / 2, computes in double and emits the south cap
// last, while the tests need a free ring count, per-vertex radii (jittered blobs) and this exact
// triangle order (TopologyTest shuffles it with a fixed seed).
template <class Radius>
inline geometry::MeshData uvSphere(int segments, int rings, Radius&& radius) {
    geometry::MeshData mesh;
    mesh.positions.push_back({0, radius(), 0});
    for (int r = 1; r < rings; ++r) {
        const float theta = 3.14159265f * static_cast<float>(r) / static_cast<float>(rings);
        for (int s = 0; s < segments; ++s) {
            const float phi = 6.2831853f * static_cast<float>(s) / static_cast<float>(segments);
            const float rad = radius();
            mesh.positions.push_back({rad * std::sin(theta) * std::cos(phi), rad * std::cos(theta),
                                      rad * std::sin(theta) * std::sin(phi)});
        }
    }
    mesh.positions.push_back({0, -radius(), 0});
    const auto ring = [&](int r, int s) {
        return static_cast<std::uint32_t>(1 + (r - 1) * segments + (s % segments));
    };
    const auto south = static_cast<std::uint32_t>(mesh.positions.size() - 1);
    for (int s = 0; s < segments; ++s) {
        mesh.triangles.emplace_back(0, ring(1, s + 1), ring(1, s));
        mesh.triangles.emplace_back(south, ring(rings - 1, s), ring(rings - 1, s + 1));
        for (int r = 1; r + 1 < rings; ++r) {
            mesh.triangles.emplace_back(ring(r, s), ring(r, s + 1), ring(r + 1, s + 1));
            mesh.triangles.emplace_back(ring(r, s), ring(r + 1, s + 1), ring(r + 1, s));
        }
    }
    return mesh;
}

// Non-manifold fan: `count` triangles on the one edge (0, 1) from (-1,0,0) to (1,0,0), alternating
// orientation, apexes spread around the edge (no Primitives.h counterpart).
inline geometry::MeshData edgeFan(int count) {
    geometry::MeshData mesh;
    mesh.positions = {{-1, 0, 0}, {1, 0, 0}};
    for (int i = 0; i < count; ++i) {
        const float a = 6.2831853f * (static_cast<float>(i) + 0.3f) / static_cast<float>(count);
        mesh.positions.push_back({0.2f * static_cast<float>(i) - 0.3f, std::cos(a), std::sin(a)});
        const auto apex = static_cast<std::uint32_t>(2 + i);
        if (i % 2) {
            mesh.triangles.emplace_back(1, 0, apex);
        } else {
            mesh.triangles.emplace_back(0, 1, apex);
        }
    }
    return mesh;
}

} // namespace testmeshes
