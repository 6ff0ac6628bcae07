// CPU model of per-silhouette blending (geometry/models/BlendModel.h; Forest, Barthe & Paulin 2006).
#include <geometry/models/BlendModel.h>

#include <geometry/shadow/Silhouette.h>
#include <geometry/shadow/Topology.h>

#include <algorithm>
#include <cassert>
#include <cmath>
#include <utility>

namespace geometry::blend {
namespace {

// --- Small convex polygons, clipped by half-planes -----------------------------------------------

// Vertices of a convex polygon; each clip by a half-plane adds at most one vertex. The largest
// ones here: a triangle clipped twice by height (5) then by a part's four sides (9).
constexpr int kMaxVertices = 16;

template <class V> struct Poly {
    std::array<V, kMaxVertices> v{};
    int n = 0;
    void push(const V& x) {
        if (n < kMaxVertices) v[n++] = x;
    }
};

// Keeps the vertices where f(x) >= 0 (Sutherland-Hodgman; f affine in x). Homogeneous vertices
// with w >= 0 may be clipped this way by linear f: interpolating them stays on the segment.
template <class V, class F> Poly<V> clipPoly(const Poly<V>& in, F f) {
    Poly<V> out;
    for (int i = 0; i < in.n; ++i) {
        const V& a = in.v[i];
        const V& b = in.v[(i + 1) % in.n];
        const double fa = f(a), fb = f(b);
        if (fa >= 0.0) out.push(a);
        if ((fa >= 0.0) != (fb >= 0.0)) out.push(a + (fa / (fa - fb)) * (b - a));
    }
    return out;
}

Poly<dvec3> clipHalf(const Poly<dvec3>& in, const dvec3& h) {
    return clipPoly(in, [&](const dvec3& x) { return glm::dot(h, x); });
}

double cross2(const dvec2& a, const dvec2& b) {
    return a.x * b.y - a.y * b.x;
}

struct AreaMoments {
    double area = 0.0;
    dvec2 moment{0.0}; // ∫ (x, y) dA
};

// Green's theorem as a fan from the origin: segment a -> b of a closed boundary adds the triangle
// (0, a, b): area cross / 2, first moments (a + b) cross / 6.
void addSegment(AreaMoments& m, const dvec2& a, const dvec2& b) {
    const double c = cross2(a, b);
    m.area += 0.5 * c;
    m.moment += (c / 6.0) * (a + b);
}

AreaMoments polygonAreaMoments(const Poly<dvec2>& poly) {
    AreaMoments m;
    for (int i = 0; i < poly.n; ++i)
        addSegment(m, poly.v[i], poly.v[(i + 1) % poly.n]);
    return m;
}

// Homogeneous (w = 1) or affine 2D vertices of a polygon whose vertices all have w > 0, with
// near-duplicate neighbours merged (clipping leaves them; they would make zero-length edges).
Poly<dvec2> dehomogenise(const Poly<dvec3>& in) {
    Poly<dvec2> out;
    for (int i = 0; i < in.n; ++i) {
        if (!(in.v[i].z > 0.0)) continue; // only the degenerate direction (0, 0, 0) gets here
        const dvec2 p = dvec2(in.v[i]) / in.v[i].z;
        if (out.n > 0 && glm::length(p - out.v[out.n - 1]) < 1e-12) continue;
        out.push(p);
    }
    while (out.n > 1 && glm::length(out.v[0] - out.v[out.n - 1]) < 1e-12)
        --out.n;
    return out;
}

// --- Parts
// ----------------------------------------------------------------------------------------

// The part's sides as half-planes dot(h, (x, y, w)) >= 0 in part homogeneous coordinates.
int partHalves(const Part& part, std::array<dvec3, 4>& h) {
    if (part.shape == PartShape::Square) {
        h = {dvec3(1, 0, 0), dvec3(0, 1, 0), dvec3(-1, 0, 1), dvec3(0, -1, 1)};
        return 4;
    }
    h = {dvec3(0, 1, 0), dvec3(1, -1, 0), dvec3(-1, 0, 1), dvec3(0)};
    return 3;
}

Poly<dvec3> partPolygon(const Part& part) {
    Poly<dvec3> poly;
    for (int k = 0; k < part.cornerCount; ++k)
        poly.push(dvec3(part.corners[k], 1.0));
    return poly;
}

// A light-coordinate half-plane in the part's coordinates: dot(h', X') = dot(h, fromPart X').
dvec3 toPartHalf(const Part& part, const dvec3& h) {
    return glm::transpose(part.fromPart) * h;
}

// The ε-perturbed inside test of cornerWinding: the corner moved by ε d1 + ε² d2 into the part.
bool insidePerturbed(const dvec3& h, const dvec3& x, const dvec2& d1, const dvec2& d2) {
    const double f = glm::dot(h, x);
    if (f != 0.0) return f > 0.0;
    const double g1 = glm::dot(dvec2(h), d1);
    if (g1 != 0.0) return g1 > 0.0;
    return glm::dot(dvec2(h), d2) > 0.0;
}

// --- Projection from P onto the light's plane ---------------------------------------------------

// ζ(x) = height(x) / height(P) (heights along the light's normal): 0 on the light's plane, 1 at
// P's level; only 0 <= ζ <= 1 can block a segment P -> y. A point maps to homogeneous light
// coordinates (s, t, w) = (dot(u*, Y), dot(v*, Y), 1 - ζ), Y = (x - c) - ζ (P - c), affine in x.
dvec3 projectPoint(const LightFrame& f, const dvec3& pc, const dvec3& x, double z) {
    const double w = std::max(0.0, 1.0 - z); // rounding must not flip a point at infinity
    const dvec3 y = (x - f.c) - z * pc;
    return dvec3(glm::dot(f.uStar, y), glm::dot(f.vStar, y), w);
}

// Triangle -> its projection (homogeneous light coordinates), clipped to 0 <= ζ <= 1.
Poly<dvec3> projectTriangle(const LightFrame& f, const dvec3& p, const Triangle& tri) {
    const dvec3 pc = p - f.c;
    const double hp = glm::dot(f.n, pc);
    if (!(std::abs(hp) > 0.0)) return {};
    Poly<glm::dvec4> poly; // (x, ζ)
    for (const dvec3& x : tri)
        poly.push(glm::dvec4(x, glm::dot(f.n, x - f.c) / hp));
    poly = clipPoly(poly, [](const glm::dvec4& x) { return x.w; });
    poly = clipPoly(poly, [](const glm::dvec4& x) { return 1.0 - x.w; });
    Poly<dvec3> out;
    for (int i = 0; i < poly.n; ++i)
        out.push(projectPoint(f, pc, dvec3(poly.v[i]), poly.v[i].w));
    return out;
}

// A projected polygon (light homogeneous) ∩ part, in part coordinates.
Poly<dvec2> polygonInPart(const Poly<dvec3>& light, const Part& part) {
    Poly<dvec3> poly;
    for (int i = 0; i < light.n; ++i)
        poly.push(part.toPart * light.v[i]);
    std::array<dvec3, 4> halves;
    const int count = partHalves(part, halves);
    for (int i = 0; i < count && poly.n > 0; ++i)
        poly = clipHalf(poly, halves[i]);
    return dehomogenise(poly);
}

// Segment-triangle test, closed triangle, open segment p -> q.
bool segmentHitsTriangle(const dvec3& p, const dvec3& q, const Triangle& tri) {
    const dvec3 dir = q - p;
    const dvec3 ab = tri[1] - tri[0], ac = tri[2] - tri[0];
    const dvec3 pv = glm::cross(dir, ac);
    const double det = glm::dot(ab, pv);
    if (!(std::abs(det) > 0.0)) return false; // segment in the triangle's plane
    const dvec3 tv = p - tri[0];
    const double u = glm::dot(tv, pv) / det;
    if (u < 0.0 || u > 1.0) return false;
    const dvec3 qv = glm::cross(tv, ab);
    const double v = glm::dot(dir, qv) / det;
    if (v < 0.0 || u + v > 1.0) return false;
    const double t = glm::dot(ac, qv) / det;
    return t > 0.0 && t < 1.0;
}

// --- Exact union of convex polygons -------------------------------------------------------------

// Area and first moments of the union of convex, counter-clockwise polygons, integrated along the
// union's boundary: the parts of every polygon edge not covered by another polygon. Collinear
// overlapping edges are the one tie that matters (adjacent mesh triangles share edges): two
// edges with opposite directions separate two polygons (interior of the union: both dropped);
// with the same direction they are one boundary, kept once (by the polygon of lower index).
AreaMoments unionAreaMoments(const std::vector<Poly<dvec2>>& polys) {
    struct Box {
        dvec2 lo, hi;
    };
    std::vector<Box> boxes(polys.size());
    for (std::size_t i = 0; i < polys.size(); ++i) {
        Box b{dvec2(1e300), dvec2(-1e300)};
        for (int k = 0; k < polys[i].n; ++k) {
            b.lo = glm::min(b.lo, polys[i].v[k]);
            b.hi = glm::max(b.hi, polys[i].v[k]);
        }
        boxes[i] = b;
    }
    constexpr double kCollinear = 1e-10; // distance to a line, part coordinates (size 1)
    constexpr double kTouch = 1e-9;      // bounding-box slack
    AreaMoments total;
    std::vector<std::pair<double, double>> covered;
    for (std::size_t i = 0; i < polys.size(); ++i) {
        const Poly<dvec2>& pi = polys[i];
        for (int e = 0; e < pi.n; ++e) {
            const dvec2 a = pi.v[e], b = pi.v[(e + 1) % pi.n];
            const dvec2 lo = glm::min(a, b) - kTouch, hi = glm::max(a, b) + kTouch;
            covered.clear();
            for (std::size_t j = 0; j < polys.size(); ++j) {
                if (j == i || boxes[j].lo.x > hi.x || boxes[j].hi.x < lo.x ||
                    boxes[j].lo.y > hi.y || boxes[j].hi.y < lo.y)
                    continue;
                const Poly<dvec2>& pj = polys[j];
                double t0 = 0.0, t1 = 1.0;
                bool skip = false;
                for (int k = 0; k < pj.n && !skip && t0 < t1; ++k) {
                    const dvec2 c = pj.v[k], d = pj.v[(k + 1) % pj.n];
                    const double len = glm::length(d - c);
                    if (!(len > 0.0)) continue;
                    const double fa = cross2(d - c, a - c) / len; // >= 0: inside (left)
                    const double fb = cross2(d - c, b - c) / len;
                    if (std::abs(fa) <= kCollinear && std::abs(fb) <= kCollinear) {
                        if (glm::dot(d - c, b - a) > 0.0 && j > i) skip = true;
                        continue; // opposite, or same and j < i: this side covers it
                    }
                    if (fa < 0.0 && fb < 0.0) {
                        skip = true;
                    } else if (fa < 0.0) {
                        t0 = std::max(t0, fa / (fa - fb));
                    } else if (fb < 0.0) {
                        t1 = std::min(t1, fa / (fa - fb));
                    }
                }
                if (!skip && t0 < t1) covered.emplace_back(t0, t1);
            }
            std::sort(covered.begin(), covered.end());
            double t = 0.0;
            auto emit = [&](double from, double to) {
                if (to > from) addSegment(total, a + from * (b - a), a + to * (b - a));
            };
            for (const auto& [c0, c1] : covered) {
                emit(t, c0);
                t = std::max(t, c1);
            }
            emit(t, 1.0);
        }
    }
    return total;
}

// Projected triangles ∩ part: convex polygons with area, part coordinates, counter-clockwise.
std::vector<Poly<dvec2>> polygonsInPart(const std::vector<Poly<dvec3>>& projected, const Part& part,
                                        Rect& bounds) {
    std::vector<Poly<dvec2>> out;
    bounds = Rect{};
    for (const Poly<dvec3>& light : projected) {
        Poly<dvec2> poly = polygonInPart(light, part);
        if (poly.n < 3) continue;
        const double area = polygonAreaMoments(poly).area;
        if (std::abs(area) < 1e-14) continue; // seen edge-on from P: blocks a null set
        if (area < 0.0) std::reverse(poly.v.begin(), poly.v.begin() + poly.n);
        for (int k = 0; k < poly.n; ++k)
            bounds = extend(bounds, poly.v[k]);
        out.push_back(poly);
    }
    return out;
}

// --- Blending
// --------------------------------------------------------------------------------------

using Poly1 = std::array<double, 4>; // c0 + c1 x + c2 x² + c3 x³

Poly1 mul(const Poly1& a, const Poly1& b) { // the degree must stay <= 3 (it does here)
    Poly1 r{};
    for (int i = 0; i < 4; ++i)
        for (int j = 0; i + j < 4; ++j)
            r[i + j] += a[i] * b[j];
    return r;
}
Poly1 timesX(const Poly1& a) {
    return {0.0, a[0], a[1], a[2]};
}

// A state's occlusion as a density over its rectangle: lambda wx(x) wy(y).
struct Density {
    double lambda = 0.0;
    Poly1 wx{1, 0, 0, 0}, wy{1, 0, 0, 0};
};

// Coefficients of 1 + k (x - m) with k = 12 (g - m) / W², clamped to keep it >= 0 on [lo, hi].
Poly1 linearWeight(double g, double m, double lo, double hi) {
    const double w = hi - lo;
    if (!(w > 0.0)) return {1, 0, 0, 0};
    double k = 12.0 * (g - m) / (w * w);
    if (m - lo > 0.0) k = std::min(k, 1.0 / (m - lo));
    if (hi - m > 0.0) k = std::max(k, -1.0 / (hi - m));
    return {1.0 - k * m, k, 0.0, 0.0};
}

Density densityOf(const PartState& s, const Part& part, Overlap overlap) {
    Density d;
    const double b = rectArea(s.rect, part);
    if (!(b > 0.0) || !(s.vCoef > 0.0)) return d;
    const double a = s.vCoef * part.area; // occluded area, part coordinates
    if (overlap == Overlap::Paper) {
        d.lambda = std::min(1.0, a / b);
        return d;
    }
    const dvec2 m(integrateRect(s.rect, part, {0, 1, 0, 0}, {1, 0, 0, 0}) / b,
                  integrateRect(s.rect, part, {1, 0, 0, 0}, {0, 1, 0, 0}) / b);
    d.wx = linearWeight(s.centroid.x, m.x, s.rect.minX, s.rect.maxX);
    d.wy = linearWeight(s.centroid.y, m.y, s.rect.minY, s.rect.maxY);
    const double mass = integrateRect(s.rect, part, d.wx, d.wy);
    d.lambda = mass > 0.0 ? a / mass : 0.0;
    return d;
}

struct OverlapResult {
    double e = 0.0;      // fraction of the part
    dvec2 centroid{0.5}; // of the overlap density
};

OverlapResult overlapOf(const PartState& f, const PartState& s, const Part& part, Overlap overlap) {
    OverlapResult r;
    const Rect both = intersect(f.rect, s.rect);
    if (both.empty()) return r;
    const Density df = densityOf(f, part, overlap), ds = densityOf(s, part, overlap);
    const Poly1 px = mul(df.wx, ds.wx), py = mul(df.wy, ds.wy);
    const double mass = integrateRect(both, part, px, py);
    if (!(mass > 0.0)) return r;
    r.centroid = dvec2(integrateRect(both, part, timesX(px), py),
                       integrateRect(both, part, px, timesX(py))) /
                 mass;
    r.e = std::clamp(df.lambda * ds.lambda * mass / part.area, 0.0, std::min(f.vCoef, s.vCoef));
    return r;
}

dvec2 clampInto(const dvec2& p, const Rect& r) {
    if (r.empty()) return p;
    return glm::clamp(p, dvec2(r.minX, r.minY), dvec2(r.maxX, r.maxY));
}

} // namespace

// --- Frames and parts ---------------------------------------------------------------------------

bool validPartCount(int parts) {
    return parts == 1 || parts == 4 || parts == 8;
}

Part radialPart(int parts, int index) {
    assert(validPartCount(parts) && index >= 0 && index < parts);
    Part part;
    if (parts == 1) {
        // x = (s + 1) / 2, y = (t + 1) / 2, columns of (s, t, w) -> (x, y, w).
        part.toPart = glm::dmat3(dvec3(0.5, 0, 0), dvec3(0, 0.5, 0), dvec3(0.5, 0.5, 1));
    } else {
        static constexpr int kSigns[4][2] = {{1, 1}, {-1, 1}, {-1, -1}, {1, -1}};
        const int quadrant = parts == 4 ? index : index / 2;
        const double sx = kSigns[quadrant][0], sy = kSigns[quadrant][1];
        const bool swapped = parts == 8 && index % 2 == 1; // the half where |t| >= |s|
        part.toPart = swapped ? glm::dmat3(dvec3(0, sx, 0), dvec3(sy, 0, 0), dvec3(0, 0, 1))
                              : glm::dmat3(dvec3(sx, 0, 0), dvec3(0, sy, 0), dvec3(0, 0, 1));
    }
    part.fromPart = glm::inverse(part.toPart);
    if (parts == 8) {
        part.shape = PartShape::Triangle;
        part.cornerCount = 3;
        part.corners = {dvec2(0, 0), dvec2(1, 0), dvec2(1, 1), dvec2(0)};
        part.area = 0.5;
        part.centroid = dvec2(2.0 / 3.0, 1.0 / 3.0);
    } else {
        part.corners = {dvec2(0, 0), dvec2(1, 0), dvec2(1, 1), dvec2(0, 1)};
    }
    const dvec3 c = part.toPart * dvec3(0, 0, 1);
    part.centre = dvec2(c) / c.z;
    return part;
}

// --- Rectangles ---------------------------------------------------------------------------------

Rect unite(const Rect& a, const Rect& b) {
    if (a.empty()) return b;
    if (b.empty()) return a;
    return {std::min(a.minX, b.minX), std::min(a.minY, b.minY), std::max(a.maxX, b.maxX),
            std::max(a.maxY, b.maxY)};
}

Rect intersect(const Rect& a, const Rect& b) {
    if (a.empty() || b.empty()) return {};
    const Rect r{std::max(a.minX, b.minX), std::max(a.minY, b.minY), std::min(a.maxX, b.maxX),
                 std::min(a.maxY, b.maxY)};
    return r.empty() ? Rect{} : r;
}

Rect extend(const Rect& r, const dvec2& p) {
    return unite(r, Rect{p.x, p.y, p.x, p.y});
}

double integrateRect(const Rect& r0, const Part& part, const std::array<double, 4>& fx,
                     const std::array<double, 4>& fy) {
    const Rect r = intersect(r0, Rect{0, 0, 1, 1});
    if (r.empty()) return 0.0;
    // ∫_a^b of a cubic, exactly.
    auto integral = [](const std::array<double, 4>& c, double a, double b) {
        auto prim = [&](double x) {
            return x * (c[0] + x * (c[1] / 2.0 + x * (c[2] / 3.0 + x * c[3] / 4.0)));
        };
        return prim(b) - prim(a);
    };
    auto eval = [](const std::array<double, 4>& c, double x) {
        return c[0] + x * (c[1] + x * (c[2] + x * c[3]));
    };
    const double iy = integral(fy, r.minY, r.maxY);
    if (part.shape == PartShape::Square) return integral(fx, r.minX, r.maxX) * iy;
    // Triangle 0 <= y <= x: for x in [minY, maxY] the inner integral runs from minY to x (a
    // quartic in x, times the cubic fx: degree 7, exact with 4-point Gauss-Legendre); beyond
    // maxY it is the full iy.
    double total = 0.0;
    const double a = std::max(r.minX, r.minY), b = std::min(r.maxX, r.maxY);
    if (b > a) {
        static constexpr double kNodes[4] = {-0.8611363115940526, -0.3399810435848563,
                                             0.3399810435848563, 0.8611363115940526};
        static constexpr double kWeights[4] = {0.3478548451374538, 0.6521451548625461,
                                               0.6521451548625461, 0.3478548451374538};
        const double half = 0.5 * (b - a), mid = 0.5 * (a + b);
        for (int i = 0; i < 4; ++i) {
            const double x = mid + half * kNodes[i];
            total += half * kWeights[i] * eval(fx, x) * integral(fy, r.minY, x);
        }
    }
    const double from = std::max(r.minX, r.maxY);
    if (r.maxX > from) total += integral(fx, from, r.maxX) * iy;
    return total;
}

// --- Per fragment and edge -----------------------------------------------------------------------

ProjectedEdge projectEdge(const LightFrame& f, const dvec3& p, const dvec3& e0, const dvec3& e1) {
    ProjectedEdge out;
    const dvec3 pc = p - f.c;
    const double hp = glm::dot(f.n, pc);
    if (!(std::abs(hp) > 0.0)) return out; // on the light's plane (or NaN): nothing between
    const double z0 = glm::dot(f.n, e0 - f.c) / hp, z1 = glm::dot(f.n, e1 - f.c) / hp;
    // The part of the edge with 0 <= ζ <= 1, as parameters [lo, hi] along e0 -> e1.
    double lo = 0.0, hi = 1.0;
    for (const auto& [f0, f1] : {std::pair{z0, z1}, std::pair{1.0 - z0, 1.0 - z1}}) {
        if (f0 < 0.0 && f1 < 0.0) return out;
        if (f0 < 0.0)
            lo = std::max(lo, f0 / (f0 - f1));
        else if (f1 < 0.0)
            hi = std::min(hi, f0 / (f0 - f1));
    }
    if (lo > hi) return out;
    // End points exactly as given when unclipped, so that two edges sharing a vertex project it
    // to the same bits (cornerWinding's tie rule relies on it).
    auto project = [&](double l) {
        const dvec3 x = l == 0.0 ? e0 : l == 1.0 ? e1 : e0 + l * (e1 - e0);
        const double z = l == 0.0 ? z0 : l == 1.0 ? z1 : z0 + l * (z1 - z0);
        return projectPoint(f, pc, x, z);
    };
    out.segment = true;
    out.q0 = project(lo);
    out.q1 = project(hi);
    const double cr = out.q0.x * out.q1.y - out.q0.y * out.q1.x;
    if (cr == 0.0) return out; // through the centre: R_e has no area
    const double sg = cr > 0.0 ? 1.0 : -1.0;
    const dvec3 line = glm::cross(out.q0, out.q1); // homogeneous line through q0, q1
    out.region = true;
    out.sign = hp > 0.0 ? sg : -sg; // see edgeCoverage (Wedge.cpp) for the orientation argument
    out.halves = {dvec3(-sg * out.q0.y, sg * out.q0.x, 0.0), // left of the ray to q0
                  dvec3(sg * out.q1.y, -sg * out.q1.x, 0.0), // right of the ray to q1
                  -sg * line};                               // beyond q0 q1, away from the centre
    return out;
}

namespace {
// R_e ∩ part, part coordinates.
Poly<dvec2> regionInPart(const ProjectedEdge& edge, const Part& part) {
    Poly<dvec3> poly = partPolygon(part);
    for (const dvec3& h : edge.halves) {
        poly = clipHalf(poly, toPartHalf(part, h));
        if (poly.n < 3) return {};
    }
    return dehomogenise(poly);
}
} // namespace

double partCoverage(const ProjectedEdge& edge, const Part& part) {
    if (!edge.region) return 0.0;
    const Poly<dvec2> poly = regionInPart(edge, part);
    if (poly.n < 3) return 0.0;
    return edge.sign * std::abs(polygonAreaMoments(poly).area) / part.area;
}

dvec2 partMoment(const ProjectedEdge& edge, const Part& part) {
    if (!edge.region) return dvec2(0.0);
    const Poly<dvec2> poly = regionInPart(edge, part);
    if (poly.n < 3) return dvec2(0.0);
    const AreaMoments m = polygonAreaMoments(poly); // counter-clockwise: area >= 0
    return (edge.sign / part.area) * m.moment;
}

Rect partEdgeBounds(const ProjectedEdge& edge, const Part& part) {
    if (!edge.segment) return {};
    const dvec3 a = part.toPart * edge.q0, b = part.toPart * edge.q1;
    std::array<dvec3, 4> halves;
    const int count = partHalves(part, halves);
    double lo = 0.0, hi = 1.0;
    for (int i = 0; i < count; ++i) {
        const double fa = glm::dot(halves[i], a), fb = glm::dot(halves[i], b);
        if (fa < 0.0 && fb < 0.0) return {};
        if (fa < 0.0)
            lo = std::max(lo, fa / (fa - fb));
        else if (fb < 0.0)
            hi = std::min(hi, fa / (fa - fb));
    }
    if (lo > hi) return {};
    Rect r;
    for (const double l : {lo, hi}) {
        const dvec3 x = a + l * (b - a);
        if (x.z > 0.0) r = extend(r, dvec2(x) / x.z);
    }
    return r;
}

int cornerWinding(const ProjectedEdge& edge, const Part& part, int corner) {
    if (!edge.region) return 0;
    const dvec2 c = part.corners[corner];
    // Into the part: towards its centroid, as cornerCount (Σ corners / cornerCount - c), which is
    // exact (the triangle's centroid (2/3, 1/3) is not: its rounding would tilt the direction
    // and decide ties on R_e's lines by it; the float twin uses the same exact directions).
    dvec2 sum(0.0);
    for (int k = 0; k < part.cornerCount; ++k)
        sum += part.corners[k];
    const dvec2 d1 = sum - double(part.cornerCount) * c;
    const dvec2 d2 = part.corners[(corner + 1) % part.cornerCount] - c; // along its side
    for (const dvec3& h : edge.halves) {
        if (!insidePerturbed(toPartHalf(part, h), dvec3(c, 1.0), d1, d2)) return 0;
    }
    return edge.sign > 0.0 ? 1 : -1;
}

void addEdge(PartAccum& acc, const ProjectedEdge& edge, const Part& part) {
    acc.coverage += partCoverage(edge, part);
    acc.moment += partMoment(edge, part);
    acc.edges = unite(acc.edges, partEdgeBounds(edge, part));
    for (int k = 0; k < part.cornerCount; ++k)
        acc.cornerWinding[k] += cornerWinding(edge, part, k);
}

std::uint32_t cornerBits(const PartAccum& acc, const Part& part) {
    std::uint32_t bits = 0u;
    for (int k = 0; k < part.cornerCount; ++k)
        bits |= static_cast<std::uint32_t>(acc.cornerWinding[k] & 1) << k;
    return bits;
}

Rect partRectangle(const Rect& edgeBounds, const std::array<bool, 4>& cornerOccluded,
                   const Part& part) {
    Rect r = edgeBounds;
    for (int k = 0; k < part.cornerCount; ++k)
        if (cornerOccluded[k]) r = extend(r, part.corners[k]);
    return r;
}

PartState resolvePart(const PartAccum& acc, bool centreOccluded, const Part& part) {
    const double c = centreOccluded ? 1.0 : 0.0;
    PartState s;
    // Terms of Σ coverage that cancel exactly in exact arithmetic leave ~1e-17 here (a region of
    // zero area, e.g. an edge projected along a part's side); that is no occlusion, and gets no
    // rectangle. (The float twin needs ~1e-6.)
    constexpr double kNoOcclusion = 1e-12;
    s.vCoef = std::clamp(c + acc.coverage, 0.0, 1.0);
    s.centroid = part.centroid;
    if (!(s.vCoef > kNoOcclusion)) {
        s.vCoef = 0.0;
        return s; // nothing occluded: empty rectangle
    }
    std::array<bool, 4> occluded{};
    for (int k = 0; k < part.cornerCount; ++k)
        occluded[k] = (centreOccluded ? 1 : 0) + acc.cornerWinding[k] >= 1;
    s.rect = partRectangle(acc.edges, occluded, part);
    const double area = c + acc.coverage;
    const dvec2 centroid = (c * part.centroid + acc.moment) / area;
    s.centroid = clampInto(centroid, s.rect);
    return s;
}

// --- Per group ----------------------------------------------------------------------------------

std::vector<Group> silhouetteGroups(const SilhouetteFrame& frame, const Topology& topology) {
    const auto positions = topology.positions();
    const auto triangles = topology.triangles();
    std::vector<Group> groups;
    groups.reserve(frame.groups.size());
    for (const SilhouetteGroup& g : frame.groups) {
        Group out;
        for (std::uint32_t i = 0; i < g.triangleCount; ++i) {
            const std::uint32_t id = frame.triangles[g.firstTriangle + i];
            const glm::uvec3 t = triangles[id & ~kTriangleFlipped];
            Triangle tri = {dvec3(positions[t.x]), dvec3(positions[t.y]), dvec3(positions[t.z])};
            if (id & kTriangleFlipped) std::swap(tri[1], tri[2]);
            out.triangles.push_back(tri);
        }
        for (std::uint32_t i = 0; i < g.edgeCount; ++i) {
            const SilhouetteEdge& e = frame.edges[g.firstEdge + i];
            out.edges.push_back({dvec3(positions[e.v0]), dvec3(positions[e.v1])});
        }
        groups.push_back(std::move(out));
    }
    return groups;
}

double GroupState::visibility() const {
    double occluded = 0.0;
    for (int k = 0; k < parts; ++k)
        occluded += part[k].vCoef;
    return 1.0 - occluded / parts;
}

int centreCount(const LightFrame& light, const dvec3& p, const Group& group) {
    int count = 0;
    for (const Triangle& t : group.triangles)
        count += segmentHitsTriangle(p, light.c, t) ? 1 : 0;
    return count;
}

GroupState groupState(const RectLight& light, const dvec3& p, const Group& group, int parts) {
    const LightFrame f = lightFrame(light);
    GroupState out;
    out.parts = parts;
    out.centreOccluded = centreCount(f, p, group) != 0;
    std::array<Part, kMaxParts> part;
    std::array<PartAccum, kMaxParts> acc{};
    for (int k = 0; k < parts; ++k)
        part[k] = radialPart(parts, k);
    for (const auto& [e0, e1] : group.edges) {
        const ProjectedEdge edge = projectEdge(f, p, e0, e1);
        if (!edge.segment) continue; // the fragment is outside this edge's wedge
        for (int k = 0; k < parts; ++k)
            addEdge(acc[k], edge, part[k]);
    }
    for (int k = 0; k < parts; ++k)
        out.part[k] = resolvePart(acc[k], out.centreOccluded, part[k]);
    return out;
}

GroupState exactGroupState(const RectLight& light, const dvec3& p,
                           std::span<const Triangle> triangles, int parts) {
    const LightFrame f = lightFrame(light);
    GroupState out;
    out.parts = parts;
    std::vector<Poly<dvec3>> projected;
    for (const Triangle& t : triangles) {
        Poly<dvec3> poly = projectTriangle(f, p, t);
        if (poly.n >= 3) projected.push_back(poly);
        out.centreOccluded = out.centreOccluded || segmentHitsTriangle(p, f.c, t);
    }
    for (int k = 0; k < parts; ++k) {
        const Part part = radialPart(parts, k);
        PartState& s = out.part[k];
        const std::vector<Poly<dvec2>> polys = polygonsInPart(projected, part, s.rect);
        const AreaMoments m = unionAreaMoments(polys);
        s.vCoef = std::clamp(m.area / part.area, 0.0, 1.0);
        s.centroid = part.centroid;
        if (m.area > 0.0)
            s.centroid = clampInto(m.moment / m.area, s.rect);
        else
            s.rect = Rect{};
    }
    return out;
}

double exactVisibility(const RectLight& light, const dvec3& p,
                       std::span<const Triangle> triangles) {
    return exactGroupState(light, p, triangles, 1).visibility();
}

// --- Blending
// --------------------------------------------------------------------------------------

double overlapEstimate(const PartState& f, const PartState& s, const Part& part, Overlap overlap) {
    return overlapOf(f, s, part, overlap).e;
}

PartState blendPart(const PartState& f, const PartState& s, const Part& part, Overlap overlap) {
    const OverlapResult o = overlapOf(f, s, part, overlap);
    // A_f + A_s - E summed as max + (min - E): E <= min(A_f, A_s), so the bracket cannot round
    // below 0 and the result never falls below either input, in any floating-point precision:
    // a full part (A = 1) stays exactly 1.
    const double sum = std::max(f.vCoef, s.vCoef) + (std::min(f.vCoef, s.vCoef) - o.e);
    PartState out;
    out.vCoef = std::clamp(sum, 0.0, 1.0);
    out.rect = unite(f.rect, s.rect);
    if (sum > 1e-12) {
        const dvec2 moment = f.vCoef * f.centroid + s.vCoef * s.centroid - o.e * o.centroid;
        out.centroid = clampInto(moment / sum, out.rect);
    } else {
        out.centroid = part.centroid;
    }
    return out;
}

double blendVisibility(std::span<const GroupState> groups, const BlendSettings& settings) {
    if (groups.empty()) return 1.0;
    const int parts = groups[0].parts;
    double occluded = 0.0;
    for (int k = 0; k < parts; ++k) {
        const Part part = radialPart(parts, k);
        PartState final; // empty: nothing occluded yet
        final.centroid = part.centroid;
        for (const GroupState& g : groups) {
            assert(g.parts == parts);
            const PartState s = quantise(g.part[k], settings.bits);
            final = quantise(blendPart(final, s, part, settings.overlap), settings.bits);
        }
        occluded += final.vCoef;
    }
    return 1.0 - occluded / parts;
}

double multiplyVisibility(std::span<const GroupState> groups) {
    double v = 1.0;
    for (const GroupState& g : groups)
        v *= g.visibility();
    return v;
}

double additiveVisibility(const RectLight& light, const dvec3& p, std::span<const Group> groups) {
    const LightFrame f = lightFrame(light);
    const Part whole = radialPart(1, 0);
    bool centre = false;
    double coverage = 0.0;
    for (const Group& g : groups) {
        centre = centre || centreCount(f, p, g) != 0;
        for (const auto& [e0, e1] : g.edges)
            coverage += partCoverage(projectEdge(f, p, e0, e1), whole);
    }
    return std::clamp((centre ? 0.0 : 1.0) - coverage, 0.0, 1.0);
}

// --- Packing
// ---------------------------------------------------------------------------------------- Written
// as the GLSL will be: float maths in float, bit fields with uint32 shifts and masks. (Bit-exact
// with a GPU except where a compiler fuses v * 255 + 0.5 into one rounding, which can only move a
// value lying exactly on a tie.)

namespace {
float clamp01(float v) {
    return v > 0.0f ? std::min(v, 1.0f) : 0.0f;
} // NaN -> 0
} // namespace

std::uint32_t packUnorm8(float v) {
    return static_cast<std::uint32_t>(std::floor(clamp01(v) * 255.0f + 0.5f));
}
std::uint32_t packUnorm8Down(float v) {
    return static_cast<std::uint32_t>(std::floor(clamp01(v) * 255.0f));
}
std::uint32_t packUnorm8Up(float v) {
    return static_cast<std::uint32_t>(std::ceil(clamp01(v) * 255.0f));
}
float unpackUnorm8(std::uint32_t bits) {
    return static_cast<float>(bits & 255u) / 255.0f;
}

std::uint32_t packUnorm16(float v) {
    return static_cast<std::uint32_t>(std::floor(clamp01(v) * 65535.0f + 0.5f));
}
std::uint32_t packUnorm16Down(float v) {
    return static_cast<std::uint32_t>(std::floor(clamp01(v) * 65535.0f));
}
std::uint32_t packUnorm16Up(float v) {
    return static_cast<std::uint32_t>(std::ceil(clamp01(v) * 65535.0f));
}
float unpackUnorm16(std::uint32_t bits) {
    return static_cast<float>(bits & 65535u) / 65535.0f;
}

std::uint32_t packRect8(const glm::vec4& rect) {
    return packUnorm8Down(rect.x) | (packUnorm8Down(rect.y) << 8u) | (packUnorm8Up(rect.z) << 16u) |
           (packUnorm8Up(rect.w) << 24u);
}
glm::vec4 unpackRect8(std::uint32_t bits) {
    return glm::vec4(unpackUnorm8(bits), unpackUnorm8(bits >> 8u), unpackUnorm8(bits >> 16u),
                     unpackUnorm8(bits >> 24u));
}
std::uint32_t packCoef8(float vCoef, const glm::vec2& centroid, std::uint32_t cornerBits) {
    return packUnorm8(vCoef) | (packUnorm8(centroid.x) << 8u) | (packUnorm8(centroid.y) << 16u) |
           ((cornerBits & 255u) << 24u);
}
float unpackVCoef8(std::uint32_t bits) {
    return unpackUnorm8(bits);
}
glm::vec2 unpackCentroid8(std::uint32_t bits) {
    return glm::vec2(unpackUnorm8(bits >> 8u), unpackUnorm8(bits >> 16u));
}
std::uint32_t unpackCornerBits8(std::uint32_t bits) {
    return bits >> 24u;
}

glm::uvec2 packRect16(const glm::vec4& rect) {
    return glm::uvec2(packUnorm16Down(rect.x) | (packUnorm16Down(rect.y) << 16u),
                      packUnorm16Up(rect.z) | (packUnorm16Up(rect.w) << 16u));
}
glm::vec4 unpackRect16(const glm::uvec2& bits) {
    return glm::vec4(unpackUnorm16(bits.x), unpackUnorm16(bits.x >> 16u), unpackUnorm16(bits.y),
                     unpackUnorm16(bits.y >> 16u));
}
glm::uvec2 packCoef16(float vCoef, const glm::vec2& centroid, std::uint32_t cornerBits) {
    return glm::uvec2(packUnorm16(vCoef) | (packUnorm16(centroid.x) << 16u),
                      packUnorm16(centroid.y) | ((cornerBits & 65535u) << 16u));
}
float unpackVCoef16(const glm::uvec2& bits) {
    return unpackUnorm16(bits.x);
}
glm::vec2 unpackCentroid16(const glm::uvec2& bits) {
    return glm::vec2(unpackUnorm16(bits.x >> 16u), unpackUnorm16(bits.y));
}

glm::vec4 toVec4(const Rect& r) {
    if (r.empty()) return glm::vec4(1.0f, 1.0f, 0.0f, 0.0f); // the one empty rectangle
    return glm::vec4(static_cast<float>(r.minX), static_cast<float>(r.minY),
                     static_cast<float>(r.maxX), static_cast<float>(r.maxY));
}
Rect toRect(const glm::vec4& v) {
    return Rect{v.x, v.y, v.z, v.w};
}

glm::uvec2 packPart8(const PartState& s) {
    return glm::uvec2(packRect8(toVec4(s.rect)),
                      packCoef8(static_cast<float>(s.vCoef), glm::vec2(s.centroid), 0u));
}
PartState unpackPart8(const glm::uvec2& bits) {
    PartState s;
    s.rect = toRect(unpackRect8(bits.x));
    s.vCoef = unpackVCoef8(bits.y);
    s.centroid = dvec2(unpackCentroid8(bits.y));
    return s;
}
glm::uvec4 packPart16(const PartState& s) {
    const glm::uvec2 rect = packRect16(toVec4(s.rect));
    const glm::uvec2 coef = packCoef16(static_cast<float>(s.vCoef), glm::vec2(s.centroid), 0u);
    return glm::uvec4(rect, coef);
}
PartState unpackPart16(const glm::uvec4& bits) {
    PartState s;
    s.rect = toRect(unpackRect16(glm::uvec2(bits.x, bits.y)));
    s.vCoef = unpackVCoef16(glm::uvec2(bits.z, bits.w));
    s.centroid = dvec2(unpackCentroid16(glm::uvec2(bits.z, bits.w)));
    return s;
}

PartState quantise(const PartState& s, int bits) {
    if (bits == 8) return unpackPart8(packPart8(s));
    if (bits == 16) return unpackPart16(packPart16(s));
    return s;
}

GroupState quantise(const GroupState& g, int bits) {
    GroupState out = g;
    for (int k = 0; k < g.parts; ++k)
        out.part[k] = quantise(g.part[k], bits);
    return out;
}

} // namespace geometry::blend
