// sample-maps early_out=on: the max N-buffer of map k (the sample nearest the light's centre).
// Level l at texel i holds the largest stored zNear / z over the window [i, i + 2^l)^2 of the
// map (0 beyond its edge: nothing there), so that the lookup bounds the nearest caster over any
// rectangle of the map with four reads (sample-maps-lookup.frag, EARLY_OUT). Level 0 is the
// map itself; level l is built from l - 1 with four reads.
#include "lib/Bindings.h"

layout(local_size_x = 8, local_size_y = 8) in;

layout(binding = TEXUNIT_SAMPLE_MAPS) uniform sampler2DArray tMaps;
layout(binding = IMAGE_SAMPLE_MAP_NBUFFER, r32f) uniform image2DArray iLevels;
layout(location = UNIFORM_PREFILTER_STEP) uniform int uLevel; // the level built

float read(ivec2 p, int level, int size) {
    if (p.x >= size || p.y >= size) return 0.0;
    return imageLoad(iLevels, ivec3(p, level)).r;
}

void main() {
    int size = imageSize(iLevels).x;
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    if (p.x >= size || p.y >= size) return;
    if (uLevel == 0) {
        int k = int(sampleMaps.emptyTest.x);
        imageStore(iLevels, ivec3(p, 0), vec4(texelFetch(tMaps, ivec3(p, k), 0).r));
        return;
    }
    int h = 1 << (uLevel - 1);
    float m = max(max(read(p, uLevel - 1, size), read(p + ivec2(h, 0), uLevel - 1, size)),
                  max(read(p + ivec2(0, h), uLevel - 1, size),
                      read(p + ivec2(h, h), uLevel - 1, size)));
    imageStore(iLevels, ivec3(p, uLevel), vec4(m));
}
