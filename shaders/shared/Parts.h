// Per radial part of the light (R = 4: quadrants) the quantities one wedge fragment adds for one
// directed silhouette edge (DESIGN.md §4 "Per-silhouette blending"; the double CPU model is
// geometry/models/BlendModel.h, whose top comment explains them): the signed fraction of each quadrant
// in R_e (partCoverage), the bounds of the projected edge clipped to each quadrant
// (partEdgeBounds) and which of each quadrant's corners lie in R_e (cornerWinding). Pure
// functions, no bindings, GLSL and C++ alike (Prelude.h); the prologue (projection, half-planes)
// is Coverage.h's.
//
// Quadrant q = 0..3 is the model's radialPart(4, q): signs (σx, σy) = (+,+), (-,+), (-,-), (+,-),
// part coordinates x = σx s, y = σy t in [0, 1]^2, the light centre at the corner (0, 0).
// Corners k = 1, 2, 3 of a part are (1, 0), (1, 1), (0, 1) (corner 0, the centre, is never in
// R_e).
//
// edgeParts4 is the paper's configuration (R = 4). edgePartSet serves every R (1, 4, 8) and adds
// the first moments (for the centroid), for one *set* of at most four parts at a time (R = 8:
// parts 4 set .. 4 set + 3, radialPart(8, i): quadrant i / 2, the half |s| >= |t| for even i,
// mirrored to the triangle 0 <= y <= x <= 1; R = 1: the whole light, x = (s + 1) / 2,
// y = (t + 1) / 2). Area and moments are integrated along the boundary of R_e ∩ part with the
// light centre as origin (the pieces along R_e's rays, through the centre, add nothing), in the
// light's coordinates for R = 1 (whose part has the centre inside, not at a corner). Its corner
// windings come as one mixed-radix number per part, Σ_j 16^j w_j over the corners that are not
// the centre (R = 1: corners 0..3; R = 4: 1..3; R = 8: 1, 2), each w_j in {-1, 0, 1}: exact in
// float, and so are sums of them while every corner's sum stays in [-8, 7].

#ifndef PENUMBRA_SHARED_PARTS_H
#define PENUMBRA_SHARED_PARTS_H

#include "Coverage.h"

SHARED_BEGIN

struct EdgeParts4 {
    vec4 coverage;    // per quadrant: signed |R_e ∩ part| / |part| (Σ / 4 = edgeCoverage)
    vec4 bounds[4];   // per quadrant: (min x, min y, max x, max y), empty = (1, 1, 0, 0)
    vec3 windings[4]; // per quadrant: corners 1, 2, 3: the edge's sign when in R_e, else 0
};

struct EdgePartSet {
    vec4 coverage;  // per part of the set: signed |R_e ∩ part| / |part|
    vec4 momentX;   // per part: signed ∫ x dA over R_e ∩ part, over |part| (part coordinates)
    vec4 momentY;   // the same for y
    vec4 bounds[4]; // per part: (min x, min y, max x, max y), empty = (1, 1, 0, 0)
    vec4 windings;  // per part: Σ_j 16^j w_j over its corners j that are not the centre
};

// The quadrant (numbered as above) that holds the light point (s, t); a point on an axis goes to
// the side of its non-negative coordinate.
SHARED_FN int partsQuadrantOf(vec2 y) {
    return y.x >= 0.0f ? (y.y >= 0.0f ? 0 : 3) : (y.y >= 0.0f ? 1 : 2);
}

// The signs (sx, sy) of quadrant q's coordinates, as numbered above.
SHARED_FN vec2 partsQuadrantSigns(int q) {
    return vec2(q == 0 || q == 3 ? 1.0f : -1.0f, q < 2 ? 1.0f : -1.0f);
}

// A light-coordinate half-plane dot(h, (s, t, 1)) >= 0 in the part coordinates of the quadrant
// with signs sg: the sign flips are exact.
SHARED_FN vec3 partsHalf(vec3 h, vec2 sg) {
    return vec3(h.x * sg.x, h.y * sg.y, h.z);
}

// A side of the quadrant on an axis of the light (through the centre) adds no area to the
// boundary integral (its points are collinear with the origin); only where the line q0 q1
// crosses it matters: the start (leave) or end (enter) of the line's piece, as in
// coverageSquareEdge.
SHARED_FN void partsAxisSide(vec2 a, vec2 b, float fa, float fb, SHARED_INOUT(vec2) leave, SHARED_INOUT(vec2) enter) {
    if (fa < 0.0f && fb < 0.0f) return;
    if (fa >= 0.0f && fb >= 0.0f) return;
    float l = fa / (fa - fb);
    vec2 x = a + l * (b - a);
    if (fa >= 0.0f)
        leave = x;
    else
        enter = x;
}

