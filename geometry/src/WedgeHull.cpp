// Fixed-topology conservative penumbra-wedge hull (geometry/WedgeHull.h). Float twin of
// shaders/lib/WedgeHull.glsl: every statement below has its counterpart there, in the same
// order and with the same names; only the C++ spelling differs (0.0f, std::, references).
#include <geometry/WedgeHull.h>

#include <algorithm>
#include <cmath>

namespace geometry {
namespace {

using glm::mat4;
using glm::vec2;
using glm::vec3;
using glm::vec4;
using std::abs;
using std::asin;
using std::clamp;
using std::max;
using std::min;
using std::sqrt;

// Rounding of the ray coordinates computed below (unit roundoff 2^-24 = 6e-8), with slack:
// - per unit of |e0 - c| + |u| + |v|: ~10 roundings of products of that size (k, the frame's
//   non-orthogonality, the dot products);
// - per unit of |e1 - e0|: e1's rays are taken as e0's plus len a, and the float a is off the
//   exact edge direction by ~2 roundings (the difference, the division), plus the frame's ~2.
constexpr float kWedgeHullRound = 1.0e-6f;
constexpr float kWedgeHullRoundLen = 5.0e-7f;
// Angles (radians) by which the sector is widened: at least this, and at most the maximum
// (beyond it the rounding bound is too weak to trust the sector and the hull is Fullscreen; the
// margin argument needs twice it below the 2° that kWedgeHullMinHalfCos leaves).
constexpr float kWedgeHullAngleBase = 1.0e-6f;
constexpr float kWedgeHullAngleMax = 1.0e-2f;
// cos(89°): sectors wider than 178° (cos of the half angle below this) are Fullscreen; the
// hull would be nearly a half-space anyway, and the slope bounds lose accuracy as 1 / cos.
constexpr float kWedgeHullMinHalfCos = 0.017452406f;

float wedgeHullCross2(vec2 a, vec2 b) {
    return a.x * b.y - a.y * b.x;
}

// Solid angle (steradians, up to a constant) of the directions over the sector from fw to bw
// (counter-clockwise) that lie below the plane A = dot(P, h): with u(φ) the unit direction at
// azimuth φ, the integral of sin(elevation) = s / sqrt(1 + s^2), s = dot(u, h), which is
// asin(cross2(h, u) / sqrt(1 + |h|^2)) between the limits.
float wedgeHullSpread(vec2 h, vec2 fw, vec2 bw) {
    const float r = 1.0f / sqrt(1.0f + dot(h, h));
    const float sb = clamp(wedgeHullCross2(h, bw) * r, -1.0f, 1.0f);
    const float sf = clamp(wedgeHullCross2(h, fw) * r, -1.0f, 1.0f);
    return asin(sb) - asin(sf);
}

// A side plane of the hull, A = dot(P, h) in the frame of wedgeHull, with dot(P[k], h) <= B[k]
// for the four rays: the feasible intersection of two constraints (one of W's own side facets)
// that leaves the hull the smallest solid angle, i.e. maximises wedgeHullSpread; then moved
// along -m until every constraint holds with a margin for rounding. The margin covers the errors
// of P and B (rho each, so rho (1 + |h|) on the constraint) and the float directions g (~2^-23
// of |r| (1 + |h|)); two passes, as the margin grows with |h|. Needs dot(P[k], m) > 0.
vec2 wedgeHullSide(const vec2 P[4], const float B[4], vec2 fw, vec2 bw, vec2 m, float rho) {
    vec2 h = vec2(0.0f);
    float best = -3.0e38f;
    bool found = false;
    for (int i = 0; i < 3; ++i) {
        for (int j = i + 1; j < 4; ++j) {
            const float det = wedgeHullCross2(P[i], P[j]);
            if (!(abs(det) > 1.0e-4f * length(P[i]) * length(P[j]))) continue;
            const vec2 c = vec2(B[i] * P[j].y - B[j] * P[i].y, P[i].x * B[j] - P[j].x * B[i]) / det;
            bool feasible = true;
            for (int k = 0; k < 4; ++k) {
                const float slack = 1.0e-5f * (abs(B[k]) + length(P[k]) * length(c));
                feasible = feasible && dot(P[k], c) <= B[k] + slack;
            }
            const float spread = wedgeHullSpread(c, fw, bw);
            if (feasible && spread > best) {
                best = spread;
                h = c;
                found = true;
            }
        }
    }
    if (!found) { // (parallel rays only) the plane through the lowest ray along m
        float lo = 3.0e38f;
        for (int k = 0; k < 4; ++k)
            lo = min(lo, B[k] / dot(P[k], m));
        h = lo * m;
    }
    for (int pass = 0; pass < 2; ++pass) {
        const float nh = 1.0f + length(h);
        float tau = 0.0f;
        for (int k = 0; k < 4; ++k) {
            const float margin =
                nh * (2.0f * rho + kWedgeHullAngleBase * (abs(B[k]) + length(P[k])));
            tau = max(tau, (dot(P[k], h) - B[k] + margin) / dot(P[k], m));
        }
        h = h - tau * m;
    }
    return h;
}

} // namespace

WedgeHull wedgeHull(vec3 e0, vec3 e1, vec3 c, vec3 u, vec3 v) {
    WedgeHull hull;
    hull.kind = kWedgeHullDegenerate;
    hull.e0 = e0;
    hull.e1 = e1;
    for (int i = 0; i < 4; ++i) {
        hull.g[i] = vec3(0.0f);
        hull.planes[i] = vec4(0.0f);
    }
    const vec3 d = e1 - e0;
    const float len = length(d);
    if (!(len > 0.0f) || std::isinf(len)) return hull; // zero length, or not finite
    hull.kind = kWedgeHullFullscreen;

    // Orthonormal frame (x, y, a), cross(x, y) = a; 2D vectors below are in (x, y).
    const vec3 a = d / len;
    const vec3 x =
        normalize(cross(abs(a.x) < 0.5f ? vec3(1.0f, 0.0f, 0.0f) : vec3(0.0f, 1.0f, 0.0f), a));
    const vec3 y = cross(a, x);

    // Rays from e0 through the corners c_j = c + s u + t v, (s, t) = (-1, -1) (1, -1) (1, 1)
    // (-1, 1): e0 - c_j = P[j] + A[j] a; e1's rays are P[j] + (A[j] + len) a.
    const vec3 k = e0 - c;
    const vec2 o = vec2(dot(k, x), dot(k, y));
    const vec2 pu = vec2(dot(u, x), dot(u, y));
    const vec2 pv = vec2(dot(v, x), dot(v, y));
    const float ak = dot(k, a);
    const float au = dot(u, a);
    const float av = dot(v, a);
    // Bound on the error of every P[j] and A[j] against the exact rays in this float frame.
    const float rho =
        kWedgeHullRound * (length(k) + length(u) + length(v)) + kWedgeHullRoundLen * len;
    vec2 P[4];
    float A[4];
    float minPerp = 3.0e38f;
    for (int j = 0; j < 4; ++j) {
        const float s = (j == 1 || j == 2) ? 1.0f : -1.0f;
        const float t = (j >= 2) ? 1.0f : -1.0f;
        P[j] = o - s * pu - t * pv;
        A[j] = ak - s * au - t * av;
        minPerp = min(minPerp, length(P[j]));
    }
    // The rays' directions in the plane ⟂ a are known to rho / |P[j]|; where that exceeds
    // kWedgeHullAngleMax the sector cannot be trusted. (Compared before dividing: minPerp may
    // be 0.)
    if (!(3.0f * rho < (kWedgeHullAngleMax - kWedgeHullAngleBase) * minPerp)) return hull;

    // The sector's clockwise-most (f) and counter-clockwise-most (b) ray; meaningful only when
    // the P[j] lie in an open half-plane, which the test after widening checks.
    int f = 0;
    int b = 0;
    for (int j = 1; j < 4; ++j) {
        if (wedgeHullCross2(P[f], P[j]) < 0.0f) f = j;
        if (wedgeHullCross2(P[b], P[j]) > 0.0f) b = j;
    }
    const vec2 fu = P[f] / length(P[f]);
    const vec2 bu = P[b] / length(P[b]);
    // Widening, per side: every ray within 3 rho of a boundary is turned 3 rho inside it (the
    // angle that takes is 3 rho / |P[j]|, at most kWedgeHullAngleMax).
    float thetaF = kWedgeHullAngleBase;
    float thetaB = kWedgeHullAngleBase;
    for (int j = 0; j < 4; ++j) {
        const float need = kWedgeHullAngleBase + 3.0f * rho / length(P[j]);
        if (wedgeHullCross2(fu, P[j]) < 3.0f * rho) thetaF = max(thetaF, need);
        if (wedgeHullCross2(P[j], bu) < 3.0f * rho) thetaB = max(thetaB, need);
    }
    // cos and sin to ~theta^3 / 6 <= 2e-7 of theta: GPU sin and cos may have absolute errors of
    // ~5e-7, more than the smallest theta.
    const float csF = 1.0f - 0.5f * thetaF * thetaF;
    const float snF = thetaF;
    const float csB = 1.0f - 0.5f * thetaB * thetaB;
    const float snB = thetaB;
    const vec2 fw = vec2(csF * fu.x + snF * fu.y, csF * fu.y - snF * fu.x); // fu turned by -thetaF
    const vec2 bw = vec2(csB * bu.x - snB * bu.y, csB * bu.y + snB * bu.x); // bu turned by +thetaB
    const vec2 sum = fw + bw;
    const float cHalf = 0.5f * length(sum); // cos(half the widened sector)
    if (!(wedgeHullCross2(fw, bw) > 0.0f && cHalf >= kWedgeHullMinHalfCos)) return hull;
    const vec2 m = sum / length(sum); // the bisector
    // Every ray at least 1.5 rho inside both boundaries, so the exact rays (within rho) are
    // strictly inside.
    for (int j = 0; j < 4; ++j) {
        if (!(wedgeHullCross2(fw, P[j]) >= 1.5f * rho && wedgeHullCross2(P[j], bw) >= 1.5f * rho))
            return hull;
    }

    // Side planes: at e0 the plane A = dot(P, h0) with every ray above it, at e1 A = dot(P, h1)
    // with every ray below it (e1's rays are the higher ones, A + len).
    float lower[4];
    float upper[4];
    for (int j = 0; j < 4; ++j) {
        lower[j] = A[j];
        upper[j] = -(A[j] + len);
    }
    const vec2 h0 = wedgeHullSide(P, lower, fw, bw, m, rho);
    const vec2 h1 = -wedgeHullSide(P, upper, fw, bw, m, rho);
    // The cone's edges: where the side planes meet the front and back planes.
    const float f0 = dot(fw, h0);
    const float f1 = dot(fw, h1);
    const float b0 = dot(bw, h0);
    const float b1 = dot(bw, h1);
    if (!(f1 > f0 && b1 > b0)) return hull; // (the sides would cross inside the sector)

    const vec3 F = fw.x * x + fw.y * y;
    const vec3 B = bw.x * x + bw.y * y;
    hull.g[0] = normalize(F + f0 * a);
    hull.g[1] = normalize(F + f1 * a);
    hull.g[2] = normalize(B + b0 * a);
    hull.g[3] = normalize(B + b1 * a);

    // Planes, pushed outward by the rounding of their offsets and of the normals against E.
    const float push = kWedgeHullRound * (length(e0) + length(e1));
    const vec3 nFront = fw.y * x - fw.x * y;
    const vec3 nBack = bw.x * y - bw.y * x;
    const vec3 nSide0 = normalize(h0.x * x + h0.y * y - a);
    const vec3 nSide1 = normalize(a - h1.x * x - h1.y * y);
    hull.planes[0] = vec4(nFront, -dot(nFront, e0) - push);
    hull.planes[1] = vec4(nBack, -dot(nBack, e0) - push);
    hull.planes[2] = vec4(nSide0, -dot(nSide0, e0) - push);
    hull.planes[3] = vec4(nSide1, -dot(nSide1, e1) - push);
    hull.kind = kWedgeHullBounded;
    return hull;
}

vec4 wedgeHullVertex(const WedgeHull& hull, int index) {
    if (hull.kind != kWedgeHullBounded) return vec4(0.0f);
    const int slot = kWedgeHullIndex[index];
    if (slot == 0) return vec4(hull.e0, 1.0f);
    if (slot == 1) return vec4(hull.e1, 1.0f);
    return vec4(hull.g[slot - 2], 0.0f);
}

vec4 wedgeHullClipVertex(const WedgeHull& hull, int index, const mat4& viewProj) {
    if (hull.kind == kWedgeHullFullscreen) {
        if (index == 0) return vec4(-1.0f, -1.0f, 0.0f, 1.0f);
        if (index == 1) return vec4(-1.0f, 3.0f, 0.0f, 1.0f);
        if (index == 2) return vec4(3.0f, -1.0f, 0.0f, 1.0f);
        return vec4(0.0f);
    }
    return viewProj * wedgeHullVertex(hull, index);
}

bool wedgeHullContains(const vec4 planes[4], vec3 p) {
    for (int i = 0; i < 4; ++i) {
        if (dot(vec3(planes[i]), p) + planes[i].w > 0.0f) return false;
    }
    return true;
}

} // namespace geometry
