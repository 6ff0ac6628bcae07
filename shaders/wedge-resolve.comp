// Resolve of additive wedges: V = clamp(V_hard - sum of coverage, 0, 1). Where the sum leaves
// [0, 1] by more than float noise, penumbrae of different silhouettes overlapped (additive
// combination double-counts them): those pixels are counted, so the error is visible.
#include "lib/Bindings.h"

layout(local_size_x = 8, local_size_y = 8) in;

layout(binding = IMAGE_VISIBILITY, r32f) uniform image2D iVisibility;
layout(std430, binding = BINDING_WEDGE_STATS) buffer WedgeStats {
    uint wedgeStats[];
};

const float kClampNoise = 1e-3; // coverage sums carry float error of ~1e-5 per edge

void main() {
    ivec2 px = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(px, imageSize(iVisibility)))) return;
    float v = imageLoad(iVisibility, px).r;
    float c = clamp(v, 0.0, 1.0);
    if (c == v) return;
    if (v < -kClampNoise || v > 1.0 + kClampNoise) atomicAdd(wedgeStats[WEDGE_STAT_CLAMPED], 1u);
    imageStore(iVisibility, px, vec4(c));
}
