#include <geometry/shadow/PotentialSilhouettes.h>

#include "SilhouetteDetail.h"

#include <array>
#include <cmath>
#include <vector>

namespace geometry {

namespace {

// a + b as s + err exactly (Knuth's two-sum; no overflow in scene coordinates).
double twoSum(double a, double b, double& err) {
    const double s = a + b;
    const double bv = s - a;
    err = (a - (s - bv)) + (b - bv);
    return s;
}

// Adds b to the expansion e (a sum of doubles whose value is exact): the old components become
// the rounding errors of the running sum, and the sum is appended (Shewchuk's grow-expansion).
void growExpansion(std::vector<double>& e, double b) {
    double q = b;
    for (double& x : e) {
        double err = 0.0;
        q = twoSum(q, x, err);
        x = err;
    }
    e.push_back(q);
}

// Whether a, b, c, d (float coordinates) lie exactly in one plane: orient(a, b, c, d) = 0 in
// exact arithmetic. The differences are exact in double where the coordinates' exponents are
// within 29 of each other (checked: false where one is not), each of the determinant's six triple
// products is four doubles exactly (fused multiply-add's product errors), and their sum is
// accumulated without rounding: zero only if every component is.
bool exactlyCoplanar(const glm::vec3& a, const glm::vec3& b, const glm::vec3& c, const glm::vec3& d) {
    std::array<glm::dvec3, 3> r;
    const std::array<const glm::vec3*, 3> to{&b, &c, &d};
    for (int i = 0; i < 3; ++i)
        for (int k = 0; k < 3; ++k) {
            double err = 0.0;
            r[i][k] = twoSum(double((*to[i])[k]), -double(a[k]), err);
            if (err != 0.0) return false;
        }
    // A filter first: the determinant in double, with a bound on its rounding error (far above
    // Shewchuk's orient3d bound of about 7 epsilon times the permanent), is clearly not zero on
    // most pairs.
    const double det = glm::dot(r[0], glm::cross(r[1], r[2]));
    const glm::dvec3 a0 = glm::abs(r[0]), a1 = glm::abs(r[1]), a2 = glm::abs(r[2]);
    const double permanent = a0.x * (a1.y * a2.z + a1.z * a2.y) + a0.y * (a1.z * a2.x + a1.x * a2.z) +
                             a0.z * (a1.x * a2.y + a1.y * a2.x);
    if (std::abs(det) > 1e-12 * permanent) return false;
    std::vector<double> sum;
    sum.reserve(32);
    // det(r0, r1, r2) = sum over permutations (i, j, k) of sign * r0[i] r1[j] r2[k].
    constexpr int kPerm[6][3] = {{0, 1, 2}, {1, 2, 0}, {2, 0, 1}, {0, 2, 1}, {2, 1, 0}, {1, 0, 2}};
    for (int p = 0; p < 6; ++p) {
        const double sign = p < 3 ? 1.0 : -1.0;
        const double x = r[0][kPerm[p][0]], y = r[1][kPerm[p][1]], z = r[2][kPerm[p][2]];
        const double yz = y * z;
        const double yzErr = std::fma(y, z, -yz);
        for (const double f : {yz, yzErr}) {
            const double hi = x * f;
            const double lo = std::fma(x, f, -hi);
            growExpansion(sum, sign * hi);
            growExpansion(sum, sign * lo);
        }
    }
    for (const double x : sum)
        if (x != 0.0) return false;
    return true;
}

std::uint32_t thirdVertex(const glm::uvec3& tri, const Edge& e) {
    for (int k = 0; k < 3; ++k)
        if (tri[k] != e.v0 && tri[k] != e.v1) return tri[k];
    return kNoApex; // not reached: topology drops degenerate triangles
}

} // namespace

PotentialSilhouettes::PotentialSilhouettes(const Topology& topology)
    : mTopology(topology) {
    const auto positions = topology.positions();
    const auto triangles = topology.triangles();
    const auto edges = topology.edges();
    const auto offsets = topology.edgeUseOffsets();
    const auto uses = topology.edgeUses();
    mNormalLength.resize(triangles.size());
    mSideLength.resize(triangles.size());
    for (std::size_t t = 0; t < triangles.size(); ++t) {
        const glm::dvec3 a(positions[triangles[t].x]), b(positions[triangles[t].y]),
            c(positions[triangles[t].z]);
        mNormalLength[t] = glm::length(glm::cross(b - a, c - a));
        mSideLength[t] = glm::length(b - a) + glm::length(c - a);
    }
    mApex.resize(uses.size());
    for (std::size_t e = 0; e < edges.size(); ++e)
        for (std::uint32_t k = offsets[e]; k < offsets[e + 1]; ++k)
            mApex[k] = thirdVertex(triangles[uses[k].triangle], edges[e]);
    mFlat.assign(edges.size(), 2);
    mSide.resize(triangles.size());
}

PotentialEdgeStats PotentialSilhouettes::update(const RectLight& light,
                                                std::vector<PotentialEdge>& out) {
    out.clear();
    PotentialEdgeStats stats;
    const auto positions = mTopology.positions();
    const auto triangles = mTopology.triangles();
    const auto edges = mTopology.edges();
    const auto offsets = mTopology.edgeUseOffsets();
    const auto uses = mTopology.edgeUses();
    const glm::dvec3 c(light.center), u(light.u), v(light.v);
    const std::array<glm::dvec3, 4> corners{c - u - v, c + u - v, c + u + v, c - u + v};
    // Per triangle, the side of its plane the light is on (orient(y, a, b, c) in its winding):
    // +1 / -1 when every corner is strictly on the side of orient > 0 / < 0, 0 when the plane
    // straddles the light or passes within the tolerance 1e-9 |n| (|a - y| + |b - a| + |c - a|)
    // of a corner. |a - y| is bounded by its 1-norm first (the square root only where that
    // bound cannot decide).
    for (std::size_t t = 0; t < triangles.size(); ++t) {
        const glm::uvec3 tri = triangles[t];
        const double len = mNormalLength[t];
        if (!(len > 0.0)) {
            mSide[t] = 0;
            continue;
        }
        const glm::dvec3 a(positions[tri.x]), b(positions[tri.y]), cc(positions[tri.z]);
        const glm::dvec3 n = glm::cross(b - a, cc - a);
        int pos = 0, neg = 0;
        for (const glm::dvec3& y : corners) {
            const glm::dvec3 ay = a - y;
            // orient(y, a, b, c) = det(a - y, b - a, c - a) = dot(a - y, n).
            const double d = glm::dot(ay, n);
            const double l1 = std::abs(ay.x) + std::abs(ay.y) + std::abs(ay.z);
            // (At least the tolerance below: l1 >= |a - y|, and the 0.1 % covers the sums'
            // rounding in either order.)
            const double bound = 1.001e-9 * len * (l1 + mSideLength[t]);
            if (d > bound) {
                ++pos;
                continue;
            }
            if (d < -bound) {
                ++neg;
                continue;
            }
            // (As the bound's: the same terms, summed as before the bound existed.)
            const double tol =
                1e-9 * len * (glm::length(ay) + glm::length(b - a) + glm::length(cc - a));
            if (d > tol) ++pos;
            else if (d < -tol) ++neg;
            else break; // within the tolerance: straddling
        }
        mSide[t] = static_cast<std::int8_t>(pos == 4 ? 1 : neg == 4 ? -1 : 0);
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
            const int fa = a.sign * mSide[a.triangle], fb = b.sign * mSide[b.triangle];
            if (fa != 0 && fb != 0 && fa != fb) {
                ++stats.skipped;
                continue;
            }
            // Two triangles in one plane, on either side of the edge (a flat face's diagonal):
            // orient(y, v0, v1, w) has opposite signs for the two third vertices at every point
            // y, so the edge is a silhouette from nowhere and m_p = 0 at every receiver, whatever
            // the light (straddling the plane, it would be kept above; a box under a lamp).
            if (mFlat[e] == 2) {
                const glm::vec3 p0 = positions[edges[e].v0], p1 = positions[edges[e].v1];
                const glm::vec3 w0 = positions[mApex[first]], w1 = positions[mApex[first + 1]];
                const glm::dvec3 along = glm::dvec3(p1) - glm::dvec3(p0);
                const double across =
                    glm::dot(glm::cross(along, glm::dvec3(w0) - glm::dvec3(p0)),
                             glm::cross(along, glm::dvec3(w1) - glm::dvec3(p0)));
                mFlat[e] = across < 0.0 && exactlyCoplanar(p0, p1, w0, w1) ? 1 : 0;
            }
            if (mFlat[e] == 1) {
                ++stats.skipped;
                continue;
            }
            ++stats.interior;
        } else if (count == 1) {
            ++stats.boundary;
        } else {
            ++stats.nonManifold;
        }
        for (std::uint32_t k = first; k < last; k += 2)
            out.push_back(PotentialEdge{edges[e].v0, edges[e].v1,
                                        {mApex[k], k + 1 < last ? mApex[k + 1] : kNoApex}});
    }
    return stats;
}

PotentialEdgeStats potentialSilhouetteEdges(const Topology& topology, const RectLight& light,
                                            std::vector<PotentialEdge>& out) {
    return PotentialSilhouettes(topology).update(light, out);
}

Aabb occluderInfluenceBounds(const Aabb& occluder, const RectLight& light, const Aabb& scene) {
    return silhouette_detail::occluderConeBounds(occluder, silhouette_detail::LightBox(light),
                                                 scene);
}

} // namespace geometry
