// View-frustum test of world-space boxes against frame.viewProj (reversed Z, infinite far
// plane: the side planes and the near plane bound it; nothing is beyond "far").
bool boxOutsideFrustum(vec3 lo, vec3 hi) {
    mat4 m = frame.viewProj;
    vec4 r0 = vec4(m[0][0], m[1][0], m[2][0], m[3][0]);
    vec4 r1 = vec4(m[0][1], m[1][1], m[2][1], m[3][1]);
    vec4 r2 = vec4(m[0][2], m[1][2], m[2][2], m[3][2]);
    vec4 r3 = vec4(m[0][3], m[1][3], m[2][3], m[3][3]);
    // Inside: -w <= x <= w, -w <= y <= w, z <= w (near plane; z >= 0 holds to infinity).
    vec4 planes[5] = vec4[5](r3 + r0, r3 - r0, r3 + r1, r3 - r1, r3 - r2);
    for (int i = 0; i < 5; ++i) {
        // The box corner farthest along the plane's normal: if even it is outside, all are.
        vec3 corner = mix(lo, hi, step(0.0, planes[i].xyz));
        if (dot(planes[i].xyz, corner) + planes[i].w < 0.0) return true;
    }
    return false;
}