// |R_e ∩ [0, 1]^2| with R_e's half-planes h0, h1 (rays from the centre) and h2 (beyond the line)
// in part coordinates: Green along the part's boundary counter-clockwise, as edgeCoverage does
// along the light's; the two sides on the axes only place the line's piece.
SHARED_FN float partsQuadrantArea(vec3 h0, vec3 h1, vec3 h2) {
    float f0 = h2.z; // at the centre (0, 0)
    float f1 = dot(h2, vec3(1.0f, 0.0f, 1.0f));
    float f2 = dot(h2, vec3(1.0f, 1.0f, 1.0f));
    float f3 = dot(h2, vec3(0.0f, 1.0f, 1.0f));
    if (f0 < 0.0f && f1 < 0.0f && f2 < 0.0f && f3 < 0.0f) return 0.0f;
    vec2 leave = vec2(0.0f, 0.0f);
    vec2 enter = vec2(0.0f, 0.0f);
    float area2 = 0.0f;
    partsAxisSide(vec2(0.0f, 0.0f), vec2(1.0f, 0.0f), f0, f1, leave, enter);
    area2 += coverageSquareEdge(vec2(1.0f, 0.0f), vec2(1.0f, 1.0f), f1, f2, h0, h1, leave, enter);
    area2 += coverageSquareEdge(vec2(1.0f, 1.0f), vec2(0.0f, 1.0f), f2, f3, h0, h1, leave, enter);
    partsAxisSide(vec2(0.0f, 1.0f), vec2(0.0f, 0.0f), f3, f0, leave, enter);
    area2 += coverageSegment(leave, enter, 0.0f, 1.0f, h0, h1);
    return 0.5f * abs(area2);
}

// Bounds of the finite end points of a + l (b - a), l in [lo, hi] (homogeneous, w >= 0);
// (1, 1, 0, 0) when neither is finite.
SHARED_FN vec4 partsSegmentBounds(vec3 a, vec3 b, float lo, float hi) {
    vec4 r = vec4(1.0f, 1.0f, 0.0f, 0.0f);
    vec3 x0 = a + lo * (b - a);
    vec3 x1 = a + hi * (b - a);
    if (x0.z > 0.0f) {
        vec2 y0 = vec2(x0.x / x0.z, x0.y / x0.z);
        r = vec4(y0, y0);
    }
    if (x1.z > 0.0f) {
        vec2 y1 = vec2(x1.x / x1.z, x1.y / x1.z);
        r = r.x > r.z ? vec4(y1, y1) : vec4(min(r.x, y1.x), min(r.y, y1.y), max(r.z, y1.x),
                                           max(r.w, y1.y));
    }
    return r;
}

// The segment a -> b (part homogeneous coordinates, w >= 0) clipped to the part [0, 1]^2 (the
// half-planes x >= 0, y >= 0, w - x >= 0, w - y >= 0, closed), bounds of its finite end points;
// (1, 1, 0, 0) when it misses.
SHARED_FN vec4 partsEdgeBounds(vec3 a, vec3 b) {
    vec4 r = vec4(1.0f, 1.0f, 0.0f, 0.0f);
    float lo = 0.0f;
    float hi = 1.0f;
    if (!coverageClipLe0(-a.x, -b.x, lo, hi)) return r;
    if (!coverageClipLe0(-a.y, -b.y, lo, hi)) return r;
    if (!coverageClipLe0(a.x - a.z, b.x - b.z, lo, hi)) return r;
    if (!coverageClipLe0(a.y - a.z, b.y - b.z, lo, hi)) return r;
    return partsSegmentBounds(a, b, lo, hi);
}

// The same for the triangle part 0 <= y <= x <= 1 (y >= 0, x - y >= 0, w - x >= 0).
SHARED_FN vec4 partsTriangleBounds(vec3 a, vec3 b) {
    vec4 r = vec4(1.0f, 1.0f, 0.0f, 0.0f);
    float lo = 0.0f;
    float hi = 1.0f;
    if (!coverageClipLe0(-a.y, -b.y, lo, hi)) return r;
    if (!coverageClipLe0(a.y - a.x, b.y - b.x, lo, hi)) return r;
    if (!coverageClipLe0(a.x - a.z, b.x - b.z, lo, hi)) return r;
    return partsSegmentBounds(a, b, lo, hi);
}

