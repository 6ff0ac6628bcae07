// wedges-bitmask silhouettes=potential evaluate=tiles, before the resolve: which pixels need the
// full resolve (bitmask-potential-resolve.frag), as 1 in a stencil of their own; the others take
// its lit variant (BITMASK_RESOLVE_LIT), a few instructions a pixel. A pixel needs the full
// resolve where a wedge added to its counts (the tiled evaluation's mark layer) or where its own
// plane may cut the light (the resolve's ownPlane, which hides the samples behind it). On a SIMD
// rasteriser (llvmpipe) every lane runs every branch of a shader, masked, so the full resolve
// cost its whole length at every pixel; a fragment the stencil test fails before the shader
// (early fragment tests) costs nothing.
#include "lib/Bindings.h"

#ifndef BITMASK_SAMPLES
#define BITMASK_SAMPLES 64
#endif

layout(binding = IMAGE_GROUP_COUNTS, r32ui) uniform readonly uimage2DArray iCounts;
layout(binding = TEXUNIT_POSITION) uniform sampler2D tPosition;
layout(binding = TEXUNIT_NORMAL) uniform sampler2D tNormal;

void main() {
    ivec2 px = ivec2(gl_FragCoord.xy);
    bool touched = imageLoad(iCounts, ivec3(px, BITMASK_SAMPLES / 8 + 2)).r != 0u;
    // ownPlane hides nothing where the light's square lies wholly in front of the plane:
    // horizonShare(nc, nu, nv) is 1 exactly where nc >= |nu| + |nv|. Here with a margin far
    // above float rounding, so that a pixel left to the lit variant has a plane the full
    // resolve would find clear of the light too (computed there by another shader).
    vec4 position = texelFetch(tPosition, px, 0);
    vec3 N = texelFetch(tNormal, px, 0).xyz;
    float nc = dot(N, frame.lightCenter.xyz - position.xyz);
    float reach = abs(dot(N, frame.lightU.xyz)) + abs(dot(N, frame.lightV.xyz));
    bool planeClear = position.w == 0.0 || nc > reach * 1.001 + 1e-30;
    if (!touched && planeClear) discard;
}
