// Light/geometry contact test. Each triangle is mapped affinely into the light's frame
// (s, t, d): light coordinates and signed distance to the light plane. The points of the triangle
// within `tol` of the light rectangle (up to the per-axis slack described in LightCheck.h) are
// then exactly the triangle clipped by the six half-spaces |d| <= tol, |s| <= sMax, |t| <= tMax,
// and there is a contact iff that convex set is non-empty. One clipping pipeline thus covers the
// transversal case (a thin strip around the triangle/plane segment), the coplanar case (the whole
// triangle) and touching within tolerance, with no special cases to get wrong.
#include <geometry/scene/LightCheck.h>

#include <geometry/core/Error.h>

#include <algorithm>
#include <array>
#include <cfloat>
#include <cmath>
#include <sstream>

namespace geometry {
namespace {

// Sutherland-Hodgman on a convex polygon of n vertices keeps k and adds at most 2*min(k, n - k)
// crossings, so it outputs at most 1.5n vertices even when rounding makes the polygon slightly
// non-convex. Six clips of a triangle: 3 -> 4 -> 6 -> 9 -> 13 -> 19 -> 28.
constexpr std::size_t kMaxVertices = 28;

// A point in light space: x = s, y = t, z = signed distance to the light plane.
using Poly = std::array<glm::dvec3, kMaxVertices>;

// Keeps the part of in[0, n) where sign * p[axis] <= bound; returns the output vertex count.
std::size_t clip(const Poly& in, std::size_t n, Poly& out, int axis, double sign, double bound) {
    std::size_t m = 0;
    for (std::size_t i = 0; i < n; ++i) {
        const glm::dvec3& a = in[i];
        const glm::dvec3& b = in[i + 1 == n ? 0 : i + 1];
        const double fa = sign * a[axis] - bound;
        const double fb = sign * b[axis] - bound;
        if (fa <= 0.0) out[m++] = a;
        if ((fa < 0.0 && fb > 0.0) || (fa > 0.0 && fb < 0.0)) {
            glm::dvec3 p = a + (fa / (fa - fb)) * (b - a);
            // Exactly on the clip plane: with tol = 0 the opposite slab plane is the same plane,
            // and a rounding error of one ulp to the wrong side would lose a real crossing.
            p[axis] = sign * bound;
            out[m++] = p;
        }
    }
    return m;
}

// The light in doubles, with what every triangle needs precomputed.
struct LightFrame {
    glm::dvec3 center;
    glm::dvec3 u;
    glm::dvec3 v;
    glm::dvec3 normal; // unit
    // Inverse of the Gram matrix [u.u u.v; u.v v.v]: u and v need not be orthogonal, so s and t
    // are not simply dot(w, u) / |u|^2.
    double invUU = 0.0;
    double invUV = 0.0;
    double invVV = 0.0;

