// The double model of a silhouette group's light-sample mask (geometry/models/MaskModel.h).
#include <geometry/models/MaskModel.h>

#include <geometry/core/Error.h>
#include <geometry/core/LightFrame.h>

#include <algorithm>
#include <cmath>
#include <string>

namespace geometry {

namespace {

using glm::dvec2;
using glm::dvec3;

// Signed distance of y from the half-plane dot(h, (y, 1)) >= 0, in light coordinates.
double halfPlaneDistance(const dvec3& h, const dvec2& y) {
    const double len = std::hypot(h.x, h.y);
    return len > 0.0 ? glm::dot(h, dvec3(y, 1.0)) / len : glm::dot(h, dvec3(y, 1.0));
}

// Whether the light centre (the origin) lies within `tolerance` of the projected edge q0 q1
// (homogeneous; a point with w = 0 is at infinity in the direction (x, y)).
bool centreNear(const dvec3& q0, const dvec3& q1, double tolerance) {
    if (q0.z <= 0.0 && q1.z <= 0.0) return false; // the whole edge at infinity
    if (q0.z <= 0.0 || q1.z <= 0.0) {             // a ray from the finite end
        const dvec3& f = q0.z > 0.0 ? q0 : q1;
        const dvec3& d = q0.z > 0.0 ? q1 : q0;
        const dvec2 a = dvec2(f) / f.z, dir = glm::normalize(dvec2(d));
        const double t = std::max(0.0, -glm::dot(a, dir));
        return glm::length(a + t * dir) < tolerance;
    }
    const dvec2 a = dvec2(q0) / q0.z, b = dvec2(q1) / q1.z;
    const dvec2 ab = b - a;
    const double len2 = glm::dot(ab, ab);
    const double t = len2 > 0.0 ? std::clamp(-glm::dot(a, ab) / len2, 0.0, 1.0) : 0.0;
    return glm::length(a + t * ab) < tolerance;
}

} // namespace

GroupMaskModel groupMaskModel(const dvec3& p, std::span<const MaskEdge> edges, int centreCount,
                              const RectLight& rect, std::span<const glm::vec2> samples,
                              double tolerance, double centreTolerance) {
    const std::size_t n = samples.size();
    const std::size_t words = (n + 31) / 32;
    GroupMaskModel model;
    model.count.assign(n, centreCount);
    model.ambiguous.assign(words, 0u);
    const LightFrame light = lightFrame(rect);
    const dvec3 pc = p - light.c;
    const double hp = glm::dot(light.n, pc);
    if (hp != 0.0) {
        for (const MaskEdge& e : edges) {
            // Heights over p's level relative to the light's (z: 1 at p's level, 0 on the light's
            // plane) and depths w = 1 - z; only the part with both in [0, 1] can block.
            const double z0 = glm::dot(light.n, e.first - light.c) / hp;
            const double z1 = glm::dot(light.n, e.second - light.c) / hp;
            double lo = 0.0, hi = 1.0;
            auto keep = [&](double f0, double f1) { // the l where f0 + l (f1 - f0) >= 0
                if (f0 >= 0.0 && f1 >= 0.0) return lo <= hi;
                if (f0 < 0.0 && f1 < 0.0) return false;
                const double l = f0 / (f0 - f1);
                if (f0 < 0.0)
                    lo = std::max(lo, l);
                else
                    hi = std::min(hi, l);
                return lo <= hi;
            };
            if (!keep(z0, z1) || !keep(1.0 - z0, 1.0 - z1)) continue;
            // The projection from p onto the light's plane, homogeneous: w (y - c) =
            // (x - c) - z (p - c) with w = 1 - z.
            auto project = [&](double l) {
                const dvec3 x = e.first + l * (e.second - e.first);
                const double z = z0 + l * (z1 - z0);
                const dvec3 y = (x - light.c) - z * pc;
                return dvec3(glm::dot(light.uStar, y), glm::dot(light.vStar, y), 1.0 - z);
            };
            const dvec3 q0 = project(lo), q1 = project(hi);
            const double cr = q0.x * q1.y - q0.y * q1.x;
            if (cr == 0.0) continue;
            const double sg = cr > 0.0 ? 1.0 : -1.0;
            const dvec3 h0(-sg * q0.y, sg * q0.x, 0.0);
            const dvec3 h1(sg * q1.y, -sg * q1.x, 0.0);
            const dvec3 h2 = -sg * glm::cross(q0, q1);
            const int sign = hp > 0.0 ? int(sg) : -int(sg); // edgeCoverage's sign
            if (centreNear(q0, q1, centreTolerance)) model.centreAmbiguous = true;
            for (std::size_t i = 0; i < n; ++i) {
                const dvec2 y(samples[i]);
                const double a = halfPlaneDistance(h0, y);
                const double b = halfPlaneDistance(h1, y);
                const double c = halfPlaneDistance(h2, y);
                // On a ray: the edge on its counter-clockwise side (shaders/shared/LightMask.h).
                const bool in0 = sg > 0.0 ? a >= 0.0 : a > 0.0;
                const bool in1 = sg > 0.0 ? b > 0.0 : b >= 0.0;
                if (in0 && in1 && c >= 0.0) model.count[i] += sign;
                if (a >= -tolerance && b >= -tolerance && c >= -tolerance &&
                    std::min({std::abs(a), std::abs(b), std::abs(c)}) < tolerance)
                    model.ambiguous[i / 32] |= 1u << (i % 32);
            }
        }
    }
    // Parity: the centre's state toggled by each crossing, i.e. count parity relative to the
    // centre's, with the centre hidden when its count is non-zero.
    model.parity.assign(words, 0u);
    const bool centreHidden = centreCount != 0;
    for (std::size_t i = 0; i < n; ++i) {
        const bool toggled = ((model.count[i] - centreCount) & 1) != 0;
        if (centreHidden != toggled) model.parity[i / 32] |= 1u << (i % 32);
    }
    return model;
}

int segmentCrossings(const dvec3& a, const dvec3& b,
                     std::span<const std::array<dvec3, 3>> triangles) {
    const dvec3 d = b - a;
    int crossings = 0;
    for (const auto& t : triangles) {
        // Moller-Trumbore style: a + s d = t0 + beta (t1 - t0) + gamma (t2 - t0).
        const dvec3 e1 = t[1] - t[0], e2 = t[2] - t[0];
        const dvec3 pv = glm::cross(d, e2);
        const double det = glm::dot(e1, pv);
        if (det == 0.0) continue;
        const dvec3 tv = a - t[0];
        const double beta = glm::dot(tv, pv) / det;
        if (beta < 0.0 || beta > 1.0) continue;
        const dvec3 qv = glm::cross(tv, e1);
        const double gamma = glm::dot(d, qv) / det;
        if (gamma < 0.0 || beta + gamma > 1.0) continue;
        const double s = glm::dot(e2, qv) / det;
        // Crossings within 1e-4 of either end are the end points' own surfaces: a receiver on
        // its occluder's face, whose G-buffer point may lie a float step inside it, the segment
        // leaving at a grazing angle near the terminator (the volumes' offset caps leave its
        // own face out too).
        if (s > 1e-4 && s < 1.0 - 1e-4) ++crossings;
    }
    return crossings;
}

} // namespace geometry

