// Per-fragment coverage of one directed silhouette edge (DESIGN.md §4; Assarsson &
// Akenine-Möller 2003, §3-4): the signed fraction of the light between the edge projected from p
// and the light centre, zero outside the edge's exact wedge; V(p) = V_hard(p) - the sum over a
// silhouette loop. Pure functions, no bindings; GLSL and C++ alike (Prelude.h), so the GPU and
// its CPU tests run the same statements. The arithmetic of the double geometry::edgeCoverage
// (geometry/shadow/src/Wedge.cpp explains it, and the tests compare the two), arranged for float:
// differences of positions are taken before anything else (the scene may be far from the
// origin), an edge point is projected from the light centre or from p, whichever is nearer (so
// that p close to the edge does not cancel), the depths below p's level come from e - p rather
// than 1 - z, the light's frame is computed once (CoverageLight) rather than per call, and the
// area of the light square clipped by three half-planes is integrated along its boundary
// instead of clipping a polygon (no arrays, which are slow on GPUs).
//
// The prologue every per-edge computation shares (coverage here, the per-part sums of
// Parts.h, the light-sample masks of LightMask.h) is edgeProjection (the edge clipped to
// between p's level and the light, both ends projected) and edgeHalfPlanes (the region R as
// three half-planes).
#ifndef PENUMBRA_SHARED_COVERAGE_H
#define PENUMBRA_SHARED_COVERAGE_H

#include "Prelude.h"

SHARED_BEGIN

// The light c + s u + t v (s, t in [-1, 1]) with its unit normal n (along cross(u, v)) and the
// dual basis: s = dot(uStar, y - c), t = dot(vStar, y - c) for y in the light's plane.
struct CoverageLight {
    vec3 c;
    vec3 u;
    vec3 v;
    vec3 n;
    vec3 uStar;
    vec3 vStar;
};

SHARED_FN CoverageLight coverageLight(vec3 c, vec3 u, vec3 v) {
    CoverageLight light;
    light.c = c;
    light.u = u;
    light.v = v;
    light.n = normalize(cross(u, v));
    vec3 a = cross(v, light.n);
    vec3 b = cross(light.n, u);
    light.uStar = a / dot(u, a);
    light.vStar = b / dot(v, b);
    return light;
}

SHARED_FN float coverageCross2(vec2 a, vec2 b) {
    return a.x * b.y - a.y * b.x;
}

// Restricts [lo, hi] to the l where f0 + l (f1 - f0) <= 0; false when that leaves nothing.
SHARED_FN bool coverageClipLe0(float f0, float f1, SHARED_INOUT(float) lo, SHARED_INOUT(float) hi) {
    if (f0 <= 0.0f && f1 <= 0.0f) return lo <= hi;
    if (f0 > 0.0f && f1 > 0.0f) return false;
    float l = f0 / (f0 - f1);
    if (f0 > 0.0f)
        lo = max(lo, l);
    else
        hi = min(hi, l);
    return lo <= hi;
}

// Restricts [lo, hi] to the l where a + l (b - a) lies in the half-plane dot(h, (x, y, 1)) >= 0
// (closed, like the polygon clipping of the double version); false when that leaves nothing.
SHARED_FN bool coverageClipHalf(vec3 h, vec2 a, vec2 b, SHARED_INOUT(float) lo,
                                SHARED_INOUT(float) hi) {
    return coverageClipLe0(-dot(h, vec3(a, 1.0f)), -dot(h, vec3(b, 1.0f)), lo, hi);
}

// Twice the area of R (edgeCoverage) is the sum of cross(start, end) over the pieces of its
// boundary (Green, the centre as origin). One piece: a + l (b - a), l in [lo, hi], between the
// rays h0, h1.
SHARED_FN float coverageSegment(vec2 a, vec2 b, float lo, float hi, vec3 h0, vec3 h1) {
    if (!coverageClipHalf(h0, a, b, lo, hi)) return 0.0f;
    if (!coverageClipHalf(h1, a, b, lo, hi)) return 0.0f;
    return coverageCross2(a + lo * (b - a), a + hi * (b - a));
}

// The part [lo, hi] of a side a -> b of the light square (or of a part of it; counter-clockwise)
// on R's side of the line, where fa, fb are the line's h2 at a and b (R: h2 >= 0); false when
// the whole side is off it. Where the side crosses the line, the crossing is kept as the start
// (leave) or end (enter) of the boundary's piece along the line: computed once for both pieces,
// so that they meet exactly however obliquely the line crosses the side.
SHARED_FN bool coverageSideRange(vec2 a, vec2 b, float fa, float fb, SHARED_INOUT(vec2) leave,
                                 SHARED_INOUT(vec2) enter, SHARED_OUT(float) lo,
                                 SHARED_OUT(float) hi) {
    lo = 0.0f;
    hi = 1.0f;
    if (fa < 0.0f && fb < 0.0f) return false;
    if (fa < 0.0f || fb < 0.0f) {
        float l = fa / (fa - fb);
        vec2 x = a + l * (b - a);
        if (fa >= 0.0f) {
            leave = x;
            hi = l;
        } else {
            enter = x;
            lo = l;
        }
    }
    return true;
}

