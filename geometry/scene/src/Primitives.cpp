// Analytic scene shapes as triangle meshes. Positions are shared wherever faces meet so that the
// closed shapes (box, sphere) are 2-manifolds even before welding; winding is counter-clockwise
// seen from outside, which the shadow-volume code uses to tell light-facing triangles.
#include <geometry/scene/Primitives.h>

#include <geometry/core/Error.h>

#include <geometry/core/Hash.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <numbers>
#include <sstream>
#include <string>
#include <unordered_map>
#include <vector>

namespace geometry {
namespace {

bool isFinite(const glm::vec3& v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

std::string str(const glm::vec3& v) {
    std::ostringstream s;
    s << "[" << v.x << ", " << v.y << ", " << v.z << "]";
    return s.str();
}


// Uniform in [0, 1) from the seed and the exact bits of a position. Adding 0.0f turns -0 into +0,
// so the two zeros (equal positions) hash alike.
double positionNoise(std::uint32_t seed, const glm::vec3& p) {
    std::uint64_t h = mix64(0x9e3779b97f4a7c15ull ^ seed);
    for (int k = 0; k < 3; ++k) {
        h = mix64(h ^ std::bit_cast<std::uint32_t>(p[k] + 0.0f));
    }
    return static_cast<double>(h >> 11) * 0x1.0p-53;
}

} // namespace

MeshData makeBox(const glm::vec3& center, const glm::vec3& size) {
    if (!isFinite(center) || !isFinite(size)) {
        throw InputError("box: center and size must be finite (center " + str(center) + ", size " +
                         str(size) + ")");
    }
    if (!(size.x > 0.0f && size.y > 0.0f && size.z > 0.0f)) {
        throw InputError("box: every size component must be > 0, got " + str(size));
    }

    MeshData mesh;
    mesh.name = "box";
    const glm::vec3 half = 0.5f * size;
    // Corner i has bit 0/1/2 set when it lies on the + side of x/y/z.
    for (int i = 0; i < 8; ++i) {
        const glm::vec3 sign((i & 1) ? 1.0f : -1.0f, (i & 2) ? 1.0f : -1.0f,
                             (i & 4) ? 1.0f : -1.0f);
        mesh.positions.push_back(center + sign * half);
    }
    // For the face normal to axis a, walk the face in the (b, c) plane with b = a+1, c = a+2
    // (cyclic): the order (0,0) (1,0) (1,1) (0,1) turns counter-clockwise around e_b x e_c = e_a,
    // so it is outward for the + face and must be reversed for the - face.
    for (int a = 0; a < 3; ++a) {
        const int b = (a + 1) % 3;
        const int c = (a + 2) % 3;
        for (int side = 0; side < 2; ++side) {
            std::uint32_t quad[4];
            const int walk[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
            for (int k = 0; k < 4; ++k) {
                const int w = side == 1 ? k : 3 - k;
                quad[k] =
                    static_cast<std::uint32_t>((side << a) | (walk[w][0] << b) | (walk[w][1] << c));
            }
            mesh.triangles.emplace_back(quad[0], quad[1], quad[2]);
            mesh.triangles.emplace_back(quad[0], quad[2], quad[3]);
        }
    }
    return mesh;
}

MeshData makeQuad(const glm::vec3& center, const glm::vec3& u, const glm::vec3& v) {
    if (!isFinite(center) || !isFinite(u) || !isFinite(v)) {
        throw InputError("quad: center, u and v must be finite");
    }
    const float lu = glm::length(u);
    const float lv = glm::length(v);
    // Relative test: a sliver parallelogram is as useless as a zero-length axis.
    if (!(lu > 0.0f && lv > 0.0f) || glm::length(glm::cross(u, v)) <= 1e-6f * lu * lv) {
        throw InputError("quad: u " + str(u) + " and v " + str(v) +
                         " span zero area (zero length or parallel)");
    }
    MeshData mesh;
    mesh.name = "quad";
    mesh.positions = {center - u - v, center + u - v, center + u + v, center - u + v};
    // (u, v) turns counter-clockwise around cross(u, v), so both triangles face along it.
    mesh.triangles = {{0, 1, 2}, {0, 2, 3}};
    return mesh;
}

std::size_t sphereTriangleCount(int segments) {
    // Two caps of `segments` triangles and bands - 2 rings of 2 * segments (see makeSphere).
    const std::size_t bands = std::size_t(std::max(2, segments / 2));
    return 2 * std::size_t(segments) * (bands - 1);
}

std::size_t torusTriangleCount(int majorSegments, int minorSegments) {
    return 2 * std::size_t(majorSegments) * std::size_t(minorSegments);
}

MeshData makeSphere(const glm::vec3& center, float radius, int segments) {
    if (!isFinite(center) || !std::isfinite(radius)) {
        throw InputError("sphere: center and radius must be finite");
    }
    if (!(radius > 0.0f)) {
        throw InputError("sphere: radius must be > 0, got " + std::to_string(radius));
    }
    if (segments < 3) {
        throw InputError("sphere: segments must be >= 3, got " + std::to_string(segments));
    }
    // Guard against absurd requests that would exhaust memory (and 32-bit indices).
    if (segments > 4096) {
        throw InputError("sphere: segments must be <= 4096, got " + std::to_string(segments));
    }
    const int around = segments;
    // segments/2 rings of latitude bands; at least 2 so the sphere has a non-degenerate equator
    // ring even for segments = 3.
    const int bands = std::max(2, segments / 2);

    MeshData mesh;
    mesh.name = "sphere";
    const double pi = std::numbers::pi;
    mesh.positions.push_back(center + glm::vec3(0.0f, radius, 0.0f)); // north pole, index 0
    for (int i = 1; i < bands; ++i) {
        const double theta = pi * i / bands;
        for (int j = 0; j < around; ++j) {
            const double phi = 2.0 * pi * j / around;
            const glm::dvec3 dir(std::sin(theta) * std::cos(phi), std::cos(theta),
                                 std::sin(theta) * std::sin(phi));
            mesh.positions.push_back(center + glm::vec3(dir * double(radius)));
        }
    }
    const auto south = static_cast<std::uint32_t>(mesh.positions.size());
    mesh.positions.push_back(center - glm::vec3(0.0f, radius, 0.0f));

    // Ring r (1-based) point j; j wraps so the seam shares vertices and the mesh stays closed.
    auto ring = [around](int r, int j) {
        return static_cast<std::uint32_t>(1 + (r - 1) * around + (j % around));
    };
    // With phi running from +x towards +z, (pole, next, current) is counter-clockwise seen from
    // outside at the north cap; the bands and the south cap follow by edge consistency.
    for (int j = 0; j < around; ++j) {
        mesh.triangles.emplace_back(0u, ring(1, j + 1), ring(1, j));
    }
    for (int r = 1; r + 1 < bands; ++r) {
        for (int j = 0; j < around; ++j) {
            const std::uint32_t a0 = ring(r, j), a1 = ring(r, j + 1);
            const std::uint32_t b0 = ring(r + 1, j), b1 = ring(r + 1, j + 1);
            mesh.triangles.emplace_back(a0, a1, b1);
            mesh.triangles.emplace_back(a0, b1, b0);
        }
    }
    for (int j = 0; j < around; ++j) {
        mesh.triangles.emplace_back(ring(bands - 1, j), ring(bands - 1, j + 1), south);
    }
    return mesh;
}

MeshData makeIcosphere(const glm::vec3& center, float radius, int subdivisions) {
    if (!isFinite(center) || !std::isfinite(radius)) {
        throw InputError("icosphere: center and radius must be finite");
    }
    if (!(radius > 0.0f)) {
        throw InputError("icosphere: radius must be > 0, got " + std::to_string(radius));
    }
    // 9 gives 5.2 M triangles; more would only exhaust memory.
    if (subdivisions < 0 || subdivisions > 9) {
        throw InputError("icosphere: subdivisions must be in [0, 9], got " +
                         std::to_string(subdivisions));
    }

    // Regular icosahedron: the cyclic permutations of (0, ±1, ±phi). Unit directions are kept in
    // double until the end so that deep subdivisions do not accumulate float rounding.
    const double phi = std::numbers::phi;
    std::vector<glm::dvec3> dirs = {
        {-1, phi, 0}, {1, phi, 0}, {-1, -phi, 0}, {1, -phi, 0},
        {0, -1, phi}, {0, 1, phi}, {0, -1, -phi}, {0, 1, -phi},
        {phi, 0, -1}, {phi, 0, 1}, {-phi, 0, -1}, {-phi, 0, 1},
    };
    for (glm::dvec3& d : dirs) d = glm::normalize(d);
    // Counter-clockwise seen from outside (checked by the tests through the signed volume).
    std::vector<glm::uvec3> tris = {
        {0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
        {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
        {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
        {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1},
    };

    const std::size_t finalVertices = 10 * (std::size_t(1) << (2 * subdivisions)) + 2;
    dirs.reserve(finalVertices);
    std::unordered_map<std::uint64_t, std::uint32_t> midpoints;
    for (int level = 0; level < subdivisions; ++level) {
        // One midpoint per undirected edge, shared by its two triangles: that is what keeps the
        // subdivided mesh welded and closed.
        midpoints.clear();
        midpoints.reserve(tris.size() * 3 / 2);
        auto midpoint = [&](std::uint32_t a, std::uint32_t b) {
            const std::uint64_t key =
                (std::uint64_t(std::min(a, b)) << 32) | std::uint64_t(std::max(a, b));
            const auto [it, inserted] =
                midpoints.try_emplace(key, static_cast<std::uint32_t>(dirs.size()));
            if (inserted) dirs.push_back(glm::normalize(dirs[a] + dirs[b]));
            return it->second;
        };
        std::vector<glm::uvec3> next;
        next.reserve(tris.size() * 4);
        for (const glm::uvec3& t : tris) {
            const std::uint32_t ab = midpoint(t.x, t.y);
            const std::uint32_t bc = midpoint(t.y, t.z);
            const std::uint32_t ca = midpoint(t.z, t.x);
            // The four children keep the parent's winding.
            next.emplace_back(t.x, ab, ca);
            next.emplace_back(t.y, bc, ab);
            next.emplace_back(t.z, ca, bc);
            next.emplace_back(ab, bc, ca);
        }
        tris = std::move(next);
    }

    MeshData mesh;
    mesh.name = "icosphere";
    mesh.positions.reserve(dirs.size());
    const glm::dvec3 c(center);
    for (const glm::dvec3& d : dirs) mesh.positions.emplace_back(c + d * double(radius));
    mesh.triangles = std::move(tris);
    return mesh;
}

MeshData makeTorus(const glm::vec3& center, float majorRadius, float minorRadius,
                   int majorSegments, int minorSegments) {
    if (!isFinite(center) || !std::isfinite(majorRadius) || !std::isfinite(minorRadius)) {
        throw InputError("torus: center and radii must be finite");
    }
    // A horn or spindle torus (minor >= major) touches or passes through its axis: not a
    // 2-manifold.
    if (!(minorRadius > 0.0f && majorRadius > minorRadius)) {
        throw InputError("torus: need majorRadius > minorRadius > 0, got " +
                         std::to_string(majorRadius) + " and " + std::to_string(minorRadius));
    }
    if (majorSegments < 3 || minorSegments < 3) {
        throw InputError("torus: segments must be >= 3, got " + std::to_string(majorSegments) +
                         " x " + std::to_string(minorSegments));
    }
    if (majorSegments > 4096 || minorSegments > 4096) {
        throw InputError("torus: segments must be <= 4096, got " + std::to_string(majorSegments) +
                         " x " + std::to_string(minorSegments));
    }

    MeshData mesh;
    mesh.name = "torus";
    const double pi = std::numbers::pi;
    const auto nMajor = static_cast<std::uint32_t>(majorSegments);
    const auto nMinor = static_cast<std::uint32_t>(minorSegments);
    mesh.positions.reserve(std::size_t(nMajor) * nMinor);
    for (std::uint32_t i = 0; i < nMajor; ++i) {
        const double phi = 2.0 * pi * i / nMajor;
        for (std::uint32_t j = 0; j < nMinor; ++j) {
            const double theta = 2.0 * pi * j / nMinor;
            const double ring = majorRadius + minorRadius * std::cos(theta);
            const glm::dvec3 p(ring * std::cos(phi), minorRadius * std::sin(theta),
                               ring * std::sin(phi));
            mesh.positions.push_back(center + glm::vec3(p));
        }
    }
    // Both indices wrap, so the seams share vertices and the torus is closed.
    auto at = [nMajor, nMinor](std::uint32_t i, std::uint32_t j) {
        return (i % nMajor) * nMinor + (j % nMinor);
    };
    // d/dphi x d/dtheta points into the tube, so each quad is walked (i,j) (i,j+1) (i+1,j+1)
    // (i+1,j): counter-clockwise seen from outside.
    mesh.triangles.reserve(2 * std::size_t(nMajor) * nMinor);
    for (std::uint32_t i = 0; i < nMajor; ++i) {
        for (std::uint32_t j = 0; j < nMinor; ++j) {
            const std::uint32_t p00 = at(i, j), p01 = at(i, j + 1);
            const std::uint32_t p11 = at(i + 1, j + 1), p10 = at(i + 1, j);
            mesh.triangles.emplace_back(p00, p01, p11);
            mesh.triangles.emplace_back(p00, p11, p10);
        }
    }
    return mesh;
}

void displaceRadially(MeshData& mesh, const glm::vec3& center, float amplitude,
                      std::uint32_t seed) {
    if (!isFinite(center) || !std::isfinite(amplitude)) {
        throw InputError("displaceRadially: center and amplitude must be finite");
    }
    if (!(amplitude >= 0.0f)) {
        throw InputError("displaceRadially: amplitude must be >= 0, got " +
                         std::to_string(amplitude));
    }
    // Check everything first so that a bad call leaves the mesh untouched.
    for (const glm::vec3& p : mesh.positions) {
        if (!isFinite(p)) throw InputError("displaceRadially: mesh has a non-finite position");
        // A vertex moved through the centre would flip its direction, and the triangles with it.
        if (!(glm::length(glm::dvec3(p) - glm::dvec3(center)) > double(amplitude))) {
            throw InputError("displaceRadially: vertex " + str(p) + " is within amplitude " +
                             std::to_string(amplitude) + " of the center " + str(center));
        }
    }
    const glm::dvec3 c(center);
    for (glm::vec3& p : mesh.positions) {
        const glm::dvec3 d = glm::dvec3(p) - c;
        const double r = glm::length(d);
        const double offset = double(amplitude) * (2.0 * positionNoise(seed, p) - 1.0);
        p = glm::vec3(c + d * ((r + offset) / r));
    }
}

} // namespace geometry
