// Occlusion textures, N-buffers (Décoret 2005; Eisemann & Décoret 2006 §3.2): level l at texel
// i holds the mean of the slices over the window [i, i + 2^l)², built from level l - 1 with four
// reads. Outside the texture counts as empty (nothing outside the frustum was sliced).
// Layer l * TARGETS + t holds level l of target t; level 0 is what the slicing pass drew.
#include "lib/Bindings.h"

layout(local_size_x = 8, local_size_y = 8) in;

layout(binding = IMAGE_OCCLUSION_DST, rgba16) uniform image2DArray iLevels;
layout(location = UNIFORM_PREFILTER_STEP) uniform int uLevel; // the level built, >= 1

#define TARGETS ((SLICES + 3) / 4)

vec4 read(ivec2 p, int layer, int size) {
    if (p.x >= size || p.y >= size) return vec4(0.0);
    return imageLoad(iLevels, ivec3(p, layer));
}

void main() {
    int size = imageSize(iLevels).x;
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    if (p.x >= size || p.y >= size) return;
    int h = 1 << (uLevel - 1);
    for (int t = 0; t < TARGETS; ++t) {
        int src = (uLevel - 1) * TARGETS + t;
        vec4 sum = read(p, src, size) + read(p + ivec2(h, 0), src, size) +
                   read(p + ivec2(0, h), src, size) + read(p + ivec2(h, h), src, size);
        imageStore(iLevels, ivec3(p, uLevel * TARGETS + t), 0.25 * sum);
    }
}