// The piece of R's boundary along the light square's edge a -> b: twice its area term.
SHARED_FN float coverageSquareEdge(vec2 a, vec2 b, float fa, float fb, vec3 h0, vec3 h1,
                                   SHARED_INOUT(vec2) leave, SHARED_INOUT(vec2) enter) {
    float lo;
    float hi;
    if (!coverageSideRange(a, b, fa, fb, leave, enter, lo, hi)) return 0.0f;
    return coverageSegment(a, b, lo, hi, h0, h1);
}

// The edge point at parameter l, projected from p onto the light's plane, in homogeneous light
// coordinates (s, t, w) (w = 0: at infinity). With x the edge point, z its height over p's
// height and w = 1 - z, the projection is y = x - z p - (1 - z) c, computed as (x - c) - z (p - c)
// when x is nearer the light's plane (z < 1/2) and as (x - p) + w (p - c) when nearer p's level:
// each form adds a small multiple of p - c to a short vector, so neither cancels (k: end points
// relative to c, d: relative to p).
SHARED_FN vec3 coverageProject(float l, vec3 k0, vec3 k1, vec3 d0, vec3 d1, float z0, float z1,
                               float w0, float w1, vec3 pc, CoverageLight light) {
    float z = z0 + l * (z1 - z0);
    float w = max(0.0f, w0 + l * (w1 - w0)); // rounding must not flip a point at infinity
    vec3 y = z < 0.5f ? (k0 + l * (k1 - k0)) - z * pc : (d0 + l * (d1 - d0)) + w * pc;
    return vec3(dot(light.uStar, y), dot(light.vStar, y), w);
}

// The directed edge e0 -> e1 seen from p: the part of it strictly between p's level and the
// light's plane (the only part that can block), its ends projected onto the light's plane (q0,
// q1, homogeneous light coordinates) and p's height over the light's plane along n (hp); false
// when no part of the edge is in between (or p lies on the light's plane).
//
// exactEnds: an end of the edge kept whole is projected from its own vector rather than from an
// interpolation at l = 1, so that two edges meeting at a vertex agree bit for bit on the ray
// through it (the light-sample masks need that; coverage and parts integrate areas, where it
// does not matter, and keep the interpolated form).
// The end of the clipped edge at parameter l (its lo or hi), projected (coverageProject); with
// exactEnds an end of the edge kept whole (l = 0 or 1) from its own vector (edgeProjection).
SHARED_FN vec3 coverageProjectEnd(float l, bool exactEnds, vec3 k0, vec3 k1, vec3 d0, vec3 d1,
                                  float z0, float z1, float w0, float w1, vec3 pc,
                                  CoverageLight light) {
    if (exactEnds && l == 0.0f)
        return coverageProject(0.0f, k0, k0, d0, d0, z0, z0, w0, w0, pc, light);
    if (exactEnds && l == 1.0f)
        return coverageProject(0.0f, k1, k1, d1, d1, z1, z1, w1, w1, pc, light);
    return coverageProject(l, k0, k1, d0, d1, z0, z1, w0, w1, pc, light);
}

SHARED_FN bool edgeProjection(vec3 p, vec3 e0, vec3 e1, CoverageLight light, bool exactEnds,
                              SHARED_OUT(vec3) q0, SHARED_OUT(vec3) q1, SHARED_OUT(float) hp) {
    q0 = vec3(0.0f);
    q1 = vec3(0.0f);
    vec3 pc = p - light.c;
    vec3 k0 = e0 - light.c;
    vec3 k1 = e1 - light.c;
    vec3 d0 = e0 - p;
    vec3 d1 = e1 - p;
    hp = dot(light.n, pc);
    if (!(abs(hp) > 0.0f)) return false; // on the light's plane: nothing in between
    // Heights over p's height (z) and depths below p's level (w = 1 - z), each from its own
    // accurate difference.
    float z0 = dot(light.n, k0) / hp;
    float z1 = dot(light.n, k1) / hp;
    float w0 = -dot(light.n, d0) / hp;
    float w1 = -dot(light.n, d1) / hp;
    float lo = 0.0f;
    float hi = 1.0f;
    if (!coverageClipLe0(-z0, -z1, lo, hi)) return false;
    if (!coverageClipLe0(-w0, -w1, lo, hi)) return false;
    q0 = coverageProjectEnd(lo, exactEnds, k0, k1, d0, d1, z0, z1, w0, w1, pc, light);
    q1 = coverageProjectEnd(hi, exactEnds, k0, k1, d0, d1, z0, z1, w0, w1, pc, light);
    return true;
}

