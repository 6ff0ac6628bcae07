// wedges-bitmask, after the last batch: V = 1 - (occluded samples) / N from the final mask (the
// OR of the groups' masks). Formats: R32UI (32 samples), RG32UI (64), RGBA32UI (128), two
// RGBA32UI (256); only the components the format has are read.
#include "lib/Bindings.h"

#ifndef BITMASK_SAMPLES
#define BITMASK_SAMPLES 64
#endif

layout(binding = TEXUNIT_FINAL0 + 0) uniform usampler2D tFinal0;
#if BITMASK_SAMPLES > 128
layout(binding = TEXUNIT_FINAL0 + 1) uniform usampler2D tFinal1;
#endif

layout(location = 0) out float oVisibility;

void main() {
    ivec2 px = ivec2(gl_FragCoord.xy);
    uvec4 m = texelFetch(tFinal0, px, 0);
    int occluded = bitCount(m.x);
#if BITMASK_SAMPLES > 32
    occluded += bitCount(m.y);
#endif
#if BITMASK_SAMPLES > 64
    occluded += bitCount(m.z) + bitCount(m.w);
#endif
#if BITMASK_SAMPLES > 128
    uvec4 n = texelFetch(tFinal1, px, 0);
    occluded += bitCount(n.x) + bitCount(n.y) + bitCount(n.z) + bitCount(n.w);
#endif
    oVisibility = 1.0 - float(occluded) / float(BITMASK_SAMPLES);
}
