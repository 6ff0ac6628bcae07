// The wedge pass's per-wedge helpers, shared by wedge.vert (the hulls drawn) and
// wedge-tiles.comp (the hulls binned to screen tiles for the tiled evaluation).
#ifndef PENUMBRA_LIB_WEDGE_CORNERS_GLSL
#define PENUMBRA_LIB_WEDGE_CORNERS_GLSL

// The NDC rectangle of a box, or [-1, 1]^2 when part of it is behind the eye.
vec4 screenRect(vec3 lo, vec3 hi) {
    vec2 rmin = vec2(1.0), rmax = vec2(-1.0);
    for (int c = 0; c < 8; ++c) {
        vec3 corner = vec3((c & 1) != 0 ? hi.x : lo.x, (c & 2) != 0 ? hi.y : lo.y,
                           (c & 4) != 0 ? hi.z : lo.z);
        vec4 clip = frame.viewProj * vec4(corner, 1.0);
        if (clip.w <= 0.0) return vec4(-1.0, -1.0, 1.0, 1.0);
        rmin = min(rmin, clip.xy / clip.w);
        rmax = max(rmax, clip.xy / clip.w);
    }
    return vec4(max(rmin, vec2(-1.0)), min(rmax, vec2(1.0)));
}

#ifdef WEDGE_APEXES
// A triangle's corners (global welded ids a, b, c; c = 0xFFFFFFFF: no triangle, all zero) in
// ascending id order, w: the sign of the sorting permutation. Needs weldedPositions[].
void triangleCorners(uint a, uint b, uint c, out vec4 t[3]) {
    if (c == 0xFFFFFFFFu) {
        for (int i = 0; i < 3; ++i) t[i] = vec4(0.0);
        return;
    }
    // Sort (a, b, c) ascending, counting the swaps (the permutation's parity).
    float parity = 1.0;
    uint x;
    if (a > b) { x = a; a = b; b = x; parity = -parity; }
    if (b > c) { x = b; b = c; c = x; parity = -parity; }
    if (a > b) { x = a; a = b; b = x; parity = -parity; }
    t[0] = vec4(weldedPositions[a].xyz, parity);
    t[1] = vec4(weldedPositions[b].xyz, parity);
    t[2] = vec4(weldedPositions[c].xyz, parity);
}
#endif

#endif // PENUMBRA_LIB_WEDGE_CORNERS_GLSL
