// Occlusion textures (Eisemann & Décoret 2006): the frame of the slices, the float twin of
// geometry/OcclusionSlices.h (depth, lateral, the lookup of slice k).
#ifndef PENUMBRA_OCCLUSION_GLSL
#define PENUMBRA_OCCLUSION_GLSL

// Depth of q below the light's plane, along the sliced side's axis.
float occlusionDepth(vec3 q) {
    return dot(q - frame.lightCenter.xyz, occlusion.axis.xyz);
}

// (s, t) of q in the light's half-axes (the light is [-1, 1]^2).
vec2 occlusionLateral(vec3 q) {
    vec3 d = q - frame.lightCenter.xyz;
    return vec2(dot(d, frame.lightUStar.xyz), dot(d, frame.lightVStar.xyz));
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

// The fraction of the light in front of the plane through p with normal n
// (geometry::horizonFraction): clip the light's square, where the distance to the plane is
// affine in (s, t), to the positive side and take its area.
float horizonFraction(vec3 p, vec3 n) {
    float a = dot(n, frame.lightCenter.xyz - p);
    float b = dot(n, frame.lightU.xyz), c = dot(n, frame.lightV.xyz);
    const vec2 square[4] = vec2[4](vec2(-1, -1), vec2(1, -1), vec2(1, 1), vec2(-1, 1));
    vec2 clipped[5];
    int count = 0;
    for (int i = 0; i < 4; ++i) {
        vec2 p0 = square[i], p1 = square[(i + 1) & 3];
        float g0 = a + b * p0.x + c * p0.y, g1 = a + b * p1.x + c * p1.y;
        if (g0 >= 0.0) clipped[count++] = p0;
        if ((g0 >= 0.0) != (g1 >= 0.0)) clipped[count++] = p0 + (g0 / (g0 - g1)) * (p1 - p0);
    }
    float area2 = 0.0;
    for (int i = 0; i < count; ++i) {
        vec2 p0 = clipped[i], p1 = clipped[(i + 1) % count];
        area2 += p0.x * p1.y - p1.x * p0.y;
    }
    return clamp(0.125 * area2, 0.0, 1.0);
}

#endif
