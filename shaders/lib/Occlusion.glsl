// Occlusion textures (Eisemann & Décoret 2006): the frame of the slices, the float twin of
// geometry/shadow/OcclusionSlices.h (depth, lateral, the lookup of slice k).
#ifndef PENUMBRA_OCCLUSION_GLSL
#define PENUMBRA_OCCLUSION_GLSL

#include "Horizon.glsl" // horizonFraction, which the lookup multiplies V by (horizon=on)

// Relative margin of occlusionCovers (geometry::kOcclusionCoverMargin): the vertex that fits the
// frustum lies on its side plane, up to rounding.
#define OCCLUSION_COVER_MARGIN 1e-4

// Depth of q below the light's plane, along the sliced side's axis.
float occlusionDepth(vec3 q) {
    return dot(q - frame.lightCenter.xyz, occlusion.axis.xyz);
}

// (s, t) of q in the light's half-axes (the light is [-1, 1]^2).
vec2 occlusionLateral(vec3 q) {
    vec3 d = q - frame.lightCenter.xyz;
    return vec2(dot(d, frame.lightUStar.xyz), dot(d, frame.lightVStar.xyz));
}

// q lies in the slicing frustum, in front of the light (geometry::OcclusionFrame::covers, with
// the same relative margin): its lookup reads sliced texels only.
bool occlusionCovers(vec3 q) {
    float z = occlusionDepth(q);
    if (!(z > 0.0)) return false;
    vec2 st = abs(occlusionLateral(q));
    return max(st.x, st.y) <= (1.0 + z / occlusion.axis.w) * (1.0 + OCCLUSION_COVER_MARGIN);
}

// Slice k's share in V(P) (geometry::sliceLookup): the weight (0: not looked up; the slice
// containing P is never looked up, the one before it fades in with P's place in its own), and
// the kernel — the light seen from P through the slice's middle plane z_k, side
// (z_P - z_k) / z_P light sizes (eq. 4), centred on the segment from P to the light's centre —
// in texture units.
struct SliceKernel {
    float weight;
    vec2 center;
    float width;
};

SliceKernel occlusionKernel(float zP, vec2 lateralP, int k) {
    SliceKernel s;
    float u = (zP - occlusion.range.x) / occlusion.range.y;
    s.weight = clamp(u - 1.0 - float(k), 0.0, 1.0);
    float zk = occlusion.range.x + (float(k) + 0.5) * occlusion.range.y;
    float along = zk / zP;
    float m = occlusion.axis.w / (occlusion.axis.w + zk); // 1 / the frustum's magnification
    s.center = 0.5 + 0.5 * lateralP * along * m;
    s.width = (1.0 - along) * m;
    return s;
}

#endif
