// wedges-blend, after the last batch: V = 1 - mean over the R parts of the final state's occluded
// fractions (the parts have equal areas). Set k's vCoef target is bound at TEXUNIT_FINAL0 + k
// (8 bits: vCoef in bits 0-7 of each part's scalar; 16 bits: bits 0-15); R = 1 uses x only.
#ifndef BLEND_PARTS
#define BLEND_PARTS 4
#endif
#ifndef BLEND_BITS
#define BLEND_BITS 8
#endif

#include "lib/Bindings.h"

#if BLEND_BITS == 16
#define COEF_MASK 65535u
#define COEF_MAX 65535.0
#else
#define COEF_MASK 255u
#define COEF_MAX 255.0
#endif

layout(binding = TEXUNIT_FINAL0 + 0) uniform usampler2D tFinalCoef0;
#if BLEND_PARTS == 8
layout(binding = TEXUNIT_FINAL0 + 1) uniform usampler2D tFinalCoef1;
#endif

layout(location = 0) out float oVisibility;

void main() {
    ivec2 px = ivec2(gl_FragCoord.xy);
    uvec4 coef = texelFetch(tFinalCoef0, px, 0) & COEF_MASK;
#if BLEND_PARTS == 1
    uint sum = coef.x;
#else
    uint sum = coef.x + coef.y + coef.z + coef.w;
#endif
#if BLEND_PARTS == 8
    uvec4 more = texelFetch(tFinalCoef1, px, 0) & COEF_MASK;
    sum += more.x + more.y + more.z + more.w;
#endif
    oVisibility = 1.0 - float(sum) / (float(BLEND_PARTS) * COEF_MAX);
}