// R, the light points beyond q0 q1 from the centre between the rays to q0 and q1, as the
// half-planes dot(h, (s, t, 1)) >= 0 bounding it (h0: left of the ray to q0, h1: right of the
// ray to q1, h2: beyond q0 q1 from the centre), with sg the orientation of q0 -> q1 about the
// centre; false when the projected edge passes through the centre (or is empty): R is empty.
SHARED_FN bool edgeHalfPlanes(vec3 q0, vec3 q1, SHARED_OUT(vec3) h0, SHARED_OUT(vec3) h1,
                              SHARED_OUT(vec3) h2, SHARED_OUT(float) sg) {
    h0 = vec3(0.0f);
    h1 = vec3(0.0f);
    h2 = vec3(0.0f);
    sg = 0.0f;
    float cr = q0.x * q1.y - q0.y * q1.x;
    if (cr == 0.0f) return false;
    sg = cr > 0.0f ? 1.0f : -1.0f;
    vec3 line = cross(q0, q1); // homogeneous line through q0, q1
    h0 = vec3(-sg * q0.y, sg * q0.x, 0.0f);
    h1 = vec3(sg * q1.y, -sg * q1.x, 0.0f);
    h2 = -sg * line;
    return true;
}

// |R ∩ L| / |L| for the region R between the rays h0, h1 (a sector under pi about the centre)
// beyond the line h2 (edgeHalfPlanes' half-planes, or any such three).
SHARED_FN float coverageRegionShare(vec3 h0, vec3 h1, vec3 h2) {
    // h2 at the light's corners (s, t) = (-1, -1), (1, -1), (1, 1), (-1, 1), counter-clockwise;
    // all negative: the light is wholly on the centre's side of the line.
    float f0 = dot(h2, vec3(-1.0f, -1.0f, 1.0f));
    float f1 = dot(h2, vec3(1.0f, -1.0f, 1.0f));
    float f2 = dot(h2, vec3(1.0f, 1.0f, 1.0f));
    float f3 = dot(h2, vec3(-1.0f, 1.0f, 1.0f));
    if (f0 < 0.0f && f1 < 0.0f && f2 < 0.0f && f3 < 0.0f) return 0.0f;
    // The area of R integrated along its boundary, counter-clockwise, without building the
    // polygon (arrays with dynamic indices are slow on GPUs): the square's edges where h2 >= 0,
    // then the line from where the square's boundary leaves R to where it enters it again, each
    // between the rays. The boundary's pieces along the rays contribute nothing: they point at
    // the origin.
    vec2 leave = vec2(0.0f, 0.0f);
    vec2 enter = vec2(0.0f, 0.0f);
    float area2 = 0.0f;
    area2 += coverageSquareEdge(vec2(-1.0f, -1.0f), vec2(1.0f, -1.0f), f0, f1, h0, h1, leave,
                                enter);
    area2 += coverageSquareEdge(vec2(1.0f, -1.0f), vec2(1.0f, 1.0f), f1, f2, h0, h1, leave, enter);
    area2 += coverageSquareEdge(vec2(1.0f, 1.0f), vec2(-1.0f, 1.0f), f2, f3, h0, h1, leave, enter);
    area2 += coverageSquareEdge(vec2(-1.0f, 1.0f), vec2(-1.0f, -1.0f), f3, f0, h0, h1, leave,
                                enter);
    area2 += coverageSegment(leave, enter, 0.0f, 1.0f, h0, h1);
    float fraction = 0.125f * abs(area2); // half the doubled area, over the light's 4
    return fraction;
}

SHARED_FN float edgeCoverage(vec3 p, vec3 e0, vec3 e1, CoverageLight light) {
    vec3 q0;
    vec3 q1;
    float hp;
    if (!edgeProjection(p, e0, e1, light, false, q0, q1, hp)) return 0.0f;
    vec3 h0;
    vec3 h1;
    vec3 h2;
    float sg;
    if (!edgeHalfPlanes(q0, q1, h0, h1, h2, sg)) return 0.0f;
    return (hp > 0.0f ? sg : -sg) * coverageRegionShare(h0, h1, h2);
}

SHARED_END

#endif // PENUMBRA_SHARED_COVERAGE_H
