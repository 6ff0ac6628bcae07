// Debug view "error": Σ |V - V_ref| and the surface pixels per 16x16 tile (the inputs of
// debug-error.frag), one vec2 per work group; the CPU adds the few of them up.
#include "lib/Bindings.h"

layout(local_size_x = 16, local_size_y = 16) in;

layout(binding = TEXUNIT_POSITION) uniform sampler2D tPosition;
layout(binding = TEXUNIT_VISIBILITY) uniform sampler2D tVisibility;
layout(binding = TEXUNIT_DEBUG0) uniform sampler2D tReference;

layout(std430, binding = BINDING_DEBUG_SUMS) writeonly buffer Sums {
    vec2 sums[];
};

layout(location = 0) uniform float uRefScale;

shared vec2 sPartial[256];

void main() {
    ivec2 px = ivec2(gl_GlobalInvocationID.xy);
    ivec2 size = textureSize(tVisibility, 0);
    vec2 mine = vec2(0.0);
    if (all(lessThan(px, size)) && texelFetch(tPosition, px, 0).w != 0.0) {
        float v = texelFetch(tVisibility, px, 0).r;
        float ref = texelFetch(tReference, px, 0).r * uRefScale;
        mine = vec2(abs(v - ref), 1.0);
    }
    uint i = gl_LocalInvocationIndex;
    sPartial[i] = mine;
    barrier();
    for (uint stride = 128u; stride > 0u; stride >>= 1u) {
        if (i < stride) sPartial[i] += sPartial[i + stride];
        barrier();
    }
    if (i == 0u) sums[gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x] = sPartial[0];
}