    glm::dvec3 toLight(const glm::vec3& p) const {
        const glm::dvec3 w = glm::dvec3(p) - center;
        const double wu = glm::dot(w, u);
        const double wv = glm::dot(w, v);
        return {invUU * wu + invUV * wv, invUV * wu + invVV * wv, glm::dot(w, normal)};
    }
};

std::string formatCoordinate(float x) {
    // Two decimals are plenty to locate the contact; + 0.0 turns -0 into 0.
    std::ostringstream s;
    s << std::round(double(x) * 100.0) / 100.0 + 0.0;
    return s.str();
}

} // namespace

std::optional<LightContact> findLightContact(const Scene& scene, float tolerance) {
    return findLightContact(scene, scene.light, tolerance);
}

std::optional<LightContact> findLightContact(const Scene& scene, const RectLight& light,
                                             float tolerance) {
    LightFrame f;
    f.center = glm::dvec3(light.center);
    f.u = glm::dvec3(light.u);
    f.v = glm::dvec3(light.v);
    const glm::dvec3 cross = glm::cross(f.u, f.v);
    const double crossLen = glm::length(cross);
    const double uu = glm::dot(f.u, f.u);
    const double uv = glm::dot(f.u, f.v);
    const double vv = glm::dot(f.v, f.v);
    const double det = uu * vv - uv * uv; // = |u x v|^2
    if (!(crossLen > 0.0) || !(det > 0.0) || !std::isfinite(det)) return std::nullopt;
    f.normal = cross / crossLen;
    f.invUU = vv / det;
    f.invUV = -uv / det;
    f.invVV = uu / det;

    const double tol = tolerance > 0.0f ? double(tolerance) : 0.0;
    // A world distance tol across the edge s = 1 (parallel to v) is tol / (|u x v| / |v|) in s.
    const double sMax = 1.0 + tol * std::sqrt(vv) / crossLen;
    const double tMax = 1.0 + tol * std::sqrt(uu) / crossLen;

    Poly a;
    Poly b;
    for (std::size_t o = 0; o < scene.objects.size(); ++o) {
        const MeshData& mesh = scene.objects[o].mesh;
        for (std::size_t i = 0; i < mesh.triangles.size(); ++i) {
            const glm::uvec3& tri = mesh.triangles[i];
            a[0] = f.toLight(mesh.positions[tri.x]);
            a[1] = f.toLight(mesh.positions[tri.y]);
            a[2] = f.toLight(mesh.positions[tri.z]);
            // Nearly every triangle is rejected here, on the side of one of the six half-spaces;
            // only the few near the light reach the clipping.
            bool outside = false;
            for (int axis = 0; axis < 3 && !outside; ++axis) {
                const double bound = axis == 0 ? sMax : axis == 1 ? tMax : tol;
                const double lo = std::min({a[0][axis], a[1][axis], a[2][axis]});
                const double hi = std::max({a[0][axis], a[1][axis], a[2][axis]});
                outside = lo > bound || hi < -bound;
            }
            if (outside) continue;

            // Slab first: it discards most of what passed the bounds test. Ping-pong a/b.
            std::size_t n = clip(a, 3, b, 2, 1.0, tol);
            n = clip(b, n, a, 2, -1.0, tol);
            n = clip(a, n, b, 0, 1.0, sMax);
            n = clip(b, n, a, 0, -1.0, sMax);
            n = clip(a, n, b, 1, 1.0, tMax);
            n = clip(b, n, a, 1, -1.0, tMax);
            if (n == 0) continue;

            // The vertex average lies in the (convex) contact region; clamp because the region
            // may extend into the tolerance margin just outside [-1, 1]^2.
            glm::dvec3 sum(0.0);
            for (std::size_t k = 0; k < n; ++k)
                sum += a[k];
            const glm::dvec2 st = glm::clamp(glm::dvec2(sum) / double(n), -1.0, 1.0);
            return LightContact{o, i, glm::vec2(st)};
        }
    }
    return std::nullopt;
}

void validateLightClear(const Scene& scene) { validateLightClear(scene, scene.light, {}); }

float contactTolerance(const RectLight& light) {
    const glm::dvec3 c(light.center), u(light.u), v(light.v);
    // The light's own size and where it is, not the scene's extent: one far-away or huge object
    // must not make every surface within metres of the light "touch" it.
    const double diagonal = 2.0 * std::sqrt(glm::dot(u, u) + glm::dot(v, v));
    const glm::dvec3 reach = glm::abs(c) + glm::abs(u) + glm::abs(v); // bounds |light point|
    const double magnitude = std::max({reach.x, reach.y, reach.z});
    return float(std::max(1e-4 * diagonal, 4.0 * double(FLT_EPSILON) * magnitude));
}

void validateLightClear(const Scene& scene, const RectLight& light, std::string_view what) {
    const auto contact = findLightContact(scene, light, contactTolerance(light));
    if (!contact) return;
    const std::string origin = scene.source.empty() ? "scene" : scene.source.string();
    throw LightRefusedError(origin + ": " + (what.empty() ? std::string("light") : std::string(what)) +
                     " intersects object '" + scene.objects[contact->object].name +
                     "' (triangle " + std::to_string(contact->triangle) + ") near light (s " +
                     formatCoordinate(contact->st.x) + ", t " + formatCoordinate(contact->st.y) +
                     "): move or shrink the light");
}

} // namespace geometry