// Whether the corner c moved by ε d1 + ε² d2 (into the part) lies in dot(h, (x, y, 1)) >= 0:
// the model's tie rule, so that two edges sharing a projected vertex never both count a corner
// on their common ray, nor neither.
SHARED_FN bool partsInside(vec3 h, vec2 c, vec2 d1, vec2 d2) {
    float f = dot(h, vec3(c, 1.0f));
    if (f != 0.0f) return f > 0.0f;
    float g1 = h.x * d1.x + h.y * d1.y;
    if (g1 != 0.0f) return g1 > 0.0f;
    return h.x * d2.x + h.y * d2.y > 0.0f;
}

// edgeSign when the corner c (moved as partsInside says) lies in R_e, else 0.f
SHARED_FN float partsCornerWinding(vec3 h0, vec3 h1, vec3 h2, vec2 c, vec2 d1, vec2 d2, float edgeSign) {
    if (!partsInside(h0, c, d1, d2)) return 0.0f;
    if (!partsInside(h1, c, d1, d2)) return 0.0f;
    if (!partsInside(h2, c, d1, d2)) return 0.0f;
    return edgeSign;
}

// All four quadrants for the directed edge e0 -> e1 seen from p; the projection and the
// half-planes are edgeCoverage's (edgeProjection, edgeHalfPlanes).
SHARED_FN EdgeParts4 edgeParts4(vec3 p, vec3 e0, vec3 e1, CoverageLight light) {
    EdgeParts4 parts;
    parts.coverage = vec4(0.0f, 0.0f, 0.0f, 0.0f);
    for (int q = 0; q < 4; ++q) {
        parts.bounds[q] = vec4(1.0f, 1.0f, 0.0f, 0.0f);
        parts.windings[q] = vec3(0.0f, 0.0f, 0.0f);
    }
    vec3 q0;
    vec3 q1;
    float hp;
    if (!edgeProjection(p, e0, e1, light, false, q0, q1, hp)) return parts;
    // The bounds need only the segment; the rest needs R_e to have area.
    for (int q = 0; q < 4; ++q) {
        vec2 sq = partsQuadrantSigns(q);
        parts.bounds[q] = partsEdgeBounds(partsHalf(q0, sq), partsHalf(q1, sq));
    }
    vec3 h0;
    vec3 h1;
    vec3 h2;
    float sg;
    if (!edgeHalfPlanes(q0, q1, h0, h1, h2, sg)) return parts;
    float edgeSign = hp > 0.0f ? sg : -sg;
    for (int q = 0; q < 4; ++q) {
        vec2 sq = partsQuadrantSigns(q);
        vec3 g0 = partsHalf(h0, sq);
        vec3 g1 = partsHalf(h1, sq);
        vec3 g2 = partsHalf(h2, sq);
        parts.coverage[q] = edgeSign * partsQuadrantArea(g0, g1, g2);
        // Corners (1, 0), (1, 1), (0, 1); d1 towards the part's centroid, d2 along the side to
        // the next corner counter-clockwise (the model's cornerWinding).
        parts.windings[q] =
            vec3(partsCornerWinding(g0, g1, g2, vec2(1.0f, 0.0f), vec2(-0.5f, 0.5f), vec2(0.0f, 1.0f),
                                    edgeSign),
                 partsCornerWinding(g0, g1, g2, vec2(1.0f, 1.0f), vec2(-0.5f, -0.5f), vec2(-1.0f, 0.0f),
                                    edgeSign),
                 partsCornerWinding(g0, g1, g2, vec2(0.0f, 1.0f), vec2(0.5f, -0.5f), vec2(0.0f, -1.0f),
                                    edgeSign));
    }
    return parts;
}

// edgeParts4's coverage alone, unsigned: per quadrant the share of the quadrant in R_e, given
// R's half-planes (shared/LightMask.h edgeRegion, as wedges-bitmask's potential wedges take it
// for their light-sample masks). They add it times m_P(e): per quadrant the exact integral of D
// over the quadrant (estimate=quadrants and moments, bitmask-potential-resolve.frag). The
// shares in one walk along R ∩ L's boundary rather than one per quadrant (4 times the work):
// Green's sum with the centre as origin splits by quadrant at the axes, whose pieces of each
// quadrant's boundary, like R's rays, pass through the origin and add nothing.
// Each side of the light square lies half in one quadrant, half in the next; the piece along
// the line (which misses the centre) crosses each axis at most once. Measured against
// edgeParts4's per-quadrant walks and the double model in PartsTest.

