// Penumbra wedges (Assarsson & Akenine-Möller 2003) built as the exact influence region of an
// edge, and the CPU model of the per-fragment edge coverage (DESIGN.md §4).
//
// Construction (see geometry/shadow/Wedge.h): W(E) = E + K with K = cone{e_i - c_j}. K is the cone over
// the parallelepiped P = E - L (half-generators d/2, u, v around the mid point), so
// - K is pointed exactly when 0 is not in P, i.e. when E does not touch L (else: unbounded);
// - every facet of K is the cone over an edge of P seen from 0, and P's edges join generators
//   that differ by one of d, 2u, 2v: pairs (e0 - c_j, e0 - c_j+1), (e1 - c_j, e1 - c_j+1) (the
//   side planes of each end's pyramid) and (e0 - c_j, e1 - c_j) (planes holding d: front/back);
// - a facet of W = E + K with normal n is face_E(n) + face_K(n): facets of K anchored at the end
//   point maximising dot(n, .), plus the planes holding d tangent to K (front and back).
// So the facets follow from the cyclic order of K's extreme rays (a convex hull of at most 8
// directions): no search over the 36 candidate pairs of the brute force (WedgeTest compares the
// two). Every plane is then tilted until all eight generators are strictly inside, so rounding
// in the construction can only loosen the wedge, never break containment. The one configuration
// without a cyclic order is an edge lying in the light's plane (beside the light): K is flat,
// and the planes are found by a small candidate search instead.
#include <geometry/shadow/Wedge.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#if defined(__SSE2__)
#include <immintrin.h>
#endif

