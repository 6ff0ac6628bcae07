// Light-sample masks of one directed silhouette edge (wedges-bitmask). The region R of
// edgeCoverage (Coverage.h) — the light points beyond the edge projected from p, seen
// from the light centre, between the rays to its ends — kept as the set of the light's N
// samples it holds rather than as an area: bit i set when sample i lies in R, i.e. when the
// segment from the centre to the sample crosses the projected edge. Over a silhouette group, the
// centre's count plus each sample's signed crossings is the sample's count (hidden where
// non-zero: combine=counts); their parity alone (combine=parity) is exact while the group's
// projection covers no sample twice.
// The CPU model is geometry/shadow/LightMask.h (double, exact polygons); the arithmetic up to the
// half-planes is edgeCoverage's (edgeProjection with exact ends: the two edges meeting at a
// vertex agree bit for bit on the ray through it, and edgeHalfPlanes). GLSL and C++ alike
// (Prelude.h). GLSL: BITMASK_SAMPLES is 32, 64, 128 or 256 (a multiple of 32).
#ifndef PENUMBRA_SHARED_LIGHTMASK_H
#define PENUMBRA_SHARED_LIGHTMASK_H

#include "Coverage.h"

#ifndef __cplusplus
#ifndef BITMASK_SAMPLES
#define BITMASK_SAMPLES 64
#endif
#define BITMASK_WORDS (BITMASK_SAMPLES / 32)
#endif

SHARED_BEGIN

// Whether the projected edge q0 -> q1 (homogeneous light coordinates, w >= 0) meets the light,
// taken a little larger (1 + 2^-12) so that a sample on its border is kept.
SHARED_FN bool edgeMeetsLight(vec3 q0, vec3 q1) {
    // q0 + l (q1 - q0), l in [0, 1], homogeneous (w >= 0), clipped to |s|, |t| <= w (1 + 2^-12).
    const float grow = 1.000244140625f;
    float lo = 0.0f;
    float hi = 1.0f;
    if (!coverageClipLe0(q0.x - grow * q0.z, q1.x - grow * q1.z, lo, hi)) return false;
    if (!coverageClipLe0(-q0.x - grow * q0.z, -q1.x - grow * q1.z, lo, hi)) return false;
    if (!coverageClipLe0(q0.y - grow * q0.z, q1.y - grow * q1.z, lo, hi)) return false;
    return coverageClipLe0(-q0.y - grow * q0.z, -q1.y - grow * q1.z, lo, hi);
}
// R as three half-planes dot(h, (s, t, 1)) >= 0 in light coordinates (h0: the side of the ray
// to the first end, h1: of the ray to the second, h2: beyond the projected edge) and the
// orientation sg of the projected edge about the centre; false when R misses the light (no
// sample can be in it): when the projected edge misses the light. (R holds the points beyond the
// edge on the rays from the centre through it; one of them in the light would put the ray's
// point on the edge there too, the light being convex around its centre. The edge's line alone
// may cross the light where the edge does not: on a curved caster, about half the edges that
// are silhouettes from P and reach the light's plane.)
SHARED_FN bool edgeRegion(vec3 p, vec3 e0, vec3 e1, CoverageLight light, SHARED_OUT(vec3) h0, SHARED_OUT(vec3) h1,
                SHARED_OUT(vec3) h2, SHARED_OUT(float) sg) {
    vec3 q0;
    vec3 q1;
    float hp;
    if (!edgeProjection(p, e0, e1, light, true, q0, q1, hp)) {
        h0 = vec3(0.0f);
        h1 = vec3(0.0f);
        h2 = vec3(0.0f);
        sg = 0.0f;
        return false;
    }
    if (!edgeHalfPlanes(q0, q1, h0, h1, h2, sg)) return false; // through the centre: R is empty
    return edgeMeetsLight(q0, q1);
}

// Whether light point y (light coordinates) is in R. A point on a ray belongs to the edge on the
// ray's counter-clockwise side (as if moved a little counter-clockwise about the centre), so
// that of two edges meeting at a vertex exactly one holds it; the edge's own line is closed.
SHARED_FN bool regionHolds(vec3 h0, vec3 h1, vec3 h2, float sg, vec2 y) {
    vec3 y1 = vec3(y, 1.0f);
    float a = dot(h0, y1);
    float b = dot(h1, y1);
    bool in0 = sg > 0.0f ? a >= 0.0f : a > 0.0f;
    bool in1 = sg > 0.0f ? b > 0.0f : b >= 0.0f;
    return in0 && in1 && dot(h2, y1) >= 0.0f;
}

// The per-pixel shift of the pattern (BITMASK_ROTATED): a Cranley-Patterson rotation by a hash
// of the pixel, the same for every group and edge of the pixel; geometry::maskPixelShift.
SHARED_FN uint maskHash(uint x) {
    x = (x ^ (x >> 15)) * 0x2c1b3c6du;
    x = (x ^ (x >> 12)) * 0x297a2d39u;
    return x ^ (x >> 15);
}
SHARED_FN vec2 maskPixelShift(ivec2 px) {
    uint h = maskHash(uint(px.x) * 0x9e3779b9u + maskHash(uint(px.y)));
    uint g = maskHash(h);
    return vec2(float(h >> 8), float(g >> 8)) * (1.0f / 8388608.0f); // [0, 2)
}
// A sample shifted by `shift` and wrapped back into [-1, 1).
SHARED_FN vec2 maskShifted(vec2 y, vec2 shift) {
    vec2 s = y + shift;
    return vec2(s.x >= 1.0f ? s.x - 2.0f : s.x, s.y >= 1.0f ? s.y - 2.0f : s.y);
}

SHARED_END

#endif // PENUMBRA_SHARED_LIGHTMASK_H