// e_q: 1 in quadrant q's component (no dynamic index into a vector).
SHARED_FN vec4 partsOneHot(int q) {
    return vec4(q == 0 ? 1.0f : 0.0f, q == 1 ? 1.0f : 0.0f, q == 2 ? 1.0f : 0.0f,
                q == 3 ? 1.0f : 0.0f);
}

// Twice the area term of the piece a + l (b - a), l in [lo, hi], per quadrant: qa's before l =
// split, qb's after.
SHARED_FN vec4 partsSplitCross(vec2 a, vec2 b, float lo, float hi, float split, int qa, int qb) {
    vec2 x0 = a + lo * (b - a);
    vec2 x1 = a + hi * (b - a);
    if (hi <= split) return coverageCross2(x0, x1) * partsOneHot(qa);
    if (lo >= split) return coverageCross2(x0, x1) * partsOneHot(qb);
    vec2 xs = a + split * (b - a);
    return coverageCross2(x0, xs) * partsOneHot(qa) + coverageCross2(xs, x1) * partsOneHot(qb);
}

// The light square's side a -> b (quadrant qa's half first, then qb's) as coverageSquareEdge
// takes it, per quadrant.
SHARED_FN vec4 partsSquareEdgeQuadrants(vec2 a, vec2 b, float fa, float fb, vec3 h0, vec3 h1,
                                        SHARED_INOUT(vec2) leave, SHARED_INOUT(vec2) enter,
                                        int qa, int qb) {
    float lo;
    float hi;
    if (!coverageSideRange(a, b, fa, fb, leave, enter, lo, hi)) return vec4(0.0f);
    if (!coverageClipHalf(h0, a, b, lo, hi)) return vec4(0.0f);
    if (!coverageClipHalf(h1, a, b, lo, hi)) return vec4(0.0f);
    return partsSplitCross(a, b, lo, hi, 0.5f, qa, qb);
}

// The piece along the line, a -> b between the rays, per quadrant: cut where it crosses the
// axes (s = 0, then t = 0, or the other way round), each of its (at most three) pieces in the
// quadrant of its midpoint.
SHARED_FN vec4 partsLineQuadrants(vec2 a, vec2 b, vec3 h0, vec3 h1) {
    float lo = 0.0f;
    float hi = 1.0f;
    if (!coverageClipHalf(h0, a, b, lo, hi)) return vec4(0.0f);
    if (!coverageClipHalf(h1, a, b, lo, hi)) return vec4(0.0f);
    vec2 d = b - a;
    float ls = d.x != 0.0f ? -a.x / d.x : lo; // where s = 0 (none: lo)
    float lt = d.y != 0.0f ? -a.y / d.y : lo;
    float l1 = clamp(min(ls, lt), lo, hi);
    float l2 = clamp(max(ls, lt), lo, hi);
    vec2 x0 = a + lo * d;
    vec2 x1 = a + l1 * d;
    vec2 x2 = a + l2 * d;
    vec2 x3 = a + hi * d;
    return coverageCross2(x0, x1) * partsOneHot(partsQuadrantOf(0.5f * (x0 + x1))) +
           coverageCross2(x1, x2) * partsOneHot(partsQuadrantOf(0.5f * (x1 + x2))) +
           coverageCross2(x2, x3) * partsOneHot(partsQuadrantOf(0.5f * (x2 + x3)));
}

SHARED_FN vec4 regionQuadrantCoverage(vec3 h0, vec3 h1, vec3 h2) {
    // coverageRegionShare's walk (the light's corners counter-clockwise from (-1, -1), in
    // quadrants 2, 3, 0, 1), its terms kept per quadrant.
    float f0 = dot(h2, vec3(-1.0f, -1.0f, 1.0f));
    float f1 = dot(h2, vec3(1.0f, -1.0f, 1.0f));
    float f2 = dot(h2, vec3(1.0f, 1.0f, 1.0f));
    float f3 = dot(h2, vec3(-1.0f, 1.0f, 1.0f));
    if (f0 < 0.0f && f1 < 0.0f && f2 < 0.0f && f3 < 0.0f) return vec4(0.0f);
    vec2 leave = vec2(0.0f, 0.0f);
    vec2 enter = vec2(0.0f, 0.0f);
    vec4 area2 = vec4(0.0f);
    area2 += partsSquareEdgeQuadrants(vec2(-1.0f, -1.0f), vec2(1.0f, -1.0f), f0, f1, h0, h1, leave,
                                      enter, 2, 3);
    area2 += partsSquareEdgeQuadrants(vec2(1.0f, -1.0f), vec2(1.0f, 1.0f), f1, f2, h0, h1, leave,
                                      enter, 3, 0);
    area2 += partsSquareEdgeQuadrants(vec2(1.0f, 1.0f), vec2(-1.0f, 1.0f), f2, f3, h0, h1, leave,
                                      enter, 0, 1);
    area2 += partsSquareEdgeQuadrants(vec2(-1.0f, 1.0f), vec2(-1.0f, -1.0f), f3, f0, h0, h1, leave,
                                      enter, 1, 2);
    area2 += partsLineQuadrants(leave, enter, h0, h1);
    // A quadrant's area is 1 in light coordinates: its share is the area, half the doubled sum.
    return 0.5f * abs(area2);
}

