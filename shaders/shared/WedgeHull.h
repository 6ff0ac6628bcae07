// Conservative hull of a penumbra wedge with a fixed topology (8 triangles, 24 vertices), built
// per vertex on the GPU for vertex pulling (no CPU wedge building). Pure functions, no bindings;
// GLSL and C++ alike (Prelude.h): the CPU tests (tests/geometry/shadow/WedgeHullTest.cpp) run these
// very statements, and a GL test compares the driver's result with them.
//
// The exact wedge of edge E = [e0, e1] for the light c + s u + t v (s, t in [-1, 1]) is
// W = E + cone{e_i - c_j} (geometry/shadow/Wedge.h). With a = unit(e1 - e0), every ray e_i - c_j is
// P_j + A_j a (P_j ⟂ a; e1's rays have the same P_j and A_j + |e1 - e0|). When the P_j lie in a
// sector narrower than 180° (the edge's line misses the light's projection along a), its two
// boundary directions F and B give W's exact front and back planes span(a, F), span(a, B)
// through E. The side plane at e0 is a plane A = dot(P, h0) below every ray (A_j >=
// dot(P_j, h0)), the one at e1 a plane A = dot(P, h1) above every ray of e1; each is one of W's
// own side facets (a plane through the end point and two light corners), the one leaving the
// hull the smallest solid angle. Then with
//     g1 = F + dot(F, h0) a,  g2 = F + dot(F, h1) a,  g3 = B + dot(B, h0) a,  g4 = B + dot(B, h1) a
// (normalised) the cone K = cone(g1..g4) = { P + A a : P in the sector, dot(P, h0) <= A <=
// dot(P, h1) } holds every ray, and H = E + K ⊇ W. H is bounded by the front quad (E, g1, g2),
// the back quad (E, g3, g4), one side triangle at each end point and a quad at infinity:
// 8 triangles, 24 vertices, whatever the edge and light. (One slope per side against the
// sector's bisector, tried first, was looser: for generic edges far out, a median of 0.89 of the
// hull inside W and a 10th percentile of 0.66, against 0.95 and 0.80 here.)
//
// Float safety: the sector is widened and h0, h1 moved outward by amounts derived from a bound
// on the rounding of every ray coordinate, and the planes are pushed outward, so that every
// exact point of W lies inside the float planes (tested in tests/geometry/shadow/WedgeHullTest.cpp,
// which also shows the margins are needed: a 16th of them fails). The hull is Fullscreen
// instead where that bound is too weak (the edge's line passes within 3e-4 (|e0 - c| + |u| + |v|)
// + 1.5e-4 |e1 - e0| of a light corner, seen along the edge), where the sector is wider than 178°
// (wedgeHullNarrowed: unless the part of it that sees the edge as a silhouette is narrower),
// or where the side planes would cross inside the sector (a ray nearly along the edge). Quads are
// split into two triangles whose planes agree only to the rounding of their vertices (~1e-7 of
// the scene).
//
//
// Vertex shader use (one instance or 24 vertices per directed silhouette edge):
//     WedgeHull hull = wedgeHull(e0, e1, frame.lightCenter.xyz, frame.lightU.xyz, frame.lightV.xyz);
//     gl_Position = wedgeHullClipVertex(hull, gl_VertexID % kWedgeHullVertexCount, frame.viewProj);
//     vPlanes = hull.planes;  // flat, for wedgeHullContains in the fragment shader
// Draw back faces only, no depth test, depth clamp on (the face the view ray leaves through may
// lie in front of the near plane when the camera is inside the hull).

#ifndef PENUMBRA_SHARED_WEDGEHULL_H
#define PENUMBRA_SHARED_WEDGEHULL_H

#include "Prelude.h"

SHARED_BEGIN

// The hull's kind (a plain int, the same in both languages).
const int kWedgeHullBounded = 0;    // the 24 vertices below bound W
const int kWedgeHullFullscreen = 1; // no useful bound (the edge touches or crosses the light,
                                    // sees it over ~180 degrees, or points at a corner): test
                                    // every pixel (scissored); vertices 0..2 cover the viewport
const int kWedgeHullDegenerate = 2; // zero-length (or non-finite) edge: draw nothing
const int kWedgeHullVertexCount = 24;