namespace geometry {

namespace {

// The part of a triangle strictly between p's level (z = 1) and the light's plane (z = 0), z
// the height over the light's plane over p's, as a convex polygon.
std::vector<glm::dvec3> clipToSlab(const std::array<glm::dvec3, 3>& t, const glm::dvec3& n,
                                   const glm::dvec3& c, double ap) {
    std::vector<glm::dvec3> poly(t.begin(), t.end()), next;
    const auto z = [&](const glm::dvec3& x) { return glm::dot(n, x - c) / ap; };
    for (int side = 0; side < 2; ++side) {
        // side 0: keep z >= 0; side 1: keep z <= 1.
        next.clear();
        const auto f = [&](const glm::dvec3& x) { return side == 0 ? z(x) : 1.0 - z(x); };
        for (std::size_t i = 0; i < poly.size(); ++i) {
            const glm::dvec3& a = poly[i];
            const glm::dvec3& b = poly[(i + 1) % poly.size()];
            const double fa = f(a), fb = f(b);
            if (fa >= 0.0) next.push_back(a);
            if ((fa >= 0.0) != (fb >= 0.0)) next.push_back(a + (b - a) * (fa / (fa - fb)));
        }
        poly.swap(next);
        if (poly.size() < 3) return {};
    }
    return poly;
}

} // namespace

CountModel potentialCountModel(const glm::dvec3& p,
                               std::span<const std::array<glm::dvec3, 3>> triangles,
                               const RectLight& light, std::span<const glm::vec2> samples,
                               double tolerance, double centreTolerance) {
    const LightFrame f = lightFrame(light);
    CountModel m;
    m.count.assign(samples.size(), 0);
    m.ambiguous.assign((samples.size() + 31) / 32, 0u);
    const double ap = glm::dot(f.n, p - f.c);
    if (ap == 0.0) return m;
    std::vector<glm::dvec3> q, lines;
    for (const auto& t : triangles) {
        // Wholly at or beyond p's level, or at or beyond the light's plane: nothing in between
        // (the common case; decided before clipping).
        const double z0 = glm::dot(f.n, t[0] - f.c) / ap, z1 = glm::dot(f.n, t[1] - f.c) / ap,
                     z2 = glm::dot(f.n, t[2] - f.c) / ap;
        if ((z0 <= 0.0 && z1 <= 0.0 && z2 <= 0.0) || (z0 >= 1.0 && z1 >= 1.0 && z2 >= 1.0))
            continue;
        const std::vector<glm::dvec3> poly = clipToSlab(t, f.n, f.c, ap);
        if (poly.empty()) continue;
        // Homogeneous light coordinates (s w, t w, w) of each vertex's projection from p, w = 1 - z
        // >= 0 (0: at infinity, a vertex at p's level).
        q.clear();
        for (const glm::dvec3& x : poly) {
            const double w = std::max(0.0, 1.0 - glm::dot(f.n, x - f.c) / ap);
            const glm::dvec3 y = w * (p - f.c) + (x - p);
            q.emplace_back(glm::dot(f.uStar, y), glm::dot(f.vStar, y), w);
        }
        glm::dvec3 inner(0.0);
        for (const glm::dvec3& x : q) inner += x / std::max(glm::length(x), 1e-300);
        lines.clear();
        for (std::size_t i = 0; i < q.size(); ++i) {
            glm::dvec3 l = glm::cross(q[i], q[(i + 1) % q.size()]);
            const double len = std::hypot(l.x, l.y);
            if (!(len > 0.0)) continue;
            l /= len; // dot(l, (s, t, 1)): signed distance in light coordinates
            if (glm::dot(l, inner) < 0.0) l = -l;
            lines.push_back(l);
        }
        if (lines.size() < 3) continue;
        const auto classify = [&](double s, double tt, double tol, bool& ambiguous) {
            double least = 1e300;
            for (const glm::dvec3& l : lines) least = std::min(least, l.x * s + l.y * tt + l.z);
            ambiguous = std::abs(least) < tol;
            return least > 0.0;
        };
        bool amb = false;
        if (classify(0.0, 0.0, centreTolerance, amb)) ++m.centreCount;
        m.centreAmbiguous = m.centreAmbiguous || amb;
        for (std::size_t i = 0; i < samples.size(); ++i) {
            if (classify(samples[i].x, samples[i].y, tolerance, amb)) ++m.count[i];
            if (amb) m.ambiguous[i / 32] |= 1u << (i % 32);
        }
    }
    return m;
}

} // namespace geometry