// --- Every R, with moments (edgePartSet) ---

// Twice the area and six times the first moments, (cross(x0, x1), cross(x0, x1) (x0 + x1)), of
// the triangle (0, x0, x1) for the piece x0 -> x1 of a + l (b - a), l in [lo, hi], between the
// rays h0, h1: one term of Green's theorem with the centre as origin.
SHARED_FN vec3 partsSegment(vec2 a, vec2 b, float lo, float hi, vec3 h0, vec3 h1) {
    if (!coverageClipHalf(h0, a, b, lo, hi)) return vec3(0.0f, 0.0f, 0.0f);
    if (!coverageClipHalf(h1, a, b, lo, hi)) return vec3(0.0f, 0.0f, 0.0f);
    vec2 x0 = a + lo * (b - a);
    vec2 x1 = a + hi * (b - a);
    float c = coverageCross2(x0, x1);
    return vec3(c, c * (x0 + x1));
}

// coverageSquareEdge with the moments: the piece of R's boundary along the part's side a -> b
// (counter-clockwise; fa, fb: the line's h2 at a and b), placing the line's piece as it goes.
SHARED_FN vec3 partsSide(vec2 a, vec2 b, float fa, float fb, vec3 h0, vec3 h1,
                         SHARED_INOUT(vec2) leave, SHARED_INOUT(vec2) enter) {
    float lo;
    float hi;
    if (!coverageSideRange(a, b, fa, fb, leave, enter, lo, hi)) return vec3(0.0f, 0.0f, 0.0f);
    return partsSegment(a, b, lo, hi, h0, h1);
}

// (2 area, 6 ∫x, 6 ∫y) of R_e ∩ [0, 1]^2, the centre at (0, 0): partsQuadrantArea's walk.
SHARED_FN vec3 partsSquareMoments(vec3 h0, vec3 h1, vec3 h2) {
    float f0 = h2.z;
    float f1 = dot(h2, vec3(1.0f, 0.0f, 1.0f));
    float f2 = dot(h2, vec3(1.0f, 1.0f, 1.0f));
    float f3 = dot(h2, vec3(0.0f, 1.0f, 1.0f));
    if (f0 < 0.0f && f1 < 0.0f && f2 < 0.0f && f3 < 0.0f) return vec3(0.0f, 0.0f, 0.0f);
    vec2 leave = vec2(0.0f, 0.0f);
    vec2 enter = vec2(0.0f, 0.0f);
    vec3 sum = vec3(0.0f, 0.0f, 0.0f);
    partsAxisSide(vec2(0.0f, 0.0f), vec2(1.0f, 0.0f), f0, f1, leave, enter);
    sum += partsSide(vec2(1.0f, 0.0f), vec2(1.0f, 1.0f), f1, f2, h0, h1, leave, enter);
    sum += partsSide(vec2(1.0f, 1.0f), vec2(0.0f, 1.0f), f2, f3, h0, h1, leave, enter);
    partsAxisSide(vec2(0.0f, 1.0f), vec2(0.0f, 0.0f), f3, f0, leave, enter);
    sum += partsSegment(leave, enter, 0.0f, 1.0f, h0, h1);
    return sum;
}

// (2 area, 6 ∫x, 6 ∫y) of R_e ∩ the triangle 0 <= y <= x <= 1, the centre at (0, 0): its sides
// on y = 0 and on the diagonal pass through the centre and only place the line's piece.
SHARED_FN vec3 partsTriangleMoments(vec3 h0, vec3 h1, vec3 h2) {
    float f0 = h2.z;
    float f1 = dot(h2, vec3(1.0f, 0.0f, 1.0f));
    float f2 = dot(h2, vec3(1.0f, 1.0f, 1.0f));
    if (f0 < 0.0f && f1 < 0.0f && f2 < 0.0f) return vec3(0.0f, 0.0f, 0.0f);
    vec2 leave = vec2(0.0f, 0.0f);
    vec2 enter = vec2(0.0f, 0.0f);
    vec3 sum = vec3(0.0f, 0.0f, 0.0f);
    partsAxisSide(vec2(0.0f, 0.0f), vec2(1.0f, 0.0f), f0, f1, leave, enter);
    sum += partsSide(vec2(1.0f, 0.0f), vec2(1.0f, 1.0f), f1, f2, h0, h1, leave, enter);
    partsAxisSide(vec2(1.0f, 1.0f), vec2(0.0f, 0.0f), f2, f0, leave, enter);
    sum += partsSegment(leave, enter, 0.0f, 1.0f, h0, h1);
    return sum;
}

