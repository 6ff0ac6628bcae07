// Small hand-built meshes shared by the geometry tests (shadow volumes, silhouettes, topology),
// and the large ones that geometry_bench times (the tests check what they assert on them); and
// the square lights above them.
// geometry/scene/Primitives.h is used where it yields the very same mesh; the builders kept here differ
// from it in vertex or triangle order, or in how coordinates are computed, which the tests rely on.
#pragma once

#include <geometry/scene/Primitives.h>
#include <geometry/core/Types.h>

#include <cmath>
#include <cstddef>
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

// Bumpy open height field over [0, 1]^2 in xz: (n + 1)^2 shared vertices, 2 n^2 triangles facing
// +y, y = 0.05 sin(40 x) cos(33 z). n = 224: 100,352 triangles (ShadowVolumeTest, geometry_bench).
inline geometry::MeshData heightField(int n) {
    geometry::MeshData mesh;
    for (int j = 0; j <= n; ++j) {
        for (int i = 0; i <= n; ++i) {
            const float x = static_cast<float>(i) / n, z = static_cast<float>(j) / n;
            mesh.positions.push_back({x, 0.05f * std::sin(40.0f * x) * std::cos(33.0f * z), z});
        }
    }
    for (int j = 0; j < n; ++j) {
        for (int i = 0; i < n; ++i) {
            const auto v = static_cast<std::uint32_t>(j * (n + 1) + i);
            mesh.triangles.emplace_back(v, v + n + 1, v + 1);
            mesh.triangles.emplace_back(v + 1, v + n + 1, v + n + 2);
        }
    }
    return mesh;
}

// n x n unit quads of a gentle height field, each with its own 4 vertices (split per quad as a
// glTF export might): 4 n^2 positions, 2 n^2 triangles facing +y, welding to (n + 1)^2 vertices
// and an open mesh with 4 n boundary edges. n = 400: 320,000 triangles (TopologyTest,
// geometry_bench).
inline geometry::MeshData splitGrid(int n) {
    geometry::MeshData mesh;
    mesh.positions.reserve(4 * static_cast<std::size_t>(n) * n);
    for (int y = 0; y < n; ++y) {
        for (int x = 0; x < n; ++x) {
            const auto base = static_cast<std::uint32_t>(mesh.positions.size());
            const auto h = [](int i, int j) {
                return 0.1f * std::sin(0.05f * static_cast<float>(i)) *
                       std::cos(0.07f * static_cast<float>(j));
            };
            for (int c = 0; c < 4; ++c) {
                const int i = x + (c == 1 || c == 2), j = y + (c >= 2);
                mesh.positions.push_back({static_cast<float>(i), h(i, j), static_cast<float>(j)});
            }
            mesh.triangles.emplace_back(base, base + 2, base + 1);
            mesh.triangles.emplace_back(base, base + 3, base + 2);
        }
    }
    return mesh;
}

// A square light of half size `halfSize` at `center`, in the xz plane (u along +x, v along +z).
inline geometry::RectLight squareLight(const glm::vec3& center, float halfSize) {
    geometry::RectLight light;
    light.center = center;
    light.u = {halfSize, 0.0f, 0.0f};
    light.v = {0.0f, 0.0f, halfSize};
    return light;
}

} // namespace testmeshes
