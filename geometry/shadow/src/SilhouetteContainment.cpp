// Whether the light centre lies inside a closed mesh (which decides the one-sided rule): a box
// test, else the winding number by signed ray crossings.
#include "SilhouetteDetail.h"

namespace geometry {

namespace {

// Generic directions for the containment rays (no axis-aligned or diagonal ties with
// axis-aligned meshes); the next is tried when a ray passes too close to an edge.
constexpr std::array<std::array<double, 3>, 4> kContainmentDirs = {{{0.3241, 0.8127, 0.4842},
                                                                    {-0.7053, 0.2671, 0.6567},
                                                                    {0.5512, -0.4117, -0.7257},
                                                                    {-0.2089, -0.8736, 0.4395}}};

// Whether the ray l + t d (t >= 0) meets the box grown by pad.
bool rayMeetsBox(const glm::dvec3& l, const glm::dvec3& d, const Aabb& box, double pad) {
    double t0 = 0.0, t1 = std::numeric_limits<double>::infinity();
    for (int k = 0; k < 3; ++k) {
        const double lo = double(box.min[k]) - pad, hi = double(box.max[k]) + pad;
        if (d[k] == 0.0) {
            if (l[k] < lo || l[k] > hi) return false;
            continue;
        }
        double a = (lo - l[k]) / d[k], b = (hi - l[k]) / d[k];
        if (a > b) std::swap(a, b);
        t0 = std::max(t0, a);
        t1 = std::min(t1, b);
        if (t0 > t1) return false;
    }
    return true;
}

} // namespace

// Winding number of the closed mesh at the light centre by signed ray crossings: +1 for each
// triangle the ray leaves through (along its normal), -1 for each it enters through. Unsure when
// the centre lies on a triangle (within 1e-7 of the mesh size along the ray), or when every ray
// tried passes within rounding distance of an edge or vertex.
SilhouetteExtractor::Scratch::Containment
SilhouetteExtractor::Scratch::rayContainment(const Topology& topology,
                                             const glm::dvec3& l) const {
    const auto positions = topology.positions();
    const std::size_t clusterCount = clusterOffsets.size() - 1;
    const double pad = 1e-6 * meshScale;
    const double onSurface = 1e-7 * meshScale;
    for (const auto& dirValues : kContainmentDirs) {
        const glm::dvec3 d = glm::normalize(glm::dvec3(dirValues[0], dirValues[1], dirValues[2]));
        int winding = 0;
        bool tie = false;
        for (std::size_t c = 0; c < clusterCount && !tie; ++c) {
            if (!rayMeetsBox(l, d, clusterBounds[c], pad)) continue;
            for (std::uint32_t t = clusterOffsets[c]; t < clusterOffsets[c + 1]; ++t) {
                const glm::uvec3 tri = localTriangles[t];
                const glm::dvec3 da = glm::dvec3(positions[tri.x]) - l;
                const glm::dvec3 db = glm::dvec3(positions[tri.y]) - l;
                const glm::dvec3 dc = glm::dvec3(positions[tri.z]) - l;
                // The line l + t d passes through the triangle when these three agree in sign
                // (signed volumes of d with each edge seen from l); their sum is dot(n, d).
                const double pa = glm::dot(d, glm::cross(db, dc));
                const double pb = glm::dot(d, glm::cross(dc, da));
                const double pc = glm::dot(d, glm::cross(da, db));
                const double r = std::max({glm::length(da), glm::length(db), glm::length(dc)});
                const double tol = 1e-10 * r * r;
                const double lo = std::min({pa, pb, pc}), hi = std::max({pa, pb, pc});
                if (lo < -tol && hi > tol) continue; // clearly beside the triangle
                const glm::dvec3 n = glm::cross(db - da, dc - da);
                const double nd = glm::dot(n, d);
                if (lo > tol || hi < -tol) {
                    const double along = glm::dot(n, da) / nd; // ray parameter of the plane
                    if (std::abs(along) <= onSurface) return Containment::Unsure;
                    if (along > 0.0) winding += nd > 0.0 ? 1 : -1;
                    continue;
                }
                // Near an edge or vertex, or in the triangle's plane: a tie unless the triangle
                // lies wholly behind the centre.
                const double back = -1e-9 * r;
                if (glm::dot(da, d) < back && glm::dot(db, d) < back && glm::dot(dc, d) < back)
                    continue;
                tie = true;
                break;
            }
        }
        if (!tie) return winding != 0 ? Containment::Inside : Containment::Outside;
    }
    return Containment::Unsure;
}

SilhouetteExtractor::Scratch::Containment
SilhouetteExtractor::Scratch::lightContainment(const Topology& topology, const glm::vec3& light) {
    if (haveContainment && containmentLight == light) return containment;
    const glm::dvec3 l(light);
    const double pad = 1e-6 * meshScale;
    bool inBox = !meshBounds.empty();
    for (int k = 0; k < 3 && inBox; ++k)
        inBox = l[k] >= double(meshBounds.min[k]) - pad && l[k] <= double(meshBounds.max[k]) + pad;
    containment = inBox ? rayContainment(topology, l) : Containment::Outside;
    containmentLight = light;
    haveContainment = true;
    return containment;
}

} // namespace geometry