// (2 area, 6 ∫s, 6 ∫t) of R_e ∩ the light [-1, 1]^2 in light coordinates: edgeCoverage's walk.
SHARED_FN vec3 partsLightMoments(vec3 h0, vec3 h1, vec3 h2) {
    float f0 = dot(h2, vec3(-1.0f, -1.0f, 1.0f));
    float f1 = dot(h2, vec3(1.0f, -1.0f, 1.0f));
    float f2 = dot(h2, vec3(1.0f, 1.0f, 1.0f));
    float f3 = dot(h2, vec3(-1.0f, 1.0f, 1.0f));
    if (f0 < 0.0f && f1 < 0.0f && f2 < 0.0f && f3 < 0.0f) return vec3(0.0f, 0.0f, 0.0f);
    vec2 leave = vec2(0.0f, 0.0f);
    vec2 enter = vec2(0.0f, 0.0f);
    vec3 sum = vec3(0.0f, 0.0f, 0.0f);
    sum += partsSide(vec2(-1.0f, -1.0f), vec2(1.0f, -1.0f), f0, f1, h0, h1, leave, enter);
    sum += partsSide(vec2(1.0f, -1.0f), vec2(1.0f, 1.0f), f1, f2, h0, h1, leave, enter);
    sum += partsSide(vec2(1.0f, 1.0f), vec2(-1.0f, 1.0f), f2, f3, h0, h1, leave, enter);
    sum += partsSide(vec2(-1.0f, 1.0f), vec2(-1.0f, -1.0f), f3, f0, h0, h1, leave, enter);
    sum += partsSegment(leave, enter, 0.0f, 1.0f, h0, h1);
    return sum;
}

// Corner windings as one mixed-radix number; d1 towards the part's centroid, d2 along the side
// to the next corner counter-clockwise (the model's cornerWinding; directions scaled to exact
// small numbers). Square: corners (1, 0), (1, 1), (0, 1).
SHARED_FN float partsSquareWindings(vec3 g0, vec3 g1, vec3 g2, float edgeSign) {
    return partsCornerWinding(g0, g1, g2, vec2(1.0f, 0.0f), vec2(-0.5f, 0.5f), vec2(0.0f, 1.0f),
                              edgeSign) +
           16.0f * partsCornerWinding(g0, g1, g2, vec2(1.0f, 1.0f), vec2(-0.5f, -0.5f),
                                     vec2(-1.0f, 0.0f), edgeSign) +
           256.0f * partsCornerWinding(g0, g1, g2, vec2(0.0f, 1.0f), vec2(0.5f, -0.5f),
                                      vec2(0.0f, -1.0f), edgeSign);
}

// Triangle (centroid (2/3, 1/3)): corners (1, 0), (1, 1).
SHARED_FN float partsTriangleWindings(vec3 g0, vec3 g1, vec3 g2, float edgeSign) {
    return partsCornerWinding(g0, g1, g2, vec2(1.0f, 0.0f), vec2(-1.0f, 1.0f), vec2(0.0f, 1.0f),
                              edgeSign) +
           16.0f * partsCornerWinding(g0, g1, g2, vec2(1.0f, 1.0f), vec2(-1.0f, -2.0f),
                                     vec2(-1.0f, -1.0f), edgeSign);
}

// The whole light, in light coordinates: its corners (-1, -1), (1, -1), (1, 1), (-1, 1) (the
// part's (0, 0), (1, 0), (1, 1), (0, 1)).
SHARED_FN float partsLightWindings(vec3 h0, vec3 h1, vec3 h2, float edgeSign) {
    return partsCornerWinding(h0, h1, h2, vec2(-1.0f, -1.0f), vec2(1.0f, 1.0f), vec2(1.0f, 0.0f),
                              edgeSign) +
           16.0f * partsCornerWinding(h0, h1, h2, vec2(1.0f, -1.0f), vec2(-1.0f, 1.0f),
                                     vec2(0.0f, 1.0f), edgeSign) +
           256.0f * partsCornerWinding(h0, h1, h2, vec2(1.0f, 1.0f), vec2(-1.0f, -1.0f),
                                      vec2(-1.0f, 0.0f), edgeSign) +
           4096.0f * partsCornerWinding(h0, h1, h2, vec2(-1.0f, 1.0f), vec2(1.0f, -1.0f),
                                       vec2(0.0f, -1.0f), edgeSign);
}

