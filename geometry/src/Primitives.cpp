// Analytic scene shapes as triangle meshes. Positions are shared wherever faces meet so that the
// closed shapes (box, sphere) are 2-manifolds even before welding; winding is counter-clockwise
// seen from outside, which the shadow-volume code uses to tell light-facing triangles.
#include <geometry/Primitives.h>

#include <geometry/Error.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <sstream>
#include <string>

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

} // namespace geometry
