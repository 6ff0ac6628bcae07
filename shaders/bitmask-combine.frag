// wedges-bitmask, per batch (GroupBatches.h): a group's light-sample mask into the final mask by
// the fixed-function OR (V = 1 - popcount(OR over groups) / N: overlapping groups combine
// exactly). uMode 0: where the group leaves the light centre visible, its mask as the wedges
// left it (the samples whose state differs from the centre's: occluded); 1: where it hides the
// centre, the complement; 2: the group's umbra (no wedge reached, centre hidden): every sample.
#include "lib/Bindings.h"

#ifndef BITMASK_SAMPLES
#define BITMASK_SAMPLES 64
#endif

layout(binding = TEXUNIT_PARTS0 + 0) uniform usampler2D tGroup0;
#if BITMASK_SAMPLES > 128
layout(binding = TEXUNIT_PARTS0 + 1) uniform usampler2D tGroup1;
#endif

layout(location = 0) uniform uint uMode;

layout(location = 0) out uvec4 oMask0;
#if BITMASK_SAMPLES > 128
layout(location = 1) out uvec4 oMask1;
#endif

uvec4 combined(uvec4 group) {
    return uMode == 0u ? group : uMode == 1u ? ~group : uvec4(0xFFFFFFFFu);
}

void main() {
    ivec2 px = ivec2(gl_FragCoord.xy);
    oMask0 = combined(uMode == 2u ? uvec4(0u) : texelFetch(tGroup0, px, 0));
#if BITMASK_SAMPLES > 128
    oMask1 = combined(uMode == 2u ? uvec4(0u) : texelFetch(tGroup1, px, 0));
#endif
}