// Light homogeneous coordinates (points and half-planes alike: a signed permutation) in the part
// coordinates of part `index` of R = 4 or 8.f
SHARED_FN vec3 partsFrame(vec3 h, int parts, int index) {
    int q = parts == 8 ? index / 2 : index;
    vec2 sq = vec2(q == 0 || q == 3 ? 1.0f : -1.0f, q < 2 ? 1.0f : -1.0f);
    vec3 g = partsHalf(h, sq);
    return parts == 8 && index % 2 == 1 ? vec3(g.y, g.x, g.z) : g;
}

// A light homogeneous point in the part coordinates of R = 1: x = (s + 1) / 2, y = (t + 1) / 2.f
SHARED_FN vec3 partsWhole(vec3 q) {
    return vec3(0.5f * (q.x + q.z), 0.5f * (q.y + q.z), q.z);
}

// The parts of set `set` of R = `parts` (1, 4, 8) for the directed edge e0 -> e1 seen from p
// (parts 4 set + k, k < 4; R = 1: k = 0 only); the projection is edgeCoverage's.
SHARED_FN EdgePartSet edgePartSet(vec3 p, vec3 e0, vec3 e1, CoverageLight light, int parts, int set) {
    EdgePartSet e;
    e.coverage = vec4(0.0f, 0.0f, 0.0f, 0.0f);
    e.momentX = vec4(0.0f, 0.0f, 0.0f, 0.0f);
    e.momentY = vec4(0.0f, 0.0f, 0.0f, 0.0f);
    e.windings = vec4(0.0f, 0.0f, 0.0f, 0.0f);
    for (int k = 0; k < 4; ++k) e.bounds[k] = vec4(1.0f, 1.0f, 0.0f, 0.0f);
    vec3 q0;
    vec3 q1;
    float hp;
    if (!edgeProjection(p, e0, e1, light, false, q0, q1, hp)) return e;
    int count = parts == 1 ? 1 : 4;
    // The bounds need only the segment; the rest needs R_e to have area.
    for (int k = 0; k < count; ++k) {
        int index = 4 * set + k;
        if (parts == 1)
            e.bounds[k] = partsEdgeBounds(partsWhole(q0), partsWhole(q1));
        else if (parts == 4)
            e.bounds[k] = partsEdgeBounds(partsFrame(q0, parts, index),
                                          partsFrame(q1, parts, index));
        else
            e.bounds[k] = partsTriangleBounds(partsFrame(q0, parts, index),
                                              partsFrame(q1, parts, index));
    }
    vec3 h0;
    vec3 h1;
    vec3 h2;
    float sg;
    if (!edgeHalfPlanes(q0, q1, h0, h1, h2, sg)) return e;
    float edgeSign = hp > 0.0f ? sg : -sg;
    for (int k = 0; k < count; ++k) {
        int index = 4 * set + k;
        if (parts == 1) {
            // |part| = 1 is the light's area 4 over 4; x = (s + 1) / 2 adds half the area.
            vec3 m = partsLightMoments(h0, h1, h2);
            e.coverage[k] = edgeSign * 0.125f * abs(m.x);
            e.momentX[k] = edgeSign * 0.125f * (m.y / 6.0f + 0.5f * m.x);
            e.momentY[k] = edgeSign * 0.125f * (m.z / 6.0f + 0.5f * m.x);
            e.windings[k] = partsLightWindings(h0, h1, h2, edgeSign);
        } else {
            vec3 g0 = partsFrame(h0, parts, index);
            vec3 g1 = partsFrame(h1, parts, index);
            vec3 g2 = partsFrame(h2, parts, index);
            if (parts == 4) {
                vec3 m = partsSquareMoments(g0, g1, g2);
                e.coverage[k] = edgeSign * 0.5f * abs(m.x);
                e.momentX[k] = edgeSign * m.y / 6.0f;
                e.momentY[k] = edgeSign * m.z / 6.0f;
                e.windings[k] = partsSquareWindings(g0, g1, g2, edgeSign);
            } else {
                // |part| = 1/2.f
                vec3 m = partsTriangleMoments(g0, g1, g2);
                e.coverage[k] = edgeSign * abs(m.x);
                e.momentX[k] = edgeSign * m.y / 3.0f;
                e.momentY[k] = edgeSign * m.z / 3.0f;
                e.windings[k] = partsTriangleWindings(g0, g1, g2, edgeSign);
            }
        }
    }
    return e;
}

