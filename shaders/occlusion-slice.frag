// Occlusion textures, slicing pass: marks the fragment's slab (and, with the leak fix, the next
// one) as occupied. Slice k is channel k % 4 of target k / 4; MAX blending ORs the marks.
#include "lib/Bindings.h"
#include "lib/Material.glsl"
#include "lib/Occlusion.glsl"

in vec3 vWorld;
in vec2 vTexcoord;
flat in vec3 vNormal; // the triangle's

// 0: off; 1: where the surface comes within sliceDepth * tan(tilt) of the next slab (the band
// a light ray crossing the surface near that plane can slip through, for rays within 45° of
// the slicing rays); 2: always (the paper's rule: flat sheets then count twice).
layout(location = UNIFORM_SLICE_LEAKFIX) uniform int uLeakFix;

#define TARGETS ((SLICES + 3) / 4)
layout(location = 0) out vec4 oSlices0;
#if TARGETS > 1
layout(location = 1) out vec4 oSlices1;
#endif
#if TARGETS > 2
layout(location = 2) out vec4 oSlices2;
#endif
#if TARGETS > 3
layout(location = 3) out vec4 oSlices3;
#endif

void main() {
#ifdef ALPHA_TEST
    if (materialCutOut(materialTexel(vTexcoord))) discard; // no leaf here: casts nothing
#endif
    // Behind the light's plane (or in it) a surface hides no receiver from the light (a
    // segment from a receiver in front of the plane to the light never crosses it), yet the
    // projection from the centre of projection, copDistance behind the light, still rasterises
    // what lies between the two planes: the ceiling over a lamp hung in a room. Clamped into
    // the first slab it would cover every receiver the frustum holds.
    const float z = occlusionDepth(vWorld);
    if (!(z > 0.0)) discard;
    // The casters' depth range in front of the light was fitted on the CPU
    // (geometry::fitOcclusionFrame, clipped to z >= 0): clamping only catches rounding.
    const float u = (z - occlusion.range.x) / occlusion.range.y;
    const int k = clamp(int(floor(u)), 0, SLICES - 1);
    vec4 marks[4] = vec4[4](vec4(0.0), vec4(0.0), vec4(0.0), vec4(0.0));
    marks[k >> 2][k & 3] = 1.0;
    // Leak fix (paper Fig. 6): a sheet crossing into the next slab is looked up there half a
    // slab deeper and here half a slab higher; rays slip through between. Marking the next slab
    // as well closes the gap.
    bool next = uLeakFix == 2;
    if (uLeakFix == 1) {
        float c = abs(dot(vNormal, occlusion.axis.xyz)); // cos(tilt) of the sheet to the slabs
        float s = sqrt(max(1.0 - c * c, 0.0));
        next = (float(k + 1) - u) * c <= s; // (z_k+1 - z) / sliceDepth <= tan(tilt)
    }
    if (next && k + 1 < SLICES) marks[(k + 1) >> 2][(k + 1) & 3] = 1.0;
    oSlices0 = marks[0];
#if TARGETS > 1
    oSlices1 = marks[1];
#endif
#if TARGETS > 2
    oSlices2 = marks[2];
#endif
#if TARGETS > 3
    oSlices3 = marks[3];
#endif
}