// Vertex slots of the 24 hull vertices: 0 e0, 1 e1, 2..5 g1..g4 (w = 0). Outward winding
// (counter-clockwise seen from outside; a triangle at infinity counts as seen from any finite
// point, which is inside):
//   front  (e1, e0, g1) (e1, g1, g2)    back   (e0, e1, g4) (e0, g4, g3)
//   side 0 (e0, g3, g1)                 side 1 (e1, g2, g4)
//   far    (g1, g3, g4) (g1, g4, g2)
const int kWedgeHullIndex[kWedgeHullVertexCount] = {
    1, 0, 2, 1, 2, 3, // front
    0, 1, 5, 0, 5, 4, // back
    0, 4, 2,          // side at e0
    1, 3, 5,          // side at e1
    2, 4, 5, 2, 5, 3, // far
};

// "Front" is the plane with the sector on its counter-clockwise side about a = e1 - e0: with the
// loop orientation of geometry/shadow/Silhouette.h (occluder to the left of e0 -> e1 seen from the
// light centre) it borders the lit side and "back" the umbra side.
struct WedgeHull {
    int kind;
    vec3 e0;
    vec3 e1;
    vec3 g[4];      // g1..g4: unit directions of the cone's edges (Bounded only)
    vec4 planes[4]; // front, back, side at e0, side at e1: xyz unit outward normal,
                    // w = -dot(n, point); inside when dot(n, p) + w <= 0
    int cone;       // 1: a silhouette cone (wedgeHullSilhouetteCone): vertices 0 and 1 both at apex
    vec3 apex;
    float reach;    // a cone truncated to a box (wedgeHullTruncateCone): vertices 2..5 are the
                    // points apex + reach g; 0: directions at infinity
};

// Rounding of the ray coordinates computed below (unit roundoff 2^-24 = 6e-8), with slack:
// - per unit of |e0 - c| + |u| + |v|: ~10 roundings of products of that size (k, the frame's
//   non-orthogonality, the dot products);
// - per unit of |e1 - e0|: e1's rays are taken as e0's plus len a, and the float a is off the
//   exact edge direction by ~2 roundings (the difference, the division), plus the frame's ~2.
const float kWedgeHullRound = 1.0e-6f;
const float kWedgeHullRoundLen = 5.0e-7f;
// Angles (radians) by which the sector is widened: at least this, and at most the maximum
// (beyond it the rounding bound is too weak to trust the sector and the hull is Fullscreen; the
// margin argument needs twice it below the 2° that kWedgeHullMinHalfCos leaves).
const float kWedgeHullAngleBase = 1.0e-6f;
const float kWedgeHullAngleMax = 1.0e-2f;
// cos(89°): sectors wider than 178° (cos of the half angle below this) are Fullscreen; the
// hull would be nearly a half-space anyway, and the slope bounds lose accuracy as 1 / cos.
const float kWedgeHullMinHalfCos = 0.017452406f;

SHARED_FN float wedgeHullCross2(vec2 a, vec2 b) {
    return a.x * b.y - a.y * b.x;
}

// Solid angle (steradians, up to a constant) of the directions over the sector from fw to bw
// (counter-clockwise) that lie below the plane A = dot(P, h): with u(φ) the unit direction at
// azimuth φ, the integral of sin(elevation) = s / sqrt(1 + s^2), s = dot(u, h), which is
// asin(cross2(h, u) / sqrt(1 + |h|^2)) between the limits.
SHARED_FN float wedgeHullSpread(vec2 h, vec2 fw, vec2 bw) {
    float r = 1.0f / sqrt(1.0f + dot(h, h));
    float sb = clamp(wedgeHullCross2(h, bw) * r, -1.0f, 1.0f);
    float sf = clamp(wedgeHullCross2(h, fw) * r, -1.0f, 1.0f);
    return asin(sb) - asin(sf);
}

