#include <geometry/shadow/PotentialSilhouettes.h>

#include "SilhouetteDetail.h"

#include <array>
#include <cmath>

namespace geometry {

namespace {

// Which side of its plane the light lies on: +1 / -1 when every corner is strictly on the side
// of orient(y, a, b, c) > 0 / < 0, 0 when the plane straddles the light (or nearly touches it).
int lightSide(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c,
              const std::array<glm::dvec3, 4>& corners) {
    const glm::dvec3 n = glm::cross(b - a, c - a);
    const double len = glm::length(n);
    if (!(len > 0.0)) return 0;
    int pos = 0, neg = 0;
    for (const glm::dvec3& y : corners) {
        // orient(y, a, b, c) = det(a - y, b - a, c - a) = dot(a - y, n).
        const double d = glm::dot(a - y, n);
        const double tol = 1e-9 * len * (glm::length(a - y) + glm::length(b - a) + glm::length(c - a));
        if (d > tol) ++pos;
        else if (d < -tol) ++neg;
        else return 0;
    }
    return pos == 4 ? 1 : neg == 4 ? -1 : 0;
}

std::uint32_t thirdVertex(const glm::uvec3& tri, const Edge& e) {
    for (int k = 0; k < 3; ++k)
        if (tri[k] != e.v0 && tri[k] != e.v1) return tri[k];
    return kNoApex; // not reached: topology drops degenerate triangles
}

} // namespace

PotentialEdgeStats potentialSilhouetteEdges(const Topology& topology, const RectLight& light,
                                            std::vector<PotentialEdge>& out) {
    out.clear();
    PotentialEdgeStats stats;
    const auto positions = topology.positions();
    const auto triangles = topology.triangles();
    const auto edges = topology.edges();
    const auto offsets = topology.edgeUseOffsets();
    const auto uses = topology.edgeUses();
    const glm::dvec3 c(light.center), u(light.u), v(light.v);
    const std::array<glm::dvec3, 4> corners{c - u - v, c + u - v, c + u + v, c - u + v};
    // Per triangle, the side of its plane the light is on (orient(y, a, b, c) in its winding).
    std::vector<std::int8_t> side(triangles.size());
    for (std::size_t t = 0; t < triangles.size(); ++t) {
        const glm::uvec3 tri = triangles[t];
        side[t] = static_cast<std::int8_t>(lightSide(glm::dvec3(positions[tri.x]),
                                                     glm::dvec3(positions[tri.y]),
                                                     glm::dvec3(positions[tri.z]), corners));
    }
    for (std::size_t e = 0; e < edges.size(); ++e) {
        const std::uint32_t first = offsets[e], last = offsets[e + 1];
        const std::uint32_t count = last - first;
        if (count == 0) continue;
        if (count == 2) {
            // orient(y, v0, v1, w_i) = sign_i * orient(y, triangle i's winding): the edge is a
            // silhouette from y where the two have the same sign. Never, when each has one sign
            // over the light and the two differ.
            const EdgeUse a = uses[first], b = uses[first + 1];
            const int fa = a.sign * side[a.triangle], fb = b.sign * side[b.triangle];
            if (fa != 0 && fb != 0 && fa != fb) {
                ++stats.skipped;
                continue;
            }
            ++stats.interior;
        } else if (count == 1) {
            ++stats.boundary;
        } else {
            ++stats.nonManifold;
        }
        for (std::uint32_t k = first; k < last; k += 2) {
            PotentialEdge p{edges[e].v0, edges[e].v1, {kNoApex, kNoApex}};
            p.apex[0] = thirdVertex(triangles[uses[k].triangle], edges[e]);
            if (k + 1 < last) p.apex[1] = thirdVertex(triangles[uses[k + 1].triangle], edges[e]);
            out.push_back(p);
        }
    }
    return stats;
}

Aabb occluderInfluenceBounds(const Aabb& occluder, const RectLight& light, const Aabb& scene) {
    return silhouette_detail::occluderConeBounds(occluder, silhouette_detail::LightBox(light),
                                                 scene);
}

} // namespace geometry
