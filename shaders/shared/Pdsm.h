// pdsm (penumbra deep shadow maps, St-Amour, Paquette & Poulin 2005): how one texel's
// visibility function is stored and read, GLSL and C++ alike (Prelude.h): the lookup
// (shaders/pdsm-lookup.frag) and the CPU model (geometry/shadow/PenumbraDeepShadowMap.h) run
// these very statements.
//
// A texel of the deep map is a ray from the light's centre. Along it, depth is the code
// t in [0, 1] of s = zNear / z (the sample maps' reversed depth): s = 1 - t (1 - sFar), t = 0
// at the casters' nearest depth, t = 1 at the deepest receiver's. The texel's function V(t)
// is piecewise linear through its points (t_k, v_k), t non-decreasing: V(t) = v_0 before t_0,
// the last point's v after the last point, and between two points with t_k <= t < t_{k+1} the
// straight line between them; two points at the same t are a step (the later one holds from
// there on). A point is 24 bits, as the slides pack them: t in 16 bits (PDSM_DEPTH_CODES
// steps), v in 8 (PDSM_VALUE_CODES steps). Four points fill three 32-bit words (one RGB32UI
// texel of the data buffer), point j of a group at bits 24 j to 24 j + 23 of the 96.
#ifndef PENUMBRA_SHARED_PDSM_H
#define PENUMBRA_SHARED_PDSM_H

#include "Prelude.h"

#define PDSM_DEPTH_CODES 65535.0f
#define PDSM_VALUE_CODES 255.0f

SHARED_BEGIN

// Point j (0..3) of a group of four, as 24 bits: the depth code in the low 16, the value's in
// the high 8.
SHARED_FN uint pdsmPointBits(uint w0, uint w1, uint w2, uint j) {
    uint bits = j == 0u ? (w0 & 0xFFFFFFu)
                : j == 1u ? ((w0 >> 24u) | ((w1 & 0xFFFFu) << 8u))
                : j == 2u ? ((w1 >> 16u) | ((w2 & 0xFFu) << 16u))
                          : (w2 >> 8u);
    return bits;
}

SHARED_FN float pdsmPointDepth(uint bits) {
    return float(bits & 0xFFFFu) / PDSM_DEPTH_CODES;
}

SHARED_FN float pdsmPointValue(uint bits) {
    return float(bits >> 16u) / PDSM_VALUE_CODES;
}

// V at t on the segment from point (ta, va) to point (tb, vb), ta <= t < tb.
SHARED_FN float pdsmSegment(float ta, float va, float tb, float vb, float t) {
    return va + (vb - va) * clamp((t - ta) / max(tb - ta, 1e-9f), 0.0f, 1.0f);
}

// V at t from the group of four points (w0, w1, w2), `count` (1..4) of them valid, whose first
// point is the texel's first or lies at or before t, and the next group (n0, n1, n2) if `more`:
// the last point at or before t and the segment to the one after it (the first if t lies before
// every point).
SHARED_FN float pdsmGroupValue(uint w0, uint w1, uint w2, uint count, uint n0, uint n1, uint n2,
                               bool more, float t) {
    uint a = pdsmPointBits(w0, w1, w2, 0u);
    uint b = a;
    bool hasNext = false;
    for (uint j = 1u; j < 4u; ++j) {
        uint p = pdsmPointBits(w0, w1, w2, j);
        bool valid = j < count;
        if (valid && !hasNext) {
            if (pdsmPointDepth(p) <= t) {
                a = p;
            } else {
                b = p;
                hasNext = true;
            }
        }
    }
    if (!hasNext && more) {
        b = pdsmPointBits(n0, n1, n2, 0u);
        hasNext = true;
    }
    if (!hasNext) return pdsmPointValue(a);
    return pdsmSegment(pdsmPointDepth(a), pdsmPointValue(a), pdsmPointDepth(b),
                       pdsmPointValue(b), t);
}

// The receiver's depth code t from its depth z along the light's normal: below 0 it lies
// nearer to the light than every caster (lit), above 1 past the deepest receiver the map was
// built for (the last value holds).
SHARED_FN float pdsmDepthCode(float z, float zNear, float sFar) {
    return (1.0f - zNear / z) / (1.0f - sFar);
}

// The receiver as the lookup reads it: P moved along its normal N (towards the side it faces,
// where the light that reaches it lies) by bias tan(a) texels of the deep map at P's depth zP
// (a: the angle between N and the direction to the light's centre c, tan(a) capped at
// PDSM_OFFSET_MAX_TAN; texelSize: a texel's side in m, so that a texel at depth z spans
// texelSize z), so that a surface the light grazes, narrower in the maps than a texel, is not
// hidden by the surface beside it in the same texel. The build keeps the depths that such a
// point may read (geometry::PdsmReadDepths, offsetTexels = bias PDSM_OFFSET_MAX_TAN).
#define PDSM_OFFSET_MAX_TAN 8.0f
SHARED_FN vec3 pdsmOffsetReceiver(vec3 P, vec3 N, vec3 c, float zP, float bias, float texelSize) {
    vec3 toCentre = c - P;
    float cosA = abs(dot(N, toCentre)) / max(length(toCentre), 1e-30f);
    float tanA = min(sqrt(max(1.0f - cosA * cosA, 0.0f)) / max(cosA, 1e-6f), PDSM_OFFSET_MAX_TAN);
    return P + (bias * tanA * texelSize * max(zP, 0.0f)) * N;
}

// The depth (along the map's axis) at which the lookup reads the function of the texel whose
// ray is c + z' (mk, 1) for a receiver at depth z on the plane dot(Nm, X - c) = planeD (Nm: the
// plane's normal in the map's axes (eu, ev, n)): where that ray meets the plane, held within
// `span` of z (a ray nearly in the plane meets it far away), never deeper than z itself, nor
// nearer than zNear (pdsm-lookup.frag says why). The build keeps each texel's function only at
// the depths this can return for a receiver within a texel of its ray
// (geometry::PdsmReadDepths).
SHARED_FN float pdsmReadDepth(vec3 Nm, float planeD, vec2 mk, float z, float span, float zNear) {
    float along = dot(Nm, vec3(mk.x, mk.y, 1.0f));
    float zk = abs(along) > 1e-12f ? planeD / along : z;
    zk = clamp(zk > 0.0f ? zk : z, z - span, z + span);
    return max(min(zk, z), zNear);
}

SHARED_END

#endif // PENUMBRA_SHARED_PDSM_H
