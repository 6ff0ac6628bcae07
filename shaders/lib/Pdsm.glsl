// pdsm: one texel's visibility function read from the data buffer (four points per RGB32UI
// texel, shared/Pdsm.h). Used by pdsm-lookup.frag and by the test that holds it to the CPU model
// (tests/gpu/PdsmMethodTest.cpp).
#ifndef PENUMBRA_PDSM_GLSL
#define PENUMBRA_PDSM_GLSL

#include "shared/Pdsm.h"

layout(binding = TEXUNIT_PDSM_DATA) uniform usamplerBuffer tData;

// V at depth code t of the function of `count` points from group `first` (geometry::evaluatePdsm
// runs the same statements): the last group whose first point lies at or before t, found by
// bisection (a texel's function may hold a hundred points), then within it (shared/Pdsm.h). The
// bisection's one read serves also as the group's: its first pass reads group 0 (taken
// whatever its first point), each later one the middle of what is left. On llvmpipe a loop's
// body runs at least once for a SIMD group, so a search with nothing to bisect (one group)
// still cost a read before the group's own (data/overlap.json at 256²: 0.9 M of the lookup's
// 31 M instructions per frame).
float pdsmFunction(uint first, uint count, float t) {
    uint lo = 0u, hi = (count - 1u) >> 2u, at = 0u;
    uvec3 w = uvec3(0u);
    for (;;) {
        uvec3 m = texelFetch(tData, int(first + at)).xyz;
        if (at == 0u || pdsmPointDepth(pdsmPointBits(m.x, m.y, m.z, 0u)) <= t) {
            lo = at;
            w = m;
        } else {
            hi = at - 1u;
        }
        if (lo >= hi) break;
        at = (lo + hi + 1u) >> 1u;
    }
    uint next = lo + 1u < (count + 3u) >> 2u ? lo + 1u : lo;
    uvec3 wn = texelFetch(tData, int(first + next)).xyz;
    return pdsmGroupValue(w.x, w.y, w.z, min(count - 4u * lo, 4u), wn.x, wn.y, wn.z, next != lo,
                          t);
}

#endif
