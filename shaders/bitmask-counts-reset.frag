// wedges-bitmask combine=counts (GroupBatches.h, step 4): a batch's per-sample counts back to
// their bias (8 in every 4-bit count) where its wedges touched; the stencil test selects those
// pixels (before the shader runs) and zeroes their stencil.
#include "lib/Bindings.h"

#ifndef BITMASK_SAMPLES
#define BITMASK_SAMPLES 64
#endif

layout(early_fragment_tests) in;

layout(binding = IMAGE_GROUP_COUNTS, r32ui) uniform writeonly uimage2DArray iCounts;

void main() {
    ivec2 px = ivec2(gl_FragCoord.xy);
    for (int layer = 0; layer < BITMASK_SAMPLES / 8; ++layer)
        imageStore(iCounts, ivec3(px, layer), uvec4(0x88888888u));
}
