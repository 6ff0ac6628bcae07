// The share of the light in front of a surface's own plane (geometry::horizonFraction): an
// opaque surface hides the rest of the light from its points. Used by the occlusion and pcss
// lookups (parameter horizon=on) as one more independent occluder.
#ifndef PENUMBRA_HORIZON_GLSL
#define PENUMBRA_HORIZON_GLSL

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
