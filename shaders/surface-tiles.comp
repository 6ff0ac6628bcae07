// World-space bounds of the visible surface per SURFACE_TILE^2 pixel tile (16 x 16 unless
// defined; the G-buffer's positions), for
// the per-silhouette methods' batching (gpu/src/methods/GroupBatches.h): a group can change a
// pixel only where the pixel's surface point lies in the group's influence region, so a tile
// whose surface box misses that region needs none of the group's passes. Two vec4 per tile
// (min, max); a tile without surface pixels gets min > max.
#include "lib/Bindings.h"
#include "lib/PotentialReceiver.glsl"

// One invocation per tile, looping over its pixels: no barriers (llvmpipe runs work groups
// with barriers slowly, and a tile is only 256 texel reads); 8 tiles of a row per work group,
// so that SIMD lanes have work.
layout(local_size_x = 8) in;

#ifndef SURFACE_TILE
#define SURFACE_TILE 16
#endif

layout(binding = TEXUNIT_POSITION) uniform sampler2D tPosition;

layout(std430, binding = BINDING_SURFACE_TILES) writeonly buffer Tiles {
    vec4 tileBounds[]; // 2 per tile
};

layout(location = 0) uniform int uTilesX;

void main() {
    ivec2 tileXY = ivec2(gl_GlobalInvocationID.xy);
    if (tileXY.x >= uTilesX) return;
    ivec2 size = textureSize(tPosition, 0);
    ivec2 origin = tileXY * SURFACE_TILE;
    ivec2 end = min(origin + SURFACE_TILE, size);
    vec3 lo = vec3(3.0e38), hi = vec3(-3.0e38);
    for (int y = origin.y; y < end.y; ++y)
        for (int x = origin.x; x < end.x; ++x) {
            vec4 p = texelFetch(tPosition, ivec2(x, y), 0);
            if (p.w != 0.0) {
                lo = min(lo, p.xyz);
                hi = max(hi, p.xyz);
            }
        }
    // wedges-bitmask's potential edges may take a receiver RECEIVER_NUDGE of its distance to the
    // eye towards it (lib/PotentialReceiver.glsl): the bounds hold it there too, grown by that
    // share of the box's farthest corner's distance (a tile without a surface keeps its empty
    // box).
    vec3 eye = frame.eye.xyz;
    float grow = hi.x >= lo.x ? RECEIVER_NUDGE * length(max(abs(eye - lo), abs(eye - hi))) : 0.0;
    lo -= vec3(grow);
    hi += vec3(grow);
    uint tile = uint(tileXY.y * uTilesX + tileXY.x);
    tileBounds[2u * tile] = vec4(lo, 0.0);
    tileBounds[2u * tile + 1u] = vec4(hi, 0.0);
}