// --- Where two regions overlap (wedges-bitmask estimate=moments) ---

// A region R as the overlap below takes it: the sector from its start ray `from` counter-
// clockwise to its end ray `to` (under pi; directions from the centre) and its line h2 (R:
// dot(h2, (s, t, 1)) >= 0, the centre on the other side). From edgeHalfPlanes' h0, h1 and its
// orientation sg: q0 = sg (h0.y, -h0.x), q1 = sg (-h1.y, h1.x), counter-clockwise from q0 to q1
// when sg > 0.
SHARED_FN vec2 partsSectorFrom(vec3 h0, vec3 h1, float sg) {
    return sg > 0.0f ? vec2(h0.y, -h0.x) : vec2(h1.y, -h1.x);
}
SHARED_FN vec2 partsSectorTo(vec3 h0, vec3 h1, float sg) {
    return sg > 0.0f ? vec2(-h1.y, h1.x) : vec2(-h0.y, h0.x);
}

// Whether direction d lies in the sector from -> to (closed).
SHARED_FN bool partsInSector(vec2 from, vec2 to, vec2 d) {
    return coverageCross2(from, d) >= 0.0f && coverageCross2(d, to) >= 0.0f;
}

// |L ∩ (sector from -> to) beyond both lines a and b| / |L|, where neither line crosses the
// sector's interior after the other (the farther line, as seen from the centre, is the same
// across it): that line's region, by coverageRegionShare's walk.
SHARED_FN float partsSectorBeyondBoth(vec2 from, vec2 to, vec3 a, vec3 b) {
    vec2 v = normalize(from) + normalize(to); // inside the sector (under pi)
    // Along v, the line h is reached at distance -h.z / dot(h.xy, v), never where that
    // dot is <= 0; the farther one bounds what lies beyond both.
    float ga = a.x * v.x + a.y * v.y;
    float gb = b.x * v.x + b.y * v.y;
    if (!(ga > 0.0f) || !(gb > 0.0f)) return 0.0f;
    bool aFarther = -a.z * gb >= -b.z * ga;
    vec3 h0 = vec3(-from.y, from.x, 0.0f);
    vec3 h1 = vec3(to.y, -to.x, 0.0f);
    return coverageRegionShare(h0, h1, aFarther ? a : b);
}

// |L ∩ R_a ∩ R_b| / |L| for two regions (sectors and lines as above): the sectors' common
// sector (empty, or one sector: both are under pi), split where the two lines cross inside it;
// in each piece the region beyond the farther line (coverageRegionShare). No polygon is built
// (arrays with dynamic indices are slow on GPUs).
SHARED_FN float partsRegionsOverlap(vec2 fromA, vec2 toA, vec3 lineA, vec2 fromB, vec2 toB,
                                    vec3 lineB) {
    vec2 from;
    vec2 to;
    if (partsInSector(fromA, toA, fromB))
        from = fromB;
    else if (partsInSector(fromB, toB, fromA))
        from = fromA;
    else
        return 0.0f;
    if (partsInSector(fromA, toA, toB))
        to = toB;
    else if (partsInSector(fromB, toB, toA))
        to = toA;
    else
        return 0.0f;
    if (!(coverageCross2(from, to) > 0.0f)) return 0.0f; // a ray, or nothing
    // Two pieces, split where the lines cross inside the sector, else at its bisector (the
    // farther line is then the same on both sides, and the pieces add up to the whole): on a
    // SIMD machine both sides of a branch run (llvmpipe), and a third walk for the unsplit
    // sector was about a third of the overlaps' cost (data/plates-three.json: 339 -> 318 M
    // instructions per frame, 65 M of them in the overlaps before).
    vec2 split = normalize(from) + normalize(to); // inside the sector (under pi)
    vec3 x = cross(lineA, lineB); // where the lines cross (homogeneous)
    if (x.z != 0.0f) {
        vec2 c = vec2(x.x / x.z, x.y / x.z);
        if (coverageCross2(from, c) > 0.0f && coverageCross2(c, to) > 0.0f) split = c;
    }
    return partsSectorBeyondBoth(from, split, lineA, lineB) +
           partsSectorBeyondBoth(split, to, lineA, lineB);
}

SHARED_END

#endif // PENUMBRA_SHARED_PARTS_H
