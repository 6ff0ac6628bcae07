// Exact visibility for horizontal rectangles under a horizontal rectangular light: the ground
// truth of DESIGN.md §4 "Reference" (the uncovered fraction of the light, computed exactly).
#include <geometry/reference/Analytic.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <vector>

namespace geometry {

namespace {

// A rectangle in the light plane, in world x and z. Doubles: the union is summed from many
// cells and the tests compare against it at 1e-6.
struct PlaneRect {
    double x0, x1, z0, z1;
};

std::size_t indexOf(const std::vector<double>& sorted, double value) {
    return static_cast<std::size_t>(std::lower_bound(sorted.begin(), sorted.end(), value) -
                                    sorted.begin());
}

// Area of the union of rectangles by coordinate compression: the distinct x and z edges cut the
// plane into cells that are either fully inside or fully outside every rectangle, so marking
// cells and summing the marked ones is exact (up to rounding). k rectangles give at most
// (2k+1)^2 cells, which is nothing for the handful of occluders a test uses.
double unionArea(const std::vector<PlaneRect>& rects) {
    if (rects.empty()) return 0.0;
    std::vector<double> xs, zs;
    xs.reserve(2 * rects.size());
    zs.reserve(2 * rects.size());
    for (const PlaneRect& r : rects) {
        xs.insert(xs.end(), {r.x0, r.x1});
        zs.insert(zs.end(), {r.z0, r.z1});
    }
    std::sort(xs.begin(), xs.end());
    xs.erase(std::unique(xs.begin(), xs.end()), xs.end());
    std::sort(zs.begin(), zs.end());
    zs.erase(std::unique(zs.begin(), zs.end()), zs.end());
    if (xs.size() < 2 || zs.size() < 2) return 0.0;

    const std::size_t cellsX = xs.size() - 1;
    const std::size_t cellsZ = zs.size() - 1;
    std::vector<unsigned char> covered(cellsX * cellsZ, 0);
    for (const PlaneRect& r : rects) {
        const std::size_t i0 = indexOf(xs, r.x0), i1 = indexOf(xs, r.x1);
        const std::size_t j0 = indexOf(zs, r.z0), j1 = indexOf(zs, r.z1);
        for (std::size_t j = j0; j < j1; ++j) {
            for (std::size_t i = i0; i < i1; ++i) covered[j * cellsX + i] = 1;
        }
    }
    double area = 0.0;
    for (std::size_t j = 0; j < cellsZ; ++j) {
        for (std::size_t i = 0; i < cellsX; ++i) {
            if (covered[j * cellsX + i]) area += (xs[i + 1] - xs[i]) * (zs[j + 1] - zs[j]);
        }
    }
    return area;
}

} // namespace

float visibilityParallelRects(const RectLight& light, std::span<const HorizontalRect> occluders,
                              const glm::vec3& p) {
    // The closed form needs the light's own axes to be the world x and z axes; anything else is a
    // misuse of this helper, not a case to approximate.
    if (light.u.y != 0.0f || light.u.z != 0.0f || light.v.x != 0.0f || light.v.y != 0.0f ||
        light.u.x == 0.0f || light.v.z == 0.0f) {
        throw std::invalid_argument(
            "visibilityParallelRects: the light must be horizontal and axis aligned "
            "(u along x, v along z, both non-zero)");
    }
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) {
        return std::numeric_limits<float>::quiet_NaN();
    }

    const double lx0 = static_cast<double>(light.center.x) - std::abs(light.u.x);
    const double lx1 = static_cast<double>(light.center.x) + std::abs(light.u.x);
    const double lz0 = static_cast<double>(light.center.z) - std::abs(light.v.z);
    const double lz1 = static_cast<double>(light.center.z) + std::abs(light.v.z);
    const double ly = light.center.y;
    const double px = p.x, py = p.y, pz = p.z;

    std::vector<PlaneRect> projected;
    projected.reserve(occluders.size());
    for (const HorizontalRect& o : occluders) {
        const double oy = o.y;
        // Only an occluder strictly between P and the light plane can block a segment P -> y.
        // Below P, at P's height (P on its plane) or at/above the light it blocks nothing.
        if (!(oy > py && oy < ly)) continue;
        // Central projection from P onto the light plane: scale about P by k > 1. A positive
        // scale keeps the rectangle a rectangle with the same edge order.
        const double k = (ly - py) / (oy - py);
        PlaneRect r{px + (std::min(o.x0, o.x1) - px) * k, px + (std::max(o.x0, o.x1) - px) * k,
                    pz + (std::min(o.z0, o.z1) - pz) * k, pz + (std::max(o.z0, o.z1) - pz) * k};
        r.x0 = std::max(r.x0, lx0);
        r.x1 = std::min(r.x1, lx1);
        r.z0 = std::max(r.z0, lz0);
        r.z1 = std::min(r.z1, lz1);
        if (r.x0 < r.x1 && r.z0 < r.z1) projected.push_back(r);
    }

    const double lightArea = (lx1 - lx0) * (lz1 - lz0);
    const double v = 1.0 - unionArea(projected) / lightArea;
    return static_cast<float>(std::clamp(v, 0.0, 1.0));
}

} // namespace geometry