// A side plane of the hull, A = dot(P, h) in the frame of wedgeHull, with dot(P[k], h) <= B[k]
// for the four rays: the feasible intersection of two constraints (one of W's own side facets)
// that leaves the hull the smallest solid angle, i.e. maximises wedgeHullSpread; then moved
// along -m until every constraint holds with a margin for rounding. The margin covers the errors
// of P and B (rho each, so rho (1 + |h|) on the constraint) and the float directions g (~2^-23
// of |r| (1 + |h|)); two passes, as the margin grows with |h|. Needs dot(P[k], m) > 0.
SHARED_FN vec2 wedgeHullSide(const vec2 P[4], const float B[4], vec2 fw, vec2 bw, vec2 m, float rho) {
    vec2 h = vec2(0.0f);
    float best = -3.0e38f;
    bool found = false;
    for (int i = 0; i < 3; ++i) {
        for (int j = i + 1; j < 4; ++j) {
            float det = wedgeHullCross2(P[i], P[j]);
            if (!(abs(det) > 1.0e-4f * length(P[i]) * length(P[j]))) continue;
            vec2 c = vec2(B[i] * P[j].y - B[j] * P[i].y, P[i].x * B[j] - P[j].x * B[i]) / det;
            bool feasible = true;
            for (int k = 0; k < 4; ++k) {
                float slack = 1.0e-5f * (abs(B[k]) + length(P[k]) * length(c));
                feasible = feasible && dot(P[k], c) <= B[k] + slack;
            }
            float spread = wedgeHullSpread(c, fw, bw);
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
        float nh = 1.0f + length(h);
        float tau = 0.0f;
        for (int k = 0; k < 4; ++k) {
            float margin =
                nh * (2.0f * rho + kWedgeHullAngleBase * (abs(B[k]) + length(P[k])));
            tau = max(tau, (dot(P[k], h) - B[k] + margin) / dot(P[k], m));
        }
        h = h - tau * m;
    }
    return h;
}


// The angle (radians, in (-pi, pi]) from unit direction `from` to d, counter-clockwise.
SHARED_FN float wedgeHullAngle(vec2 from, vec2 d) {
    return atan(wedgeHullCross2(from, d), dot(from, d));
}

// Margin (radians) by which a silhouette-narrowed sector is widened on either side, at least:
// receivers within it of a face's plane are decided by the camera's side of it (wedges-bitmask),
// and the direction of a receiver close to the edge is known only to its rounding. To it is added
// the angle the rounding of the third vertices' components across the edge may turn them
// (kWedgeHullRound of the coordinates over their length); beyond kWedgeHullSilhouetteMarginMax
// the hull is not narrowed.
const float kWedgeHullSilhouetteMargin = 2.0e-3f;
const float kWedgeHullSilhouetteMarginMax = 0.1f;

// The part [lo, hi] of the sector [0, span] (angles from fw) whose directions d see the edge as
// a silhouette: the plane through the edge along d leaves both triangles' third vertices (q0, q1:
// their components across the edge) on one side, cross(d, q0) cross(d, q1) >= 0. That sign
// changes only at +-q0, +-q1, so over the sector widened by kWedgeHullSilhouetteMargin the
// silhouette part starts at the widened start if that qualifies, else at the first of those
// directions inside, and ends likewise. Widened by `margin` and clamped to the sector; false
// when no direction within the margin of the sector qualifies.
SHARED_FN bool wedgeHullSilhouetteSpan(vec2 fw, float span, vec2 q0, vec2 q1, float margin,
                                       SHARED_OUT(float) lo, SHARED_OUT(float) hi) {
    float first = -margin;
    float last = span + margin;
    vec2 df = vec2(cos(first) * fw.x - sin(first) * fw.y, sin(first) * fw.x + cos(first) * fw.y);
    vec2 dl = vec2(cos(last) * fw.x - sin(last) * fw.y, sin(last) * fw.x + cos(last) * fw.y);
    bool atFirst = wedgeHullCross2(df, q0) * wedgeHullCross2(df, q1) >= 0.0f;
    bool atLast = wedgeHullCross2(dl, q0) * wedgeHullCross2(dl, q1) >= 0.0f;
    lo = atFirst ? first : 3.0e38f;
    hi = atLast ? last : -3.0e38f;
    for (int k = 0; k < 4; ++k) {
        vec2 q = k < 2 ? q0 : q1;
        if (k == 1 || k == 3) q = -q;
        // Measured from `first` round the full turn: a sector near 180 degrees (a wide one,
        // wedgeHullNarrowed) ends past pi, where wedgeHullAngle wraps.
        float t = wedgeHullAngle(fw, q);
        if (!(t > first)) t += 6.28318531f;
        if (t > first && t < last) {
            lo = min(lo, t);
            hi = max(hi, t);
        }
    }
    if (!(hi >= lo)) return false;
    lo = max(lo - margin, 0.0f);
    hi = min(hi + margin, span);
    return hi >= lo;
}

// wedgeHull limited to the receivers that can see the edge as a silhouette, for an edge of two
// triangles with third vertices w0, w1 (wedges-bitmask silhouettes=potential: elsewhere the
// edge's m_P is 0 and its fragments would be discarded). The front and back planes turn towards
// each other to the silhouette part of the sector (wedgeHullSilhouetteSpan); the side planes
// stay those of the whole sector, which hold for any part of it. Degenerate (nothing drawn)
// when no receiver of the wedge sees a silhouette. A sector over 178 degrees (but under 180),
// which wedgeHull leaves Fullscreen, is bounded where its silhouette part is under 178: an edge
// just under the light's plane, under the light, seen from the light over nearly a half-plane,
// of which a box's edge sees one quarter as a silhouette (data/stability/light-grazing's shelf:
// two of its four Fullscreen wedges, 5663 -> 4006 tile entries at 256^2).
SHARED_FN WedgeHull wedgeHullNarrowed(vec3 e0, vec3 e1, vec3 c, vec3 u, vec3 v, bool narrow,
                                      vec3 w0, vec3 w1);

// Degenerate, every field set.
SHARED_FN WedgeHull wedgeHullEmpty(vec3 e0, vec3 e1) {
    WedgeHull hull;
    hull.kind = kWedgeHullDegenerate;
    hull.e0 = e0;
    hull.e1 = e1;
    for (int i = 0; i < 4; ++i) {
        hull.g[i] = vec3(0.0f);
        hull.planes[i] = vec4(0.0f);
    }
    hull.cone = 0;
    hull.apex = vec3(0.0f);
    hull.reach = 0.0f;
    return hull;
}

SHARED_FN WedgeHull wedgeHull(vec3 e0, vec3 e1, vec3 c, vec3 u, vec3 v) {
    return wedgeHullNarrowed(e0, e1, c, u, v, false, vec3(0.0f), vec3(0.0f));
}

SHARED_FN WedgeHull wedgeHullNarrowed(vec3 e0, vec3 e1, vec3 c, vec3 u, vec3 v, bool narrow,
                                      vec3 w0, vec3 w1) {
    WedgeHull hull = wedgeHullEmpty(e0, e1);
    vec3 d = e1 - e0;
    float len = length(d);
    if (!(len > 0.0f) || isinf(len)) return hull; // zero length, or not finite
    hull.kind = kWedgeHullFullscreen;

    // Orthonormal frame (x, y, a), cross(x, y) = a; 2D vectors below are in (x, y).
    vec3 a = d / len;
    vec3 x =
        normalize(cross(abs(a.x) < 0.5f ? vec3(1.0f, 0.0f, 0.0f) : vec3(0.0f, 1.0f, 0.0f), a));
    vec3 y = cross(a, x);

    // Rays from e0 through the corners c_j = c + s u + t v, (s, t) = (-1, -1) (1, -1) (1, 1)
    // (-1, 1): e0 - c_j = P[j] + A[j] a; e1's rays are P[j] + (A[j] + len) a.
    vec3 k = e0 - c;
    vec2 o = vec2(dot(k, x), dot(k, y));
    vec2 pu = vec2(dot(u, x), dot(u, y));
    vec2 pv = vec2(dot(v, x), dot(v, y));
    float ak = dot(k, a);
    float au = dot(u, a);
    float av = dot(v, a);
    // Bound on the error of every P[j] and A[j] against the exact rays in this float frame.
    float rho =
        kWedgeHullRound * (length(k) + length(u) + length(v)) + kWedgeHullRoundLen * len;
    vec2 P[4];
    float A[4];
    float minPerp = 3.0e38f;
    for (int j = 0; j < 4; ++j) {
        float s = (j == 1 || j == 2) ? 1.0f : -1.0f;
        float t = (j >= 2) ? 1.0f : -1.0f;
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
    vec2 fu = P[f] / length(P[f]);
    vec2 bu = P[b] / length(P[b]);
    // Widening, per side: every ray within 3 rho of a boundary is turned 3 rho inside it (the
    // angle that takes is 3 rho / |P[j]|, at most kWedgeHullAngleMax).
    float thetaF = kWedgeHullAngleBase;
    float thetaB = kWedgeHullAngleBase;
    for (int j = 0; j < 4; ++j) {
        float need = kWedgeHullAngleBase + 3.0f * rho / length(P[j]);
        if (wedgeHullCross2(fu, P[j]) < 3.0f * rho) thetaF = max(thetaF, need);
        if (wedgeHullCross2(P[j], bu) < 3.0f * rho) thetaB = max(thetaB, need);
    }
    // cos and sin to ~theta^3 / 6 <= 2e-7 of theta: GPU sin and cos may have absolute errors of
    // ~5e-7, more than the smallest theta.
    float csF = 1.0f - 0.5f * thetaF * thetaF;
    float snF = thetaF;
    float csB = 1.0f - 0.5f * thetaB * thetaB;
    float snB = thetaB;
    vec2 fw = vec2(csF * fu.x + snF * fu.y, csF * fu.y - snF * fu.x); // fu turned by -thetaF
    vec2 bw = vec2(csB * bu.x - snB * bu.y, csB * bu.y + snB * bu.x); // bu turned by +thetaB
    vec2 sum = fw + bw;
    float cHalf = 0.5f * length(sum); // cos(half the widened sector)
    // Wider than 178 degrees (a light whose plane nearly holds the edge: a lamp close under a
    // ceiling, a shelf's top): the whole wedge is Fullscreen, but the part of it that sees the
    // edge as a silhouette may still be a narrow sector (below), bounded while under 180.
    bool wide = !(cHalf >= kWedgeHullMinHalfCos);
    if (!(wedgeHullCross2(fw, bw) > 0.0f) || (wide && !narrow)) return hull;
    vec2 m = sum / length(sum); // the bisector
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
    vec2 h0 = wedgeHullSide(P, lower, fw, bw, m, rho);
    vec2 h1 = -wedgeHullSide(P, upper, fw, bw, m, rho);
    // The cone's edges: where the side planes meet the front and back planes.
    float f0 = dot(fw, h0);
    float f1 = dot(fw, h1);
    float b0 = dot(bw, h0);
    float b1 = dot(bw, h1);
    if (!(f1 > f0 && b1 > b0)) return hull; // (the sides would cross inside the sector)
    if (narrow) {
        vec3 r0 = w0 - e0;
        vec3 r1 = w1 - e0;
        vec2 q0 = vec2(dot(r0, x), dot(r0, y));
        vec2 q1 = vec2(dot(r1, x), dot(r1, y));
        float shortest = min(length(q0), length(q1));
        float margin = kWedgeHullSilhouetteMargin +
                       4.0f * kWedgeHullRound * (length(e0) + length(w0) + length(w1)) / shortest;
        float lo = 0.0f;
        float hi = 0.0f;
        if (!(margin < kWedgeHullSilhouetteMarginMax)) {
            if (wide) return hull; // too uncertain, and the whole sector too wide: Fullscreen
            lo = 0.0f; // too uncertain: the whole sector
            hi = wedgeHullAngle(fw, bw);
        } else if (!wedgeHullSilhouetteSpan(fw, wedgeHullAngle(fw, bw), q0, q1, margin, lo, hi)) {
            hull.kind = kWedgeHullDegenerate;
            return hull;
        }
        vec2 nf = vec2(cos(lo) * fw.x - sin(lo) * fw.y, sin(lo) * fw.x + cos(lo) * fw.y);
        vec2 nb = vec2(cos(hi) * fw.x - sin(hi) * fw.y, sin(hi) * fw.x + cos(hi) * fw.y);
        // A wide sector narrowed to 178 degrees or more stays Fullscreen.
        if (wide && !(0.5f * length(nf + nb) >= kWedgeHullMinHalfCos)) return hull;
        fw = nf;
        bw = nb;
        // The side planes are linear along the sector: ordered at its ends, so at these.
        f0 = dot(fw, h0);
        f1 = dot(fw, h1);
        b0 = dot(bw, h0);
        b1 = dot(bw, h1);
    }

    vec3 F = fw.x * x + fw.y * y;
    vec3 B = bw.x * x + bw.y * y;
    hull.g[0] = normalize(F + f0 * a);
    hull.g[1] = normalize(F + f1 * a);
    hull.g[2] = normalize(B + b0 * a);
    hull.g[3] = normalize(B + b1 * a);

    // Planes, pushed outward by the rounding of their offsets and of the normals against E.
    float push = kWedgeHullRound * (length(e0) + length(e1));
    vec3 nFront = fw.y * x - fw.x * y;
    vec3 nBack = bw.x * y - bw.y * x;
    vec3 nSide0 = normalize(h0.x * x + h0.y * y - a);
    vec3 nSide1 = normalize(a - h1.x * x - h1.y * y);
    hull.planes[0] = vec4(nFront, -dot(nFront, e0) - push);
    hull.planes[1] = vec4(nBack, -dot(nBack, e0) - push);
    hull.planes[2] = vec4(nSide0, -dot(nSide0, e0) - push);
    hull.planes[3] = vec4(nSide1, -dot(nSide1, e1) - push);
    hull.kind = kWedgeHullBounded;
    return hull;
}

// Where wedgeHull is Fullscreen (typically an edge whose line passes through the light: the
// rays from the light through it surround it), the receivers that can see an edge of two
// triangles as a silhouette still lie in two thin opposite sectors about its line: directions d
// (across the edge) with both third vertices' components q0, q1 on one side of span(a, d),
// cross(d, q0) cross(d, q1) >= 0. With alpha the angle from q0 to q1, they are the sector from
// -qa to qb (counter-clockwise, pi - |alpha| wide) and its opposite, (qa, qb) = (q1, q0) when
// alpha >= 0, else (q0, q1); `which` (0 or 1) picks one, widened by the narrowed hull's margin on
// each side. Every receiver is a point e + lambda (e - y) of the edge e and a light point y, so
// it lies farther from the light's plane than the end point nearer to it: the cap, that plane
// moved through this end point. Sector and cap make a cone with its apex on the edge's line
// (just past the nearer end point, towards the light) and three edges at infinity: along the
// edge away from the light, and the sector's two boundary directions turned into the cap's
// plane. It takes the hull's topology with vertices 0 and 1 both at the apex (their triangles
// of the front and back quads and the far side's are then empty): the cap is the side plane at
// the nearer end point, the other side plane is dropped (0, 0, 0, -1). Fullscreen where this
// cannot be done: an end point within rounding of the light's plane (or beyond it), an edge
// within 0.57 degrees of parallel to it, a sector (widened) of 178 degrees or more, or third
// vertices too close to the edge to give a direction.
SHARED_FN WedgeHull wedgeHullSilhouetteCone(vec3 e0, vec3 e1, vec3 c, vec3 u, vec3 v, vec3 w0,
                                            vec3 w1, int which) {
    WedgeHull hull = wedgeHullEmpty(e0, e1);
    vec3 d = e1 - e0;
    float len = length(d);
    if (!(len > 0.0f) || isinf(len)) return hull;
    hull.kind = kWedgeHullFullscreen;
    vec3 a = d / len;
    vec3 x =
        normalize(cross(abs(a.x) < 0.5f ? vec3(1.0f, 0.0f, 0.0f) : vec3(0.0f, 1.0f, 0.0f), a));
    vec3 y = cross(a, x);
    vec3 n = cross(u, v);
    float nLen = length(n);
    if (!(nLen > 0.0f)) return hull;
    n = n / nLen;
    float s0 = dot(n, c - e0);
    if (s0 < 0.0f) n = -n;
    s0 = dot(n, c - e0);
    float s1 = dot(n, c - e1);
    float push = kWedgeHullRound * (length(e0) + length(e1));
    float tol = kWedgeHullRound * (length(c) + length(u) + length(v)) + 2.0f * push;
    if (!(s0 > tol && s1 > tol)) return hull;
    float na = dot(n, a); // > 0: e1 is the end point nearer the light's plane
    if (!(abs(na) > 1.0e-2f)) return hull;

    vec3 r0 = w0 - e0;
    vec3 r1 = w1 - e0;
    vec2 q0 = vec2(dot(r0, x), dot(r0, y));
    vec2 q1 = vec2(dot(r1, x), dot(r1, y));
    float shortest = min(length(q0), length(q1));
    if (!(shortest > 0.0f)) return hull;
    float margin = kWedgeHullSilhouetteMargin +
                   4.0f * kWedgeHullRound * (length(e0) + length(w0) + length(w1)) / shortest;
    if (!(margin < kWedgeHullSilhouetteMarginMax)) return hull;
    vec2 u0 = q0 / length(q0);
    vec2 u1 = q1 / length(q1);
    bool ccw = wedgeHullCross2(u0, u1) >= 0.0f;
    vec2 qa = ccw ? u1 : u0;
    vec2 qb = ccw ? u0 : u1;
    vec2 start = which == 0 ? -qa : qa;
    vec2 end = which == 0 ? qb : -qb;
    float cm = cos(margin);
    float sm = sin(margin);
    vec2 fw = vec2(cm * start.x + sm * start.y, cm * start.y - sm * start.x); // turned by -margin
    vec2 bw = vec2(cm * end.x - sm * end.y, cm * end.y + sm * end.x);         // by +margin
    vec2 sum = fw + bw;
    if (!(wedgeHullCross2(fw, bw) > 0.0f && 0.5f * length(sum) >= kWedgeHullMinHalfCos))
        return hull;

    vec3 F = fw.x * x + fw.y * y;
    vec3 B = bw.x * x + bw.y * y;
    // The sector's boundaries turned along the edge into the cap's plane (dot(n, .) = 0).
    vec3 Fh = normalize(F - (dot(n, F) / na) * a);
    vec3 Bh = normalize(B - (dot(n, B) / na) * a);
    // The apex: the nearer end point moved towards the light along the edge's line, so that the
    // cap's plane clears the end point by 4 pushes; the cap pushed once more.
    bool nearE1 = na > 0.0f;
    vec3 apex = (nearE1 ? e1 : e0) + ((nearE1 ? 4.0f : -4.0f) * push / abs(na)) * a;
    vec4 cap = vec4(n, -dot(n, apex) - push);
    vec4 none = vec4(0.0f, 0.0f, 0.0f, -1.0f);
    vec3 away = nearE1 ? -a : a; // along the edge, away from the light
    hull.g[0] = nearE1 ? away : Fh;
    hull.g[1] = nearE1 ? Fh : away;
    hull.g[2] = nearE1 ? away : Bh;
    hull.g[3] = nearE1 ? Bh : away;
    vec3 nFront = fw.y * x - fw.x * y;
    vec3 nBack = bw.x * y - bw.y * x;
    hull.planes[0] = vec4(nFront, -dot(nFront, e0) - push);
    hull.planes[1] = vec4(nBack, -dot(nBack, e0) - push);
    hull.planes[2] = nearE1 ? none : cap;
    hull.planes[3] = nearE1 ? cap : none;
    hull.cone = 1;
    hull.apex = apex;
    hull.kind = kWedgeHullBounded;
    return hull;
}

// A silhouette cone cut to what its receivers can reach: the cone is apex + sum c_i g_i over its
// three distinct directions (c_i >= 0), and l(p) = sum c_i is linear, so its largest value over
// a convex set is at one of the set's vertices. Receivers lie in the box [lo, hi] (the caster's
// influence bounds) and in the edge's wedge W = E + cone{e_i - c_j}, whose part above the plane
// parallel to the light through the box's corner farthest from it is the polytope of the end
// points and the 8 points where the rays from the light's corners through them cross that plane
// (every ray goes away from the light: both end points lie on one side of its plane). With reach
// just above the smaller of l's largest values over the box's corners and over those 10 points,
// the far face through apex + reach g_i leaves every receiver of the cone inside, and the cone
// becomes a tetrahedron (finite, so that it covers only the screen its receivers may).
// Degenerate when that largest value is not positive (no receiver in the cone); unchanged
// (directions at infinity, reach 0) where the directions are too close to dependent: the
// wedge set-up then keeps the edge's full-screen wedge instead of its two cones.
SHARED_FN WedgeHull wedgeHullTruncateCone(WedgeHull hull, vec3 c, vec3 u, vec3 v, vec3 lo,
                                          vec3 hi) {
    if (hull.kind != kWedgeHullBounded || hull.cone == 0) return hull;
    // The three distinct directions: slots 0 and 2 (or 1 and 3) hold the same one.
    bool nearE1 = hull.g[0] == hull.g[2];
    vec3 ga = nearE1 ? hull.g[0] : hull.g[1];
    vec3 gb = nearE1 ? hull.g[1] : hull.g[0];
    vec3 gc = nearE1 ? hull.g[3] : hull.g[2];
    float det = dot(ga, cross(gb, gc));
    if (!(abs(det) > 1.0e-4f)) return hull;
    vec3 l = (cross(gb, gc) + cross(gc, ga) + cross(ga, gb)) / det;
    vec3 n = normalize(cross(u, v));
    if (dot(n, c - hull.e0) < 0.0f) n = -n;
    float inBox = -3.0e38f;
    float deepest = 3.0e38f;
    for (int k = 0; k < 8; ++k) {
        vec3 corner = vec3((k & 1) != 0 ? hi.x : lo.x, (k & 2) != 0 ? hi.y : lo.y,
                           (k & 4) != 0 ? hi.z : lo.z);
        inBox = max(inBox, dot(l, corner - hull.apex));
        deepest = min(deepest, dot(n, corner));
    }
    deepest -= 1.0e-3f * length(hi - lo);
    float inWedge = max(dot(l, hull.e0 - hull.apex), dot(l, hull.e1 - hull.apex));
    for (int j = 0; j < 4; ++j) {
        float s = (j == 1 || j == 2) ? 1.0f : -1.0f;
        float t = (j >= 2) ? 1.0f : -1.0f;
        vec3 corner = c + s * u + t * v;
        for (int i = 0; i < 2; ++i) {
            vec3 e = i == 0 ? hull.e0 : hull.e1;
            vec3 ray = e - corner;
            float down = -dot(n, ray);
            float over = dot(n, e) - deepest;
            // (down > 0 for the cones built: both end points under the light's plane)
            float along = over > 0.0f && down > 0.0f ? over / down : 0.0f;
            inWedge = max(inWedge, dot(l, e + along * ray - hull.apex));
        }
    }
    float most = min(inBox, inWedge);
    if (!(most > 0.0f)) {
        hull.kind = kWedgeHullDegenerate;
        return hull;
    }
    hull.reach = most * 1.001f + 1.0e-4f * length(hi - lo);
    return hull;
}

// Vertex `index` (0..23) as a homogeneous point (w = 1) or direction (w = 0); vec4(0) for every
// index unless the hull is Bounded.
SHARED_FN vec4 wedgeHullVertex(WedgeHull hull, int index) {
    if (hull.kind != kWedgeHullBounded) return vec4(0.0f);
    int slot = kWedgeHullIndex[index];
    if (slot <= 1 && hull.cone != 0) return vec4(hull.apex, 1.0f);
    if (slot >= 2 && hull.cone != 0 && hull.reach > 0.0f)
        return vec4(hull.apex + hull.reach * hull.g[slot - 2], 1.0f);
    if (slot == 0) return vec4(hull.e0, 1.0f);
    if (slot == 1) return vec4(hull.e1, 1.0f);
    return vec4(hull.g[slot - 2], 0.0f);
}

// Clip-space position for a draw of 24 vertices per edge: Bounded: viewProj times the vertex;
// Fullscreen: vertices 0..2 a triangle covering the viewport, wound clockwise in NDC (back-facing
// under glFrontFace(GL_CCW), like the hull's own back faces), the others vec4(0); Degenerate:
// vec4(0) (no fragments).
SHARED_FN vec4 wedgeHullClipVertex(WedgeHull hull, int index, mat4 viewProj) {
    if (hull.kind == kWedgeHullFullscreen) {
        if (index == 0) return vec4(-1.0f, -1.0f, 0.0f, 1.0f);
        if (index == 1) return vec4(-1.0f, 3.0f, 0.0f, 1.0f);
        if (index == 2) return vec4(3.0f, -1.0f, 0.0f, 1.0f);
        return vec4(0.0f);
    }
    return viewProj * wedgeHullVertex(hull, index);
}

// The plane test (early-out in the fragment shader): true when p is inside all four planes.
// The pushes in the planes cover float rounding here; a Fullscreen hull's planes are zero, so
// every point is inside, and so are a Degenerate hull's (callers draw nothing for it).
SHARED_FN bool wedgeHullContains(const vec4 planes[4], vec3 p) {
    for (int i = 0; i < 4; ++i) {
        if (dot(vec3(planes[i]), p) + planes[i].w > 0.0f) return false;
    }
    return true;
}

SHARED_END

#endif // PENUMBRA_SHARED_WEDGEHULL_H
