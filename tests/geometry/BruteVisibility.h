// Brute-force visibility shared by the geometry tests (BlendModelTest, WedgeTest): exact
// segment-triangle tests in double precision over a midpoint grid of light points, independent of
// the projected polygons, wedges and coverage formulas the tests check.
#pragma once

#include <geometry/core/Types.h>

#include <glm/glm.hpp>

#include <cmath>
#include <vector>

namespace testutil {

// Segment p -> q against triangle (a, b, c), double precision, open segment.
inline bool segmentHitsTriangle(const glm::dvec3& p, const glm::dvec3& q, const glm::dvec3& a,
                                const glm::dvec3& b, const glm::dvec3& c) {
    const glm::dvec3 dir = q - p;
    const glm::dvec3 ab = b - a, ac = c - a;
    const glm::dvec3 pv = glm::cross(dir, ac);
    const double det = glm::dot(ab, pv);
    if (std::abs(det) < 1e-300) return false;
    const glm::dvec3 tv = p - a;
    const double u = glm::dot(tv, pv) / det;
    if (u < 0.0 || u > 1.0) return false;
    const glm::dvec3 qv = glm::cross(tv, ab);
    const double v = glm::dot(dir, qv) / det;
    if (v < 0.0 || u + v > 1.0) return false;
    const double t = glm::dot(ac, qv) / det;
    return t > 0.0 && t < 1.0;
}

// Midpoint rule over an n x n grid of light points with exact segment-triangle tests. A triangle
// is three corners (float or double), p a point (float or double); both are taken in double.
template <class Triangle, class Point>
double gridVisibility(const std::vector<Triangle>& tris, const geometry::RectLight& light,
                      const Point& p, int n) {
    using glm::dvec3;
    int visible = 0;
    for (int j = 0; j < n; ++j) {
        for (int i = 0; i < n; ++i) {
            const double s = -1.0 + (2.0 * i + 1.0) / n, t = -1.0 + (2.0 * j + 1.0) / n;
            const dvec3 y = dvec3(light.center) + s * dvec3(light.u) + t * dvec3(light.v);
            bool blocked = false;
            for (const Triangle& tr : tris) {
                if (segmentHitsTriangle(dvec3(p), y, dvec3(tr[0]), dvec3(tr[1]), dvec3(tr[2]))) {
                    blocked = true;
                    break;
                }
            }
            visible += blocked ? 0 : 1;
        }
    }
    return static_cast<double>(visible) / (static_cast<double>(n) * n);
}

} // namespace testutil