namespace geometry {
namespace {

using glm::dvec2;
using glm::dvec3;

// Tolerances, all relative (unit vectors or scaled by the local size):
constexpr double kParallelSin = 1e-6; // flat case: |a x b| below this gives no candidate plane
constexpr double kOnPlane = 1e-9;     // |dot(n, unit dir)| below this: the direction is on the
                                      // plane (anchor ties; flat-case candidate validation)
constexpr double kSameDir = 1e-6;     // unit generators closer than this are one ray of K (and
                                      // one mesh vertex: they must differ after float rounding;
                                      // the tilt still checks every generator)
constexpr double kSameNormal = 1e-7;  // flat case: normals closer than this are one plane
// Float safety. After rounding to float, a plane's normal is off by ~1e-7 and evaluating
// dot(n, p) + w in float errs by ~3e-7 (|p| + |w|). Two measures keep every exact point of W
// inside the float planes:
// - tilt: the normal is rotated towards -q, inside the polar cone K° (q the point of E - L
//   closest to the origin), until every generator g has dot(n, g) <= -kMargin |g|, so points
//   far along the shadow rays gain a margin growing like kMargin |p - anchor| (more than the
//   4e-7 |p - anchor| of rounding, so rays stay inside out to infinity);
// - push: the plane moves outward by kPush (|anchor| + |e1 - e0|), which covers the rounding of
//   w and of the finite part (the edge itself, which gets no margin from the tilt).
constexpr double kMargin = 4e-6;
constexpr double kPush = 4e-6;
constexpr double kUnbounded = 2.0 * kMargin; // below this best margin: treated as touching

using Frame = WedgeBuilder::Frame;

Frame makeFrame(const RectLight& light) {
    Frame f;
    static_cast<LightFrame&>(f) = lightFrame(light);
    f.corners = {f.c - f.u - f.v, f.c + f.u - f.v, f.c + f.u + f.v, f.c - f.u + f.v};
    return f;
}

// Restricts [lo, hi] to the λ where the affine f0 + λ (f1 - f0) is <= 0; false when empty.
bool clipLe0(double f0, double f1, double& lo, double& hi) {
    if (f0 <= 0.0 && f1 <= 0.0) return lo <= hi;
    if (f0 > 0.0 && f1 > 0.0) return false;
    const double l = f0 / (f0 - f1);
    if (f0 > 0.0) lo = std::max(lo, l);
    else hi = std::min(hi, l);
    return lo <= hi;
}

// Closest points of a segment p0 + s (p1 - p0) and a segment q0 + t (q1 - q0), s, t in [0, 1],
// both of non-zero length: minimise the convex quadratic |x(s) - y(t)|^2, first unconstrained in
// s for the optimal t(s), then clamping t and re-solving s (the minimiser of a convex quadratic
// over a box lies on the clamped line of the free variable).
void closestOnSegments(const dvec3& p0, const dvec3& p1, const dvec3& q0, const dvec3& q1,
                       double& s, double& t) {
    const dvec3 dp = p1 - p0, dq = q1 - q0, r = p0 - q0;
    const double a = glm::dot(dp, dp), e = glm::dot(dq, dq), b = glm::dot(dp, dq);
    const double c = glm::dot(dp, r), fq = glm::dot(dq, r);
    const double denom = a * e - b * b; // >= 0; 0 for parallel segments
    s = denom > 1e-14 * a * e ? std::clamp((b * fq - c * e) / denom, 0.0, 1.0) : 0.0;
    t = (b * s + fq) / e;
    if (t < 0.0) {
        t = 0.0;
        s = std::clamp(-c / a, 0.0, 1.0);
    } else if (t > 1.0) {
        t = 1.0;
        s = std::clamp((b - c) / a, 0.0, 1.0);
    }
}

// The point of P = E - L closest to the origin, q = a - y for the closest pair a in E, y in L.
// K = cone(P) is pointed iff q != 0, and dot(q, x) >= |q|^2 for every x in P, so -q is the
// interior direction of the polar cone K° with the largest guaranteed margin. The closest pair
// has y inside L with a an end point (the end projects into L), or y on a light edge, or E
// meets L (q = 0).
dvec3 closestOffset(const dvec3& e0, const dvec3& e1, const Frame& f) {
    dvec3 best(0.0);
    double bestLen = std::numeric_limits<double>::infinity();
    auto offer = [&](const dvec3& q) {
        const double l = glm::dot(q, q);
        if (l < bestLen) {
            bestLen = l;
            best = q;
        }
    };
    for (const dvec3& e : {e0, e1}) {
        const dvec3 r = e - f.c;
        if (std::abs(glm::dot(f.uStar, r)) <= 1.0 && std::abs(glm::dot(f.vStar, r)) <= 1.0)
            offer(glm::dot(f.n, r) * f.n);
    }
    // E crossing the light's plane inside the light.
    const double h0 = glm::dot(f.n, e0 - f.c), h1 = glm::dot(f.n, e1 - f.c);
    if ((h0 <= 0.0) != (h1 <= 0.0) || h0 == 0.0 || h1 == 0.0) {
        if (h0 != h1) {
            const dvec3 x = e0 + (h0 / (h0 - h1)) * (e1 - e0) - f.c;
            if (std::abs(glm::dot(f.uStar, x)) <= 1.0 && std::abs(glm::dot(f.vStar, x)) <= 1.0)
                return dvec3(0.0);
        }
    }
    for (int j = 0; j < 4; ++j) {
        const dvec3& c0 = f.corners[j];
        const dvec3& c1 = f.corners[(j + 1) % 4];
        double s, t;
        closestOnSegments(e0, e1, c0, c1, s, t);
        offer((e0 + s * (e1 - e0)) - (c0 + t * (c1 - c0)));
    }
    return best;
}

dvec3 anyPerpendicular(const dvec3& n) {
    const dvec3 a = std::abs(n.x) < 0.6 ? dvec3(1, 0, 0) : dvec3(0, 1, 0);
    return glm::normalize(glm::cross(n, a));
}

double cross2(const dvec2& a, const dvec2& b) { return a.x * b.y - a.y * b.x; }

// Extreme rays of the pointed cone spanned by vecs[0..n) (each with dot(v, axis) > 0), ordered
// counter-clockwise seen from the tip of `axis`; rays inside the cone or on the line between two
// neighbours are dropped. Gnomonic projection onto the plane ⟂ axis maps the cone's rays to
// points and its faces to a convex polygon (great circles become lines), then Andrew's monotone
// chain. Returns the count written to `order`.
int coneHullOrder(const dvec3* vecs, int n, const dvec3& axis, int* order) {
    const dvec3 a = glm::normalize(axis);
    const dvec3 b1 = anyPerpendicular(a);
    const dvec3 b2 = glm::cross(a, b1); // b1 x b2 = a: CCW in (b1, b2) is CCW seen from a
    std::array<dvec2, 16> pts;
    std::array<int, 16> idx;
    double extent = 0.0;
    for (int i = 0; i < n; ++i) {
        const double h = glm::dot(vecs[i], a);
        pts[i] = dvec2(glm::dot(vecs[i], b1), glm::dot(vecs[i], b2)) / h;
        extent = std::max(extent, std::abs(pts[i].x) + std::abs(pts[i].y));
        idx[i] = i;
    }
    // Insertion sort by (x, y): n <= 8, cheaper than std::sort here.
    for (int i = 1; i < n; ++i) {
        const int v = idx[i];
        int j = i;
        for (; j > 0; --j) {
            const dvec2& o = pts[idx[j - 1]];
            if (o.x < pts[v].x || (o.x == pts[v].x && o.y <= pts[v].y)) break;
            idx[j] = idx[j - 1];
        }
        idx[j] = v;
    }
    // The chain itself uses the plain sign of the turn. A collinearity tolerance there is not
    // consistent with the sort: points on a line across the sort direction (an axis-aligned edge
    // and light give four images with one x up to rounding) are sorted by their rounding noise,
    // and a tolerance far above that noise then pops true extreme points and keeps a middle one
    // (a wrong cone, rescued for containment only by the tilt, and a mesh not matching it).
    // With exact signs the chain is the hull of the rounded points; near-collinear vertices
    // (relative to the projected extent) are dropped afterwards, on the hull's cyclic order.
    const double eps = 1e-12 * (extent * extent + 1e-300);
    std::array<int, 32> hull;
    int k = 0;
    auto turn = [&](int o, int p, int q) {
        return cross2(pts[p] - pts[o], pts[q] - pts[o]);
    };
    for (int s = 0; s < n; ++s) {
        const int i = idx[s];
        while (k >= 2 && turn(hull[k - 2], hull[k - 1], i) <= 0.0) --k;
        hull[k++] = i;
    }
    const int lower = k + 1;
    for (int s = n - 2; s >= 0; --s) {
        const int i = idx[s];
        while (k >= lower && turn(hull[k - 2], hull[k - 1], i) <= 0.0) --k;
        hull[k++] = i;
    }
    const int count = k - 1; // the last point repeats the first
    int kept = 0;
    for (int i = 0; i < count; ++i) {
        while (kept >= 2 && turn(order[kept - 2], order[kept - 1], hull[i]) <= eps) --kept;
        order[kept++] = hull[i];
    }
    for (bool changed = true; changed && kept >= 3;) { // the wrap-around vertices
        changed = false;
        if (turn(order[kept - 2], order[kept - 1], order[0]) <= eps) {
            --kept;
            changed = true;
        } else if (turn(order[kept - 1], order[0], order[1]) <= eps) {
            for (int i = 1; i < kept; ++i) order[i - 1] = order[i];
            --kept;
            changed = true;
        }
    }
    return kept >= 3 ? kept : 0; // no area: callers emit nothing
}

struct Plane {
    dvec3 n;    // exact (untilted) unit outward normal, for the mesh
    int anchor; // 0: e0, 1: e1
};

// The general exact construction (every configuration).
std::uint32_t appendExact(const glm::vec3& e0f, const glm::vec3& e1f, const Frame& f,
                          WedgeArrays& out) {
    Wedge wedge;
    for (glm::vec4& p : wedge.planes) p = glm::vec4(0.0f);
    wedge.e0 = glm::vec4(e0f, 1.0f);
    wedge.e1 = glm::vec4(e1f, 1.0f);
    wedge.firstVertex = static_cast<std::uint32_t>(out.vertices.size());
    const auto index = static_cast<std::uint32_t>(out.wedges.size());
    auto finish = [&](std::uint32_t flags) {
        wedge.flags = flags;
        wedge.vertexCount = static_cast<std::uint32_t>(out.vertices.size()) - wedge.firstVertex;
        out.wedges.push_back(wedge);
        return index;
    };

    const bool finite = std::isfinite(e0f.x) && std::isfinite(e0f.y) && std::isfinite(e0f.z) &&
                        std::isfinite(e1f.x) && std::isfinite(e1f.y) && std::isfinite(e1f.z);
    // Zero length (in float, as the GPU sees it): the edge changes no visibility. Non-finite
    // input is not geometry; it gets the same treatment rather than NaN planes.
    if (!finite || e0f == e1f) return finish(kWedgeDegenerate);

    const std::array<dvec3, 2> ends = {dvec3(e0f), dvec3(e1f)};
    const dvec3 d = ends[1] - ends[0];
    const double dLen = glm::length(d);
    const dvec3 dHat = d / dLen;

    // Generators g_j = e0 - c_j (0..3) and h_j = e1 - c_j (4..7), as unit vectors.
    std::array<dvec3, 8> gen;
    for (int j = 0; j < 4; ++j) {
        gen[j] = ends[0] - f.corners[j];
        gen[4 + j] = ends[1] - f.corners[j];
    }
    // Unbounded: E touches L (q = 0: some shadow ray has no direction, K is all of space), or
    // comes so close that K is within kUnbounded of a half-space and no float plane could hold
    // the shadow rays out to infinity with the margin kMargin (see the tilt below).
    const dvec3 q = closestOffset(ends[0], ends[1], f);
    const double qLen = glm::length(q);
    if (!(qLen > 0.0)) return finish(kWedgeUnbounded);
    const dvec3 kHat = -q / qLen; // dot(kHat, g) <= -|q| / |g| for every generator
    double kappa = 1.0;
    for (dvec3& g : gen) {
        g = glm::normalize(g);
        kappa = std::min(kappa, -glm::dot(kHat, g));
    }
    if (kappa < kUnbounded) return finish(kWedgeUnbounded);

    // Extreme rays r_0 .. r_m-1 of K (distinct generator directions on K's boundary),
    // counter-clockwise seen from far along q.
    std::array<dvec3, 8> dirs;
    int dirCount = 0;
    for (const dvec3& g : gen) {
        bool same = false;
        for (int i = 0; i < dirCount && !same; ++i) {
            const dvec3 diff = dirs[i] - g;
            same = glm::dot(diff, diff) < kSameDir * kSameDir;
        }
        if (!same) dirs[dirCount++] = g;
    }
    std::array<int, 16> rays;
    const int m = coneHullOrder(dirs.data(), dirCount, -kHat, rays.data());
    auto ray = [&](int i) -> const dvec3& { return dirs[rays[(i + m) % m]]; };

    // Facets of W = E + K (Minkowski sum of a segment and a cone):
    // - per K facet (r_i, r_i+1), outward normal n_i = r_i+1 x r_i, anchored at the end point
    //   extreme along n_i (e1 when dot(n_i, d) > 0, else e0): the side planes;
    // - per ray r_i where that end point switches: the plane through E and r_i, tangent to L:
    //   the front and back planes. Its normal is the combination of n_i-1 and n_i orthogonal
    //   to d (both are orthogonal to r_i), which lies in K° and needs no cross product of the
    //   possibly near-parallel d and r_i.
    // In exact arithmetic dot(n_i, d) changes sign at most twice around the cycle (a great
    // circle meets the convex polygon of the normals twice): at most 6 + 2 facets.
    std::array<Plane, 24> kept;
    int keptCount = 0;
    std::array<int, 16> anchor;
    if (m >= 3) {
        std::array<dvec3, 16> normals;
        std::array<double, 16> along;
        int start = -1;
        for (int i = 0; i < m; ++i) {
            normals[i] = glm::normalize(glm::cross(ray(i + 1), ray(i)));
            along[i] = glm::dot(normals[i], dHat);
            if (start < 0 && std::abs(along[i]) > kOnPlane) start = i;
        }
        // A facet with dot(n_i, d) ~ 0 holds both end points, so either anchor is exact; it
        // takes its predecessor's, which keeps the e0 and e1 runs contiguous (two switches at
        // most) even when rounding scatters the signs, e.g. for an edge aimed at a corner.
        int current = start >= 0 && along[start] > 0.0 ? 1 : 0;
        for (int k = 0; k < m; ++k) {
            const int i = (std::max(start, 0) + k) % m;
            if (std::abs(along[i]) > kOnPlane) current = along[i] > 0.0 ? 1 : 0;
            anchor[i] = current;
        }
        for (int i = 0; i < m; ++i) {
            const int before = (i + m - 1) % m;
            if (anchor[before] != anchor[i]) {
                const dvec3 n = std::abs(glm::dot(normals[i], d)) * normals[before] +
                                std::abs(glm::dot(normals[before], d)) * normals[i];
                kept[keptCount++] = {glm::normalize(n), 0};
            }
            kept[keptCount++] = {normals[i], anchor[i]};
        }
    } else {
        // K is flat: the edge lies in the light's plane (beside the light), and so does W.
        // Search the planes instead: candidates through pairs of directions and, in the plane,
        // through the light normal and one direction; keep those with every generator on the
        // inner side (both orientations of the light's plane itself).
        auto consider = [&](dvec3 n) {
            const double len = glm::length(n);
            if (len < kParallelSin) return;
            n /= len;
            double lo = 0.0, hi = 0.0;
            for (const dvec3& g : gen) {
                lo = std::min(lo, glm::dot(n, g));
                hi = std::max(hi, glm::dot(n, g));
            }
            for (const dvec3& c : {n, -n}) {
                if (glm::dot(c, n) > 0.0 ? hi > kOnPlane : lo < -kOnPlane) continue;
                bool duplicate = false;
                for (int k = 0; k < keptCount && !duplicate; ++k) {
                    const dvec3 diff = glm::abs(kept[k].n - c);
                    duplicate = std::max({diff.x, diff.y, diff.z}) < kSameNormal;
                }
                if (!duplicate && keptCount < static_cast<int>(kept.size()))
                    kept[keptCount++] = {c, glm::dot(c, d) > 0.0 ? 1 : 0};
            }
        };
        for (int i = 0; i < dirCount; ++i) {
            consider(glm::cross(dHat, dirs[i]));
            consider(glm::cross(f.n, dirs[i]));
            for (int j = i + 1; j < dirCount; ++j) consider(glm::cross(dirs[i], dirs[j]));
        }
        consider(glm::cross(f.n, dHat));
    }
    if (keptCount == 0) return finish(kWedgeUnbounded); // no supporting plane: be conservative

    const int planeCount = std::min(keptCount, kMaxWedgePlanes);
    const std::array<double, 2> push = {kPush * (glm::length(ends[0]) + dLen),
                                        kPush * (glm::length(ends[1]) + dLen)};
    for (int i = 0; i < planeCount; ++i) {
        const dvec3& n = kept[i].n;
        double tau = 0.0;
        for (const dvec3& g : gen) {
            const double s = glm::dot(n, g);
            if (s <= -kMargin) continue;
            const double kg = glm::dot(kHat, g);
            tau = std::max(tau, (kMargin + s) / -kg); // -kg >= kappa > 0
        }
        // With this tau every generator has dot(n', g) <= -kMargin whatever n was, so the
        // plane holds W even if n carried rounding noise; it only gets looser.
        const dvec3 nt = glm::normalize(n + tau * kHat);
        const int e = glm::dot(nt, d) > 0.0 ? 1 : 0; // re-anchored: the tilt may change it
        const double w = -glm::dot(nt, ends[e]) - push[e];
        wedge.planes[i] = glm::vec4(glm::vec3(nt), static_cast<float>(w));
    }
    wedge.planeCount = static_cast<std::uint32_t>(planeCount);

    // Boundary mesh from the same combinatorial structure, so it is closed by construction (no
    // per-facet tolerance decisions that neighbours could disagree on): the cap at infinity
    // (K's cross-section, like a shadow volume's far cap, facing along q), each K facet as the
    // triangle (anchor, r_i+1, r_i), and each front/back facet as the triangle (E, r_i).
    // A flat K has no volume and gets no mesh.
    if (m >= 3) {
        std::array<glm::vec4, 16> dirVerts;
        for (int i = 0; i < m; ++i) dirVerts[i] = glm::vec4(glm::vec3(ray(i)), 0.0f);
        auto dir = [&](int i) -> const glm::vec4& { return dirVerts[(i + m) % m]; };
        const int strips = keptCount - m;
        const std::size_t first = out.vertices.size();
        out.vertices.resize(first + 3 * static_cast<std::size_t>(2 * m - 2 + strips));
        glm::vec4* v = out.vertices.data() + first;
        const std::array<glm::vec4, 2> endVerts = {wedge.e0, wedge.e1};
        auto emit = [&](const glm::vec4& a, const glm::vec4& b, const glm::vec4& c) {
            v[0] = a;
            v[1] = b;
            v[2] = c;
            v += 3;
        };
        for (int i = 1; i + 1 < m; ++i) emit(dir(0), dir(i), dir(i + 1)); // cap
        for (int i = 0; i < m; ++i) {
            emit(endVerts[anchor[i]], dir(i + 1), dir(i)); // K facet at its end point
            const int before = anchor[(i + m - 1) % m];
            if (before != anchor[i]) emit(endVerts[anchor[i]], dir(i), endVerts[before]); // strip
        }
    }
    return finish(0u);
}

// ---- Recession rays of the stored planes ---------------------------------------------------
//
// Every extreme ray of a pointed cone lies on two facets with independent normals, and a
// direction on two planes that no plane excludes is an extreme ray (a face of a face). The
// planes are stored in cyclic order around the cone, so first only neighbouring pairs are tried:
// a pointed cone has at most as many extreme rays as planes, so p distinct rays from the p
// neighbouring pairs are all of them (O(p^2)). Otherwise (redundant or near-duplicate planes,
// another order) every pair is tried (O(p^3), p <= 12). The normals are the stored floats, so
// the rays are those of the cone wedgeContains actually tests, tilt and rounding included.

// Pairs of normals closer than this (sine of the angle) give no ray: the corner of the cone's
// cross-section they would resolve is flatter than any use of the rays needs.
constexpr double kParallelNormals = 1e-7;
// A candidate ray is kept when no plane has it more than this (relative) outside. The normals
// are exact float inputs and the test runs in double, so true rays pass with a wide margin; a
// direction kept by the tolerance is a point of a slightly larger cone: still conservative.
constexpr double kRayTolerance = 1e-9;
// Two planes whose normals differ by less than this (max norm) count once for the rays.
constexpr double kSamePlaneNormal = 1e-9;

// Appends the ray on planes i and j of n[0..count) to `rays` if no plane excludes it and it is
// new (three or more planes through one ray give it several times). Sets `line` when every
// normal is orthogonal to it (C holds a line).
void tryRayPair(const dvec3* n, int count, int i, int j, WedgeRays& rays, bool& line) {
    const dvec3 r = glm::cross(n[i], n[j]);
    const double len = glm::length(r);
    if (len < kParallelNormals) return;
    double hi = 0.0, lo = 0.0;
    for (int k = 0; k < count; ++k) {
        if (k == i || k == j) continue;
        const double s = glm::dot(n[k], r);
        hi = std::max(hi, s);
        lo = std::min(lo, s);
    }
    const double tol = kRayTolerance * len;
    const bool plus = hi <= tol, minus = lo >= -tol;
    if (plus && minus) line = true;
    if (plus == minus) return;
    const glm::vec3 ray((plus ? r : -r) / len);
    for (int k = 0; k < rays.count; ++k) {
        const glm::vec3 diff = glm::abs(rays.dirs[k] - ray);
        if (std::max({diff.x, diff.y, diff.z}) <= 1e-6f) return;
    }
    rays.dirs[rays.count++] = ray;
}

// The neighbouring-pair pass for the fast path's m <= 8 planes, the same arithmetic as
// tryRayPair over the pairs (i, i + 1) (so the same rays, bit for bit), with the pairs' cross
// products, lengths and tests in flat loops the compiler can keep in registers. Returns false
// (rays unspecified) whenever that pass would not have found every ray on its own: a pair too
// close to parallel, a candidate excluded or ambiguous either way (a line, or not a ray of C),
// or a repeated ray; the caller then runs the general derivation.
bool cyclicRays(const dvec3* n, int m, WedgeRays& rays) {
    if (m < 3) return false;
    for (int i = 0; i < m; ++i) {
        const int j = i + 1 < m ? i + 1 : 0;
        const dvec3 r = glm::cross(n[i], n[j]);
        const double len = glm::length(r);
        if (len < kParallelNormals) return false;
        double hi = 0.0, lo = 0.0;
        for (int k = 0; k < m; ++k) {
            const double s = (k == i || k == j) ? 0.0 : glm::dot(n[k], r);
            hi = std::max(hi, s);
            lo = std::min(lo, s);
        }
        const double tol = kRayTolerance * len;
        const bool plus = hi <= tol, minus = lo >= -tol;
        if (plus == minus) return false;
        const glm::vec3 ray((plus ? r : -r) / len);
        for (int k = 0; k < i; ++k) {
            const glm::vec3 diff = glm::abs(rays.dirs[k] - ray);
            if (std::max({diff.x, diff.y, diff.z}) <= 1e-6f) return false;
        }
        rays.dirs[i] = ray;
    }
    rays.count = m;
    return true;
}

// The neighbouring-pair pass alone: true when it found all the rays (see above).
bool neighbourRays(const dvec3* n, int count, WedgeRays& rays, bool& line) {
    rays.count = 0;
    line = false;
    for (int i = 0; i < count && !line; ++i) tryRayPair(n, count, i, (i + 1) % count, rays, line);
    return !line && rays.count == count && count >= 3;
}

// ---- Common-case fast path -------------------------------------------------------------------
//
// Classification, before any hull work: both end points strictly on one side σ of the light's
// plane, h_i = σ dot(n, e_i - c) > 0, and every generator at an elevation
// h_i / |e_i - c_j| >= kFastElevation above that plane. The corners lie in the plane, so
// dot(σ n, g) = h_i for each generator g of end i: -σ n is inside the polar cone K° with margin
// kFastElevation, E cannot touch L (the wedge is bounded; the exact path's q is at least as far
// from 0 as the heights, so it agrees), and K is far from flat.
//
// Extreme rays combinatorially. Project each generator g = e_i - c_j onto the plane at unit
// height along σ n (gnomonic: rays become points, planes through 0 become lines). In the light's
// affine coordinates (s, t) = (dot(u*, .), dot(v*, .)) the image is
//     X_ij = (s_i - S_j, t_i - T_j) / h_i,
// with (s_i, t_i) the coordinates of e_i - c and (S_j, T_j) in {±1}^2 those of corner j. So each
// end's images form the light's parallelogram point-reflected and scaled by 1 / h_i: P_0 and P_1
// are positively homothetic, and K's extreme rays are the vertices of hull(P_0 ∪ P_1). P_i's
// corners X_i0..X_i3 run counter-clockwise in (s, t) (a point reflection is a rotation); its edge
// k (X_ik -> X_ik+1) supports it along +t, -s, -t, +s (k = 0..3) with the values
//     b_k(i) / h_i,   b(i) = (1 + t_i, 1 - s_i, 1 - t_i, 1 + s_i).
// With positive homothety both parallelograms attain the support along any direction at the same
// corner index, so in the normal cone of corner j the union's support is the larger of X_0j and
// X_1j, a linear comparison whose sign at the cone's two bounding normals decides it. Hence with
//     win_k = [b_k(0) h_1 > b_k(1) h_0]   (P_0 reaches further across edge k than P_1)
// the hull is, corner by corner counter-clockwise: X_0j when win_j-1 and win_j, X_1j when
// neither, and both where they differ (the winner of edge j-1 first): a bridge, the facet through
// E and light corner c_j, i.e. a front or back plane (it holds d = e1 - e0). The difference of the
// support functions is (1/h_0 - 1/h_1) times the support function of a translated L (linear when
// h_0 = h_1), negative on at most one arc of directions, so win changes at most twice around: at
// most two bridges and six extreme rays. With no change one pyramid holds the other (the edge
// points into it) and W is that end's pyramid. At a tie (coinciding support lines, e.g. an edge
// parallel to a light side at constant height) all four images of that edge lie on one line, and
// the hull runs along it from corner j's winner of edge j-1 to corner j+1's winner of edge j+1
// (the extreme points of that line): possibly a bridge between different corners, the plane
// through E and that light side.
//
// Facets of W = E + K as in the exact path: per hull edge (r_i, r_i+1) the normal
// cross(r_i+1, r_i), anchored at the end whose generators span it (either end for a bridge, which
// holds d); the exact path's front and back planes are these bridges. Then the same tilt and
// push, which make any normal conservative (towards -σ n instead of -q: cheaper, and looser than
// the exact path by at most kMargin / kFastElevation), and the same boundary mesh structure.
// Falls back to the exact path (returns false, nothing appended) when the two generators of one
// corner, or two consecutive extreme rays, are closer than kFastSeparation (an edge aimed at a
// light corner or very short: a bridge normal would be ill-conditioned, the exact path merges
// such rays), when two adjacent edges tie, or when the win pattern changes more than twice
// (possible only through rounding in a degenerate configuration).
constexpr double kFastElevation = 1e-3;
constexpr double kFastSeparation = 1e-5; // |r_i+1 x r_i| of unit rays: far above the float
                                          // rounding of the mesh directions (6e-8), and the
                                          // cross product keeps ~11 significant digits

// 1 / sqrt(v[i]) for four positive doubles within [1e-30, 1e30], to ~3e-7 relative: the
// hardware estimate and one Newton step (x86 SSE), else the library. The fast path only uses it
// to scale vectors: directions stay exact, and the final float normals carry an error of the
// size of their own rounding (Wedge.h stores them as float).
inline void invSqrt4(const double* v, double* out) {
#if defined(__SSE2__)
    const __m128 a =
        _mm_movelh_ps(_mm_cvtpd_ps(_mm_loadu_pd(v)), _mm_cvtpd_ps(_mm_loadu_pd(v + 2)));
    const __m128 r = _mm_rsqrt_ps(a);
    const __m128 half = _mm_mul_ps(_mm_set1_ps(0.5f), a);
    const __m128 nr =
        _mm_mul_ps(r, _mm_sub_ps(_mm_set1_ps(1.5f), _mm_mul_ps(half, _mm_mul_ps(r, r))));
    _mm_storeu_pd(out, _mm_cvtps_pd(nr));
    _mm_storeu_pd(out + 2, _mm_cvtps_pd(_mm_movehl_ps(nr, nr)));
#else
    for (int i = 0; i < 4; ++i) out[i] = 1.0 / std::sqrt(v[i]);
#endif
}

bool appendFast(const glm::vec3& e0f, const glm::vec3& e1f, const Frame& f,
                WedgeArrays& out, WedgeRays* rays) {
    const dvec3 x0(e0f), x1(e1f);
    const dvec3 r0 = x0 - f.c, r1 = x1 - f.c;
    const double n0 = glm::dot(f.n, r0), n1 = glm::dot(f.n, r1);
    if (!(n0 * n1 > 0.0)) return false; // on both sides or on the plane
    const double sigma = n0 > 0.0 ? 1.0 : -1.0;
    const std::array<double, 2> h = {sigma * n0, sigma * n1};

    // Generators g[4 i + j] = e_i - c_j (structure of arrays: the loops over the eight
    // vectorise), the elevation test, and their unit directions.
    alignas(16) double gx[8], gy[8], gz[8], len2[8], inv[8];
    for (int j = 0; j < 4; ++j) {
        gx[j] = x0.x - f.corners[j].x;
        gy[j] = x0.y - f.corners[j].y;
        gz[j] = x0.z - f.corners[j].z;
        gx[4 + j] = x1.x - f.corners[j].x;
        gy[4 + j] = x1.y - f.corners[j].y;
        gz[4 + j] = x1.z - f.corners[j].z;
    }
    constexpr double kElev2 = kFastElevation * kFastElevation;
    bool common = true;
    for (int k = 0; k < 8; ++k) {
        len2[k] = gx[k] * gx[k] + gy[k] * gy[k] + gz[k] * gz[k];
        const double hk = k < 4 ? h[0] : h[1];
        // (The range keeps invSqrt4's float conversion exact enough.)
        common &= hk * hk >= kElev2 * len2[k] && len2[k] >= 1e-30 && len2[k] <= 1e30;
    }
    if (!common) return false;
    invSqrt4(len2, inv);
    invSqrt4(len2 + 4, inv + 4);
    alignas(16) double ux[8], uy[8], uz[8];
    for (int k = 0; k < 8; ++k) {
        ux[k] = gx[k] * inv[k];
        uy[k] = gy[k] * inv[k];
        uz[k] = gz[k] * inv[k];
    }
    // An edge aimed at (or near) a light corner c_j, or very short: e0 - c_j and e1 - c_j are
    // (nearly) one ray, and the sliver facet between them has an ill-conditioned normal (the
    // exact path merges or keeps it): exact path.
    for (int j = 0; j < 4; ++j) {
        const double dx = ux[j] - ux[4 + j], dy = uy[j] - uy[4 + j], dz = uz[j] - uz[4 + j];
        common &= dx * dx + dy * dy + dz * dz >= kFastSeparation * kFastSeparation;
    }
    if (!common) return false;

    // Extreme rays (generator indices), counter-clockwise in (s, t).
    const double s0 = glm::dot(f.uStar, r0), t0 = glm::dot(f.vStar, r0);
    const double s1 = glm::dot(f.uStar, r1), t1 = glm::dot(f.vStar, r1);
    // win_k: +1 (P_0), -1 (P_1), 0 for a tie within rounding (relative to the magnitudes of the
    // operands). At a tie the hull edge runs along the common support line from the previous
    // corner's winner to the next one's, so a tied edge contributes no vertex of its own: no
    // redundant collinear vertex, plane or triangles (the exact path drops them too). Two
    // adjacent ties mean coinciding images at their corner (the edge aimed at it): exact path.
    const double tie = 1e-12 * (h[0] + h[1]) *
                       (1.0 + std::max({std::abs(s0), std::abs(t0), std::abs(s1), std::abs(t1)}));
    auto compare = [tie](double a, double b) { return a - b > tie ? 1 : b - a > tie ? -1 : 0; };
    const std::array<int, 4> win = {compare((1.0 + t0) * h[1], (1.0 + t1) * h[0]),
                                    compare((1.0 - s0) * h[1], (1.0 - s1) * h[0]),
                                    compare((1.0 - t0) * h[1], (1.0 - t1) * h[0]),
                                    compare((1.0 + s0) * h[1], (1.0 + s1) * h[0])};
    std::array<int, 8> ray;
    int m = 0;
    for (int j = 0; j < 4; ++j) {
        const int before = win[(j + 3) & 3], after = win[j];
        if (before == 0 && after == 0) return false;
        if (before != 0) ray[m++] = (before > 0 ? 0 : 4) + j;
        if (after != 0 && after != before) ray[m++] = (after > 0 ? 0 : 4) + j;
    }
    // Bridges: consecutive extreme rays from different ends (two, or none).
    int bridges = 0;
    for (int i = 0; i < m; ++i) bridges += (ray[i] >> 2) != (ray[i + 1 < m ? i + 1 : 0] >> 2);
    if (bridges > 2) return false; // (so m <= 6)
    // Counter-clockwise seen from the tip of σ n, the cone's axis: (s, t) is counter-clockwise
    // seen from +n (cross(u, v) = |u x v| n), mirrored seen from -n.
    if (sigma < 0.0) std::reverse(ray.begin(), ray.begin() + m);

    // Outward facet normals n_i = r_i+1 x r_i (the exact path's convention), in double.
    alignas(16) double nx[8], ny[8], nz[8], nLen2[8] = {1, 1, 1, 1, 1, 1, 1, 1}, nInv[8];
    for (int i = 0; i < m; ++i) {
        const int a = ray[i + 1 < m ? i + 1 : 0], b = ray[i];
        nx[i] = uy[a] * uz[b] - uz[a] * uy[b];
        ny[i] = uz[a] * ux[b] - ux[a] * uz[b];
        nz[i] = ux[a] * uy[b] - uy[a] * ux[b];
        nLen2[i] = nx[i] * nx[i] + ny[i] * ny[i] + nz[i] * nz[i];
        common &= nLen2[i] >= kFastSeparation * kFastSeparation;
    }
    if (!common) return false;
    invSqrt4(nLen2, nInv);
    invSqrt4(nLen2 + 4, nInv + 4);

    // Tilt towards kHat = -σ n, inside K° with margin >= kFastElevation: -dot(kHat, g_k) is
    // h_i / |g_k| (the corners lie in the light's plane), so 1 / that is |g_k| / h_i and needs no
    // further dot products or divisions.
    const dvec3 kHat = -sigma * f.n;
    const std::array<double, 2> invH = {1.0 / h[0], 1.0 / h[1]};
    // The tilt test runs in float, four generators at a time. A float dot product of (nearly)
    // unit vectors, with its operands rounded to float, is within kFloatSlack = 1e-6 of the
    // double value (~5 * 2^-24 = 3e-7, plus the relative error of invDepth times kMargin), so
    // asking for kMargin + kFloatSlack in float leaves at least kMargin in exact arithmetic.
    constexpr float kTiltMargin = static_cast<float>(kMargin + 1e-6);
    alignas(16) float fx[8], fy[8], fz[8], fInvDepth[8];
    for (int k = 0; k < 8; ++k) {
        fx[k] = static_cast<float>(ux[k]);
        fy[k] = static_cast<float>(uy[k]);
        fz[k] = static_cast<float>(uz[k]);
        fInvDepth[k] = static_cast<float>(len2[k] * inv[k] * (k < 4 ? invH[0] : invH[1]));
    }
    alignas(16) double tx[8], ty[8], tz[8], tLen2[8] = {1, 1, 1, 1, 1, 1, 1, 1}, tInv[8];
    for (int i = 0; i < m; ++i) {
        const double px = nx[i] * nInv[i], py = ny[i] * nInv[i], pz = nz[i] * nInv[i];
        // tau = max(0, max_k (margin + s_k) / depth_k): generators already at -margin or
        // beyond give a non-positive term, so no test is needed.
#if defined(__SSE2__)
        const __m128 qx = _mm_set1_ps(static_cast<float>(px));
        const __m128 qy = _mm_set1_ps(static_cast<float>(py));
        const __m128 qz = _mm_set1_ps(static_cast<float>(pz));
        __m128 best = _mm_setzero_ps();
        for (int k = 0; k < 8; k += 4) {
            const __m128 sx = _mm_mul_ps(qx, _mm_load_ps(fx + k));
            const __m128 sy = _mm_mul_ps(qy, _mm_load_ps(fy + k));
            const __m128 sz = _mm_mul_ps(qz, _mm_load_ps(fz + k));
            const __m128 sk =
                _mm_add_ps(_mm_add_ps(sx, sy), _mm_add_ps(sz, _mm_set1_ps(kTiltMargin)));
            best = _mm_max_ps(best, _mm_mul_ps(sk, _mm_load_ps(fInvDepth + k)));
        }
        best = _mm_max_ps(best, _mm_movehl_ps(best, best));
        best = _mm_max_ss(best, _mm_shuffle_ps(best, best, 1));
        const double tau = _mm_cvtss_f32(best);
#else
        float best = 0.0f;
        for (int k = 0; k < 8; ++k) {
            const float sk = static_cast<float>(px) * fx[k] + static_cast<float>(py) * fy[k] +
                             static_cast<float>(pz) * fz[k] + kTiltMargin;
            best = std::max(best, sk * fInvDepth[k]);
        }
        const double tau = best;
#endif
        // As in the exact path: afterwards every generator has dot(n', g) <= -kMargin whatever
        // rounding n carried, so the plane can only be looser than exact.
        tx[i] = px + tau * kHat.x;
        ty[i] = py + tau * kHat.y;
        tz[i] = pz + tau * kHat.z;
        tLen2[i] = tx[i] * tx[i] + ty[i] * ty[i] + tz[i] * tz[i];
    }
    invSqrt4(tLen2, tInv);
    invSqrt4(tLen2 + 4, tInv + 4);

    Wedge& wedge = out.wedges.emplace_back(); // value-initialised: unused planes are zero
    wedge.e0 = glm::vec4(e0f, 1.0f);
    wedge.e1 = glm::vec4(e1f, 1.0f);
    const dvec3 d = x1 - x0;
    // Push as in the exact path, kPush (|anchor| + |d|), with the lengths bounded above by
    // their 1-norms (a larger push is only safer; at most sqrt(3) times, ~7e-6 of the scene).
    const double dLen = std::abs(d.x) + std::abs(d.y) + std::abs(d.z);
    const std::array<double, 2> push = {
        kPush * (std::abs(x0.x) + std::abs(x0.y) + std::abs(x0.z) + dLen),
        kPush * (std::abs(x1.x) + std::abs(x1.y) + std::abs(x1.z) + dLen)};
    for (int i = 0; i < m; ++i) {
        const dvec3 nt(tx[i] * tInv[i], ty[i] * tInv[i], tz[i] * tInv[i]);
        const bool e = glm::dot(nt, d) > 0.0; // re-anchored: the tilt may change it
        const double w = -glm::dot(nt, e ? x1 : x0) - push[e];
        wedge.planes[i] = glm::vec4(glm::vec3(nt), static_cast<float>(w));
    }
    wedge.planeCount = static_cast<std::uint32_t>(m);
    if (rays) {
        // The planes are m distinct facets in cyclic order (the hull's), so the neighbouring
        // pairs almost always give every ray; the tilt can in principle make a plane redundant,
        // and then the general derivation decides. Either way: the rays of the stored planes.
        std::array<dvec3, 8> stored;
        for (int i = 0; i < m; ++i) stored[i] = dvec3(glm::vec3(wedge.planes[i]));
        if (!cyclicRays(stored.data(), m, *rays)) wedgeRecessionRays(wedge, *rays);
    }

    // Boundary mesh, the exact path's structure written straight into the output: the cap at
    // infinity, per facet the triangle (anchor, r_i+1, r_i), and per bridge from end a to end b
    // the second triangle (e_b, r_i+1, e_a) of its quadrilateral (e_a, e_b, r_i+1, r_i).
    std::array<glm::vec4, 6> dirs;
    for (int i = 0; i < m; ++i) {
        const int k = ray[i];
        dirs[i] = glm::vec4(static_cast<float>(ux[k]), static_cast<float>(uy[k]),
                            static_cast<float>(uz[k]), 0.0f);
    }
    const std::array<glm::vec4, 2> endVerts = {wedge.e0, wedge.e1};
    const std::size_t first = out.vertices.size();
    out.vertices.resize(first + 3 * static_cast<std::size_t>(2 * m - 2 + bridges));
    glm::vec4* v = out.vertices.data() + first;
    auto emit = [&](const glm::vec4& a, const glm::vec4& b, const glm::vec4& c) {
        v[0] = a;
        v[1] = b;
        v[2] = c;
        v += 3;
    };
    for (int i = 1; i + 1 < m; ++i) emit(dirs[0], dirs[i], dirs[i + 1]); // cap
    for (int i = 0; i < m; ++i) {
        const int next = i + 1 < m ? i + 1 : 0;
        const int a = ray[i] >> 2, b = ray[next] >> 2;
        emit(endVerts[a], dirs[next], dirs[i]);
        if (a != b) emit(endVerts[b], dirs[next], endVerts[a]);
    }
    wedge.firstVertex = static_cast<std::uint32_t>(first);
    wedge.vertexCount = static_cast<std::uint32_t>(out.vertices.size() - first);
    wedge.flags = 0u;
    return true;
}

bool finiteAndDistinct(const glm::vec3& e0, const glm::vec3& e1) {
    return std::isfinite(e0.x) && std::isfinite(e0.y) && std::isfinite(e0.z) &&
           std::isfinite(e1.x) && std::isfinite(e1.y) && std::isfinite(e1.z) && e0 != e1;
}

} // namespace

int wedgeRecessionRays(const Wedge& wedge, WedgeRays& rays) {
    rays.count = 0;
    if (wedge.flags & kWedgeDegenerate) return 0;
    if (wedge.flags & kWedgeUnbounded) return rays.count = -1;
    std::array<dvec3, kMaxWedgePlanes> n;
    int count = 0;
    for (std::uint32_t i = 0; i < wedge.planeCount; ++i) {
        const dvec3 c(glm::vec3(wedge.planes[i]));
        bool duplicate = false;
        for (int j = 0; j < count && !duplicate; ++j) {
            const dvec3 diff = glm::abs(n[j] - c);
            duplicate = std::max({diff.x, diff.y, diff.z}) < kSamePlaneNormal;
        }
        if (!duplicate) n[count++] = c;
    }
    bool line;
    if (neighbourRays(n.data(), count, rays, line)) return rays.count;
    if (line) return rays.count = -1;
    rays.count = 0;
    for (int i = 0; i < count && !line; ++i) {
        for (int j = i + 1; j < count && !line; ++j) tryRayPair(n.data(), count, i, j, rays, line);
    }
    if (line || rays.count == 0) rays.count = -1;
    return rays.count;
}

WedgeBuilder::WedgeBuilder(const RectLight& light, Path path)
    : frame_(makeFrame(light)), path_(path) {}

std::uint32_t WedgeBuilder::append(const glm::vec3& e0, const glm::vec3& e1,
                                   WedgeArrays& out) const {
    if (path_ == Path::Auto && finiteAndDistinct(e0, e1) &&
        appendFast(e0, e1, frame_, out, nullptr))
        return static_cast<std::uint32_t>(out.wedges.size() - 1);
    return appendExact(e0, e1, frame_, out);
}

std::uint32_t WedgeBuilder::append(const glm::vec3& e0, const glm::vec3& e1, WedgeArrays& out,
                                   WedgeRays& rays) const {
    if (path_ == Path::Auto && finiteAndDistinct(e0, e1) && appendFast(e0, e1, frame_, out, &rays))
        return static_cast<std::uint32_t>(out.wedges.size() - 1);
    const std::uint32_t index = appendExact(e0, e1, frame_, out);
    wedgeRecessionRays(out.wedges[index], rays);
    return index;
}

bool WedgeBuilder::takesFastPath(const glm::vec3& e0, const glm::vec3& e1) const {
    if (path_ != Path::Auto || !finiteAndDistinct(e0, e1)) return false;
    WedgeArrays scratch;
    return appendFast(e0, e1, frame_, scratch, nullptr);
}

std::uint32_t appendWedge(const glm::vec3& e0, const glm::vec3& e1, const RectLight& light,
                          WedgeArrays& out) {
    return WedgeBuilder(light).append(e0, e1, out);
}

bool wedgeContains(const Wedge& wedge, const glm::vec3& p, float eps) {
    if (wedge.flags & kWedgeDegenerate) return false;
    if (wedge.flags & kWedgeUnbounded) return true;
    for (std::uint32_t i = 0; i < wedge.planeCount; ++i) {
        const glm::vec4& pl = wedge.planes[i];
        if (glm::dot(glm::vec3(pl), p) + pl.w > eps) return false;
    }
    return true;
}

// Coverage of one directed edge (DESIGN.md §4; Assarsson & Akenine-Möller 2003, §3-4).
//
// Clipping rule: only the part of E strictly between P's level and the light's plane can block a
// segment P -> y (y on the light); with ζ(x) = height(x) / height(P) (heights along the light
// normal) that is 0 < ζ < 1. The edge is clipped to 0 <= ζ <= 1 and projected from P
// homogeneously: x maps to (s, t, w) = (dot(u*, Y), dot(v*, Y), 1 - ζ) with
// Y = x - ζ P - (1 - ζ) c, which is affine in x (so the clipped segment maps to a segment or,
// where it reaches P's level (w = 0), to a ray). R = { μ q : q on the projected segment, μ >= 1 }
// in light coordinates (centre at the origin) is the intersection of three half-planes: between
// the rays to q0 and q1, and beyond the line q0 q1. R ∩ [-1, 1]^2 is clipped exactly.
//
// Sign: with the loop orientation of Silhouette.h (occluder to the left of v0 -> v1 seen from
// the light centre) the occluder lies to the right of the projected edge seen from P, so moving
// from the centre to y across the projected edge from its left to its right enters the occluder
// (+1). Seen from P the (s, t) frame is counter-clockwise when P lies on the side cross(u, v)
// points to, and mirrored otherwise; the centre is left of q0 -> q1 iff cross(q0, q1) > 0. So
//     coverage = sign(height(P)) sign(cross(q0, q1)) |R ∩ L| / |L|
// and summing over a loop, Σ = (1/|L|) ∫_L (occ(y) - occ(centre)) dy, i.e. V = V_hard - Σ.
float edgeCoverage(const glm::vec3& pf, const glm::vec3& e0f, const glm::vec3& e1f,
                   const RectLight& light) {
    const Frame f = makeFrame(light);
    const dvec3 p(pf), e0(e0f), e1(e1f);
    const double hp = glm::dot(f.n, p - f.c);
    if (!(std::abs(hp) > 0.0)) return 0.0f; // on the light's plane (or NaN): nothing between
    const double z0 = glm::dot(f.n, e0 - f.c) / hp, z1 = glm::dot(f.n, e1 - f.c) / hp;
    double lo = 0.0, hi = 1.0;
    if (!clipLe0(-z0, -z1, lo, hi) || !clipLe0(z0 - 1.0, z1 - 1.0, lo, hi)) return 0.0f;
    auto project = [&](double l) {
        const dvec3 x = e0 + l * (e1 - e0);
        const double z = z0 + l * (z1 - z0);
        const double w = std::max(0.0, 1.0 - z); // rounding must not flip a point at infinity
        const dvec3 y = x - z * p - (1.0 - z) * f.c;
        return dvec3(glm::dot(f.uStar, y), glm::dot(f.vStar, y), w);
    };
    const dvec3 q0 = project(lo), q1 = project(hi);
    const double cr = q0.x * q1.y - q0.y * q1.x;
    if (cr == 0.0) return 0.0f; // projected edge through the centre (or empty): measure zero
    const double sg = cr > 0.0 ? 1.0 : -1.0;
    const dvec3 line = glm::cross(q0, q1); // homogeneous line through q0, q1; line.z == cr
    // Half-planes a x + b y + c >= 0 bounding R.
    const std::array<dvec3, 3> halves = {
        dvec3(-sg * q0.y, sg * q0.x, 0.0),                   // left of the ray to q0
        dvec3(sg * q1.y, -sg * q1.x, 0.0),                   // right of the ray to q1
        dvec3(-sg * line.x, -sg * line.y, -sg * line.z)};    // beyond q0 q1 from the centre
    std::array<dvec2, 8> poly = {dvec2(-1, -1), dvec2(1, -1), dvec2(1, 1), dvec2(-1, 1)};
    int count = 4;
    for (const dvec3& h : halves) {
        std::array<dvec2, 8> next;
        int nextCount = 0;
        for (int i = 0; i < count; ++i) {
            const dvec2& a = poly[i];
            const dvec2& b = poly[(i + 1) % count];
            const double fa = h.x * a.x + h.y * a.y + h.z;
            const double fb = h.x * b.x + h.y * b.y + h.z;
            if (fa >= 0.0) next[nextCount++] = a;
            if ((fa >= 0.0) != (fb >= 0.0)) next[nextCount++] = a + (fa / (fa - fb)) * (b - a);
        }
        poly = next;
        count = nextCount;
        if (count < 3) return 0.0f;
    }
    double area2 = 0.0;
    for (int i = 0; i < count; ++i) area2 += cross2(poly[i], poly[(i + 1) % count]);
    const double fraction = 0.5 * std::abs(area2) / 4.0; // the light is [-1, 1]^2 in (s, t)
    return static_cast<float>((hp > 0.0 ? sg : -sg) * fraction);
}

} // namespace geometry
