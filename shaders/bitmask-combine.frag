// wedges-bitmask, per batch (GroupBatches.h): a group's light-sample mask into the final mask by
// the fixed-function OR (V = 1 - popcount(OR over groups) / N: overlapping groups combine
// exactly). uMode 0: where the group leaves the light centre visible, its mask as the wedges
// left it (the samples whose state differs from the centre's: occluded); 1: where it hides the
// centre, the complement; 2: the group's umbra (no wedge reached, centre hidden): every sample.
#include "lib/Bindings.h"

#ifndef BITMASK_SAMPLES
#define BITMASK_SAMPLES 64
#endif

#ifdef BITMASK_COUNTS
// combine=counts: the group's per-sample counts (wedge-bitmask.frag) and, per pixel, its centre
// count from the stencil (low 7 bits, wrapping: a signed count; bit 7: a wedge touched it). A
// sample is hidden where centre + its count is non-zero. Drawn without the stencil attached
// (it is read here), scissored to the batch; untouched pixels are left to the umbra step.
layout(binding = IMAGE_GROUP_COUNTS, r32ui) uniform readonly uimage2DArray iCounts;
layout(binding = TEXUNIT_STENCIL) uniform usampler2D tStencil;
#define COUNTS_BIAS 8
#else
layout(binding = TEXUNIT_PARTS0 + 0) uniform usampler2D tGroup0;
#if BITMASK_SAMPLES > 128
layout(binding = TEXUNIT_PARTS0 + 1) uniform usampler2D tGroup1;
#endif
#endif

layout(location = 0) uniform uint uMode;

layout(location = 0) out uvec4 oMask0;
#if BITMASK_SAMPLES > 128
layout(location = 1) out uvec4 oMask1;
#endif

#ifndef BITMASK_COUNTS
uvec4 combined(uvec4 group) {
    return uMode == 0u ? group : uMode == 1u ? ~group : uvec4(0xFFFFFFFFu);
}
#endif

#ifdef BITMASK_COUNTS
// The hidden samples 32 w ... 32 w + 31: those whose count is not 8 - centre (the bias less the
// centre's count), eight at a time.
uint hiddenWord(ivec2 px, int w, int centre) {
    int target = COUNTS_BIAS - centre;
    if (target < 0 || target > 15) return 0xFFFFFFFFu; // no count can cancel the centre's
    uint targets = uint(target) * 0x11111111u;
    uint bits = 0u;
    for (int k = 0; k < 4; ++k) {
        uint x = imageLoad(iCounts, ivec3(px, 4 * w + k)).r ^ targets; // 0 where it cancels
        x |= x >> 2u;
        x |= x >> 1u;
        x &= 0x11111111u; // bit 4 j: count j differs
        x = (x | (x >> 3u)) & 0x03030303u;
        x = (x | (x >> 6u)) & 0x000F000Fu;
        x = (x | (x >> 12u)) & 0xFFu;
        bits |= x << uint(8 * k);
    }
    return bits;
}
#endif

void main() {
    ivec2 px = ivec2(gl_FragCoord.xy);
#ifdef BITMASK_COUNTS
    if (uMode != 2u) {
        uint s = texelFetch(tStencil, px, 0).r;
        if ((s & 0x80u) == 0u) discard; // no wedge of the batch reached it
        int centre = int(s & 0x7Fu);
        if (centre >= 64) centre -= 128;
        uint w[8] = uint[8](0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u);
        for (int i = 0; i < BITMASK_SAMPLES / 32; ++i) w[i] = hiddenWord(px, i, centre);
        oMask0 = uvec4(w[0], w[1], w[2], w[3]);
#if BITMASK_SAMPLES > 128
        oMask1 = uvec4(w[4], w[5], w[6], w[7]);
#endif
        return;
    }
    // (The umbra step draws with the parity variant of this program: the stencil is attached
    // then, and must not be sampled.)
    discard;
#else
    oMask0 = combined(uMode == 2u ? uvec4(0u) : texelFetch(tGroup0, px, 0));
#if BITMASK_SAMPLES > 128
    oMask1 = combined(uMode == 2u ? uvec4(0u) : texelFetch(tGroup1, px, 0));
#endif
#endif
}
