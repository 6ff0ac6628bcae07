// The influence bounds of a silhouette group (conservative bounds of its volume and wedges within
// the scene) and the shadow cone bounds of an occluder box.
#include "SilhouetteDetail.h"

namespace geometry {

namespace {


// The 12 box edges as pairs of corner indices (boxCorner: bit 0 = x, bit 1 = y, bit 2 = z).
constexpr std::array<std::array<int, 2>, 12> kBoxEdges = {{{0, 1}, {2, 3}, {4, 5}, {6, 7},
                                                           {0, 2}, {1, 3}, {4, 6}, {5, 7},
                                                           {0, 4}, {1, 5}, {2, 6}, {3, 7}}};

constexpr int kMixedFaces = -1;

// Extends `bounds` by the part of the ray p + t d (t >= 0) inside `box`. Returns the box face
// the ray leaves through (2 axis + (d[axis] > 0)) when it starts inside the box, else
// kMixedFaces.
int extendRayInBox(Aabb& bounds, const glm::vec3& p, const glm::vec3& d, const Aabb& box) {
    float t0 = 0.0f, t1 = std::numeric_limits<float>::infinity();
    int face = kMixedFaces;
    for (int k = 0; k < 3; ++k) {
        if (d[k] == 0.0f) {
            if (p[k] < box.min[k] || p[k] > box.max[k]) return kMixedFaces;
            continue;
        }
        const float inv = 1.0f / d[k];
        const float a = (box.min[k] - p[k]) * inv, b = (box.max[k] - p[k]) * inv;
        t0 = std::max(t0, std::min(a, b));
        const float exit = std::max(a, b);
        if (exit < t1) {
            t1 = exit;
            face = 2 * k + (d[k] > 0.0f ? 1 : 0);
        }
    }
    if (t0 > t1) return kMixedFaces;
    bounds.extend(p + t0 * d);
    bounds.extend(p + t1 * d);
    return t0 > 0.0f ? kMixedFaces : face;
}

// Common exit face of several rays: kMixedFaces as soon as two differ.
int mergeFaces(int a, int b) { return a == b ? a : kMixedFaces; }

// A wedge's rays from both its end points, as extendRayInBox for each (the same bounds and the
// same common exit face), but with each ray's reciprocal computed once for both ends, and for an
// end inside the box (always, for a scene box around the mesh) without the entry parameter: from
// inside the box every ray enters at t = 0, at the end point itself, which the caller's bounds
// already hold (occluderBounds), and leaves where the first of its three exit slabs ends.
int extendWedgeRaysInBox(Aabb& bounds, const glm::vec3& e0, const glm::vec3& e1,
                         const WedgeRays& rays, const Aabb& box) {
    if (!contains(box, e0) || !contains(box, e1)) {
        int face = extendRayInBox(bounds, e0, rays.dirs[0], box);
        for (int r = 0; r < rays.count; ++r) {
            if (r > 0) face = mergeFaces(face, extendRayInBox(bounds, e0, rays.dirs[r], box));
            face = mergeFaces(face, extendRayInBox(bounds, e1, rays.dirs[r], box));
        }
        return face;
    }
    bounds.extend(e0);
    bounds.extend(e1);
    const glm::vec3 lo0 = box.min - e0, hi0 = box.max - e0; // lo <= 0 <= hi
    const glm::vec3 lo1 = box.min - e1, hi1 = box.max - e1;
    glm::vec3 bmin = bounds.min, bmax = bounds.max;
    int face = kMixedFaces - 1; // not set yet
    for (int r = 0; r < rays.count; ++r) {
        const glm::vec3 d = rays.dirs[r];
        float t0 = std::numeric_limits<float>::infinity(), t1 = t0;
        int f0 = kMixedFaces, f1 = kMixedFaces;
        for (int k = 0; k < 3; ++k) {
            if (d[k] == 0.0f) continue; // parallel to this slab, and inside it
            const float inv = 1.0f / d[k];
            const bool up = d[k] > 0.0f;
            const float a = (up ? hi0[k] : lo0[k]) * inv, b = (up ? hi1[k] : lo1[k]) * inv;
            // Strictly smaller, in axis order: the face extendRayInBox reports.
            if (a < t0) {
                t0 = a;
                f0 = 2 * k + up;
            }
            if (b < t1) {
                t1 = b;
                f1 = 2 * k + up;
            }
        }
        const glm::vec3 x0 = e0 + t0 * d, x1 = e1 + t1 * d;
        bmin = glm::min(bmin, glm::min(x0, x1));
        bmax = glm::max(bmax, glm::max(x0, x1));
        face = mergeFaces(face == kMixedFaces - 1 ? f0 : face, f0);
        face = mergeFaces(face, f1);
    }
    bounds.min = bmin;
    bounds.max = bmax;
    return face == kMixedFaces - 1 ? kMixedFaces : face;
}

// Where the group can change visibility, clamped to the scene: the AABB of
// (volume ∪ wedges) ∩ box, for the wedges as built (their float planes, which are looser than
// the exact E + cone{e_i - c_j}: see wedgeRecessionRays in geometry/shadow/Wedge.h).
//
// The extreme points of a convex piece P ∩ box are vertices: vertices of P inside the box,
// crossings of P's edges with box faces, crossings of P's facets with box edges, and box
// corners inside P. For a wedge P = conv(V) + C, V its finite vertices (at E, within the
// planes' outward push) and C the recession cone above, so its edges are segments near E
// (occluderBounds) and rays v + t r (r an extreme ray of C), approximated by e0 + t r and
// e1 + t r: points of P (e0, e1 are in P, r in C) within the push of the true edges, which the
// final padding covers. Facet crossings and corners use the stored planes, evaluated in float
// exactly as wedgeContains does. The volume's boundary is its caps (in occluderBounds or at
// infinity) and side quads, which lie inside the wedges (the light centre is a light point),
// so with wedges only box corners inside the volume need a test of their own; without wedges
// the side quads' rays and box-edge crossings are used instead.
//
// Work is ordered by cost: rays first, then box edges and corners, and those only where they can
// matter. When every edge ray of a piece P starts inside the box and leaves it through the same
// face F, P ∩ box = P ∩ (F's half-space), a bounded polytope whose vertices are P's finite
// vertices and the ray exits on F (every recession direction of P leaves through F): no box
// edge or corner can add anything. That holds for almost every wedge in practice (a penumbra
// falls on one wall), so the per-edge box tests run only for the few pieces that straddle a box
// edge, and only for box edges and corners still outside the bounds.
//
// With wedges, pass 1 (the rays) runs in update() as each wedge is built, while its rays are at
// hand from the builder (WedgeRayPass below); `rayBounds` and `straddles` are its result.
// A float no greater than x (finite x within float range): x rounded, and when that rounded up,
// moved down by at least one ulp (|f| 2^-23 is one or two ulps; FLT_MIN covers f = 0).
inline float floatAtMost(double x) {
    const auto f = static_cast<float>(x);
    if (static_cast<double>(f) <= x) return f;
    return f - (std::abs(f) * 0x1p-23f + std::numeric_limits<float>::min());
}

// InfluenceBoundsMode::OccluderCone: the bounds of R ∩ S for
//     R = { a + t (a - y) : a in B, y in L, t >= 0 }
// (B the occluder box, L the light, S the scene box). R holds the group's volume (a on its
// triangles, y the light centre) and the exact wedge E + cone{e - y} of every edge in B.
//
// Why this is conservative (not just "the corner rays clipped to S", which need not be): for a
// fixed t, the points (1 + t) a - t y form the Minkowski sum (1 + t) B + (-t) L, which lies in the
// box Q(t) = [lo(t), hi(t)] with, per axis k (L's box [Lmin, Lmax]),
//     lo_k(t) = Bmin_k + t (Bmin_k - Lmax_k),   hi_k(t) = Bmax_k + t (Bmax_k - Lmin_k).
// A point P of R ∩ S lies in Q(t) ∩ S for its own t, so t is in T = { t >= 0 : Q(t) meets S },
// an interval (each "Q(t) meets S on axis k" is a pair of linear inequalities in t), and
// P_k is in [max(lo_k(t), Smin_k), min(hi_k(t), Smax_k)]. Over t in T those ends are extreme at
// T's ends (lo_k and hi_k are linear), which gives the bounds; at an infinite end a decreasing
// lo_k (or increasing hi_k) reaches S's face.
//
// Rounding, and the float planes of wedges built elsewhere (slightly outside the exact wedges,
// by an angle: so by more the farther from the edge): B and S are grown by a margin (growing B
// by m grows R by (1 + t) m, which follows that angle), and the result is clamped to S.
} // namespace

namespace silhouette_detail {

void WedgeRayPass::add(const Wedge& wedge, const WedgeRays& rays, const Aabb& box,
                   std::uint8_t& straddle) {
    if (whole || (wedge.flags & kWedgeDegenerate)) return;
    if (rays.count < 0) {
        whole = true; // may reach any point of the scene
        return;
    }
    const int face = extendWedgeRaysInBox(bounds, glm::vec3(wedge.e0), glm::vec3(wedge.e1),
                                          rays, box);
    straddle = face == kMixedFaces;
    // Typical in interiors (the light inside, walls all around): the group's penumbrae
    // already reach every wall, nothing further can grow the bounds.
    whole = coversBox(bounds, box);
}

Aabb influenceBounds(const SilhouetteFrame& frame, const SilhouetteGroup& group,
                     const Topology& topo, const glm::vec3& lc, const Aabb& box, bool wedges,
                     const Aabb& rayBounds, std::vector<std::uint8_t>& straddles) {
    if (box.empty()) return Aabb{};
    const auto positions = topo.positions();
    Aabb b = wedges ? rayBounds : group.occluderBounds;
    std::array<glm::vec3, 8> corners;
    for (int i = 0; i < 8; ++i) corners[i] = boxCorner(box, i);
    const std::uint32_t edgeEnd = group.firstEdge + group.edgeCount;
    const Wedge* groupWedges = wedges ? frame.wedges.wedges.data() + group.firstWedge : nullptr;

    // Pass 1 without wedges: the side quads' rays, and which quads straddle a box edge.
    if (!wedges) {
        straddles.assign(group.edgeCount, 0);
        for (std::uint32_t k = group.firstEdge; k < edgeEnd; ++k) {
            const glm::vec3 e0 = positions[frame.edges[k].v0];
            const glm::vec3 e1 = positions[frame.edges[k].v1];
            // The side quad's two edge rays (a vertex at the light casts none).
            int face = e0 != lc ? extendRayInBox(b, e0, e0 - lc, box) : kMixedFaces;
            face = mergeFaces(face, e1 != lc ? extendRayInBox(b, e1, e1 - lc, box) : kMixedFaces);
            straddles[k - group.firstEdge] = face == kMixedFaces;
            if (coversBox(b, box)) return box;
        }
    }

    // Pass 2: box edges and corners not yet inside the bounds.
    std::uint32_t cornersOut = 0, edgesOut = 0;
    const auto updateOutside = [&] {
        cornersOut = 0;
        for (int i = 0; i < 8; ++i) cornersOut |= contains(b, corners[i]) ? 0u : 1u << i;
        edgesOut = 0;
        for (int e = 0; e < 12; ++e) {
            // An edge is covered when both its ends are (the bounds are a box).
            edgesOut |= (cornersOut >> kBoxEdges[e][0] | cornersOut >> kBoxEdges[e][1]) & 1u
                            ? 1u << e
                            : 0u;
        }
    };
    updateOutside();
    for (std::uint32_t k = group.firstEdge; k < edgeEnd && edgesOut != 0; ++k) {
        if (!straddles[k - group.firstEdge]) continue;
        const Aabb before = b;
        if (wedges) {
            const Wedge& wedge = groupWedges[k - group.firstEdge];
            if (wedge.flags & kWedgeDegenerate) continue;
            // f[p][c]: plane p at corner c, as wedgeContains evaluates it.
            std::array<std::array<float, 8>, kMaxWedgePlanes> f;
            const auto planeCount = static_cast<int>(wedge.planeCount);
            for (int p = 0; p < planeCount; ++p) {
                const glm::vec4& pl = wedge.planes[p];
                for (int c = 0; c < 8; ++c)
                    f[p][c] = glm::dot(glm::vec3(pl), corners[c]) + pl.w;
            }
            for (int c = 0; c < 8; ++c) {
                if (!(cornersOut >> c & 1u)) continue;
                bool inside = true;
                for (int p = 0; p < planeCount && inside; ++p) inside = f[p][c] <= 0.0f;
                if (inside) b.extend(corners[c]);
            }
            for (int e = 0; e < 12; ++e) {
                if (!(edgesOut >> e & 1u)) continue;
                const int ca = kBoxEdges[e][0], cb = kBoxEdges[e][1];
                float t0 = 0.0f, t1 = 1.0f;
                for (int p = 0; p < planeCount && t0 <= t1; ++p) {
                    const float fa = f[p][ca], fb = f[p][cb];
                    if (fa <= 0.0f && fb <= 0.0f) continue;
                    if (fa > 0.0f && fb > 0.0f) {
                        t1 = -1.0f;
                        break;
                    }
                    const float t = fa / (fa - fb);
                    if (fa > 0.0f) {
                        t0 = std::max(t0, t);
                    } else {
                        t1 = std::min(t1, t);
                    }
                }
                if (t0 > t1) continue;
                const glm::vec3 d = corners[cb] - corners[ca];
                b.extend(corners[ca] + t0 * d);
                b.extend(corners[ca] + t1 * d);
            }
        } else {
            // The side quad E + cone{e0 - lc, e1 - lc} (planar) against the box edges.
            const glm::dvec3 l(lc);
            const glm::dvec3 r0 = glm::dvec3(positions[frame.edges[k].v0]) - l;
            const glm::dvec3 r1 = glm::dvec3(positions[frame.edges[k].v1]) - l;
            const glm::dvec3 n = glm::cross(r0, r1);
            const double nn = glm::dot(n, n);
            if (nn == 0.0) continue; // edge in line with the light: a flat, empty quad
            std::array<double, 8> f;
            for (int c = 0; c < 8; ++c) f[c] = glm::dot(n, glm::dvec3(corners[c]) - l);
            const double onPlane = 1e-9 * std::sqrt(nn) * (glm::length(box.extent()) + 1.0);
            for (int e = 0; e < 12; ++e) {
                if (!(edgesOut >> e & 1u)) continue;
                const int ca = kBoxEdges[e][0], cb = kBoxEdges[e][1];
                const double fa = f[ca], fb = f[cb];
                if (std::abs(fa) <= onPlane && std::abs(fb) <= onPlane) {
                    // Box edge in the quad's plane: conservatively take it whole.
                    b.extend(corners[ca]);
                    b.extend(corners[cb]);
                    continue;
                }
                if ((fa > 0.0 && fb > 0.0) || (fa < 0.0 && fb < 0.0)) continue;
                const double t = fa / (fa - fb);
                const glm::dvec3 a(corners[ca]);
                const glm::dvec3 x = a + t * (glm::dvec3(corners[cb]) - a) - l;
                // x = alpha r0 + beta r1 with alpha, beta >= 0 and alpha + beta >= 1 (beyond E).
                const double alpha = glm::dot(glm::cross(x, r1), n) / nn;
                const double beta = glm::dot(glm::cross(r0, x), n) / nn;
                constexpr double kTol = 1e-9;
                if (alpha >= -kTol && beta >= -kTol && alpha + beta >= 1.0 - kTol)
                    b.extend(glm::vec3(x + l));
            }
        }
        if (b.min != before.min || b.max != before.max) updateOutside();
    }

    // Box corners inside the volume (the segment to the light centre crosses one of the
    // group's triangles). Corners inside a wedge were taken above.
    const auto groupTriangles = std::span<const std::uint32_t>(frame.triangles)
                                    .subspan(group.firstTriangle, group.triangleCount);
    for (int i = 0; i < 8; ++i) {
        if (!(cornersOut >> i & 1u) || contains(b, corners[i])) continue;
        const glm::dvec3 p(corners[i]);
        double t0, t1;
        if (!clipRay(p, glm::dvec3(lc) - p, group.occluderBounds, 1.0, t0, t1)) continue;
        bool inside = group.triangleCount > kExactCornerTestLimit; // conservative for big groups
        for (std::size_t j = 0; j < groupTriangles.size() && !inside; ++j) {
            const glm::uvec3 tri = topo.triangles()[groupTriangles[j] & ~kTriangleFlipped];
            inside = segmentHitsTriangle(p, glm::dvec3(lc), glm::dvec3(positions[tri.x]),
                                         glm::dvec3(positions[tri.y]),
                                         glm::dvec3(positions[tri.z]));
        }
        if (inside) b.extend(corners[i]);
    }

    // Float rounding of the clipped points and the push of the wedge planes: pad by a hair,
    // then clamp to the scene.
    const glm::vec3 pad = 1e-5f * (box.extent() + glm::vec3(1e-6f));
    b.min = glm::max(b.min - pad, box.min);
    b.max = glm::min(b.max + pad, box.max);
    if (b.min.x > b.max.x || b.min.y > b.max.y || b.min.z > b.max.z) return Aabb{};
    return b;
}

Aabb occluderConeBounds(const Aabb& occluder, const LightBox& light, const Aabb& scene) {
    if (scene.empty() || occluder.empty()) return Aabb{};
    const glm::dvec3 sceneExtent(scene.extent());
    const double margin =
        1e-5 * std::max({sceneExtent.x, sceneExtent.y, sceneExtent.z, 1e-6});
    const glm::dvec3 bMin = glm::dvec3(occluder.min) - margin;
    const glm::dvec3 bMax = glm::dvec3(occluder.max) + margin;
    const glm::dvec3 sMin = glm::dvec3(scene.min) - margin;
    const glm::dvec3 sMax = glm::dvec3(scene.max) + margin;
    const glm::dvec3 loSlope = bMin - light.max, hiSlope = bMax - light.min;
    constexpr double kInf = std::numeric_limits<double>::infinity();
    double t0 = 0.0, t1 = kInf;
    // f0 + f1 t <= g on T.
    const auto constrain = [&](double f0, double f1, double g) {
        if (f1 > 0.0) {
            t1 = std::min(t1, (g - f0) / f1);
        } else if (f1 < 0.0) {
            t0 = std::max(t0, (g - f0) / f1);
        } else if (f0 > g) {
            t1 = -1.0;
        }
    };
    for (int k = 0; k < 3; ++k) {
        constrain(bMin[k], loSlope[k], sMax[k]);    // lo_k(t) <= Smax_k
        constrain(-bMax[k], -hiSlope[k], -sMin[k]); // hi_k(t) >= Smin_k
    }
    if (!(t0 <= t1)) return Aabb{};
    Aabb b;
    for (int k = 0; k < 3; ++k) {
        const double loEnd = loSlope[k] >= 0.0 ? t0 : t1;
        const double hiEnd = hiSlope[k] <= 0.0 ? t0 : t1;
        const double lo = loEnd == kInf ? -kInf : bMin[k] + loEnd * loSlope[k];
        const double hi = hiEnd == kInf ? kInf : bMax[k] + hiEnd * hiSlope[k];
        // Rounded outward to float, then clamped to the scene.
        b.min[k] = std::max(floatAtMost(std::max(lo, sMin[k])), scene.min[k]);
        b.max[k] = std::min(-floatAtMost(-std::min(hi, sMax[k])), scene.max[k]);
    }
    if (b.min.x > b.max.x || b.min.y > b.max.y || b.min.z > b.max.z) return Aabb{};
    return b;
}

} // namespace silhouette_detail

} // namespace geometry
