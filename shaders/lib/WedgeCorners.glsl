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
// A triangle's plane as lib/BitmaskEdge.glsl's triangleSide takes it (global welded ids a, b,
// c; c = 0xFFFFFFFF: no triangle, all zero): t[0] its first corner t0 in ascending id order,
// with in w the sign of the sorting permutation (which turns orientations about the sorted
// corners into those about (a, b, c)); t[1] the normal (t1 - t0) x (t2 - t0) of the sorted
// corners. A triangle reaches triangleSide as the same floats from each of its three edges, so
// its side of P is decided bit for bit alike on all three (their counts cancel exactly).
// Computed once per wedge, for the raster pass (wedge.vert) and the tiled evaluation's records
// (wedge-tiles.comp) alike: two texels a triangle where its three corners took three, and no
// cross product per pixel. Needs weldedPositions[].
void trianglePlane(uint a, uint b, uint c, out vec4 t[2]) {
    if (c == 0xFFFFFFFFu) {
        t[0] = vec4(0.0);
        t[1] = vec4(0.0);
        return;
    }
    // Sort (a, b, c) ascending, counting the swaps (the permutation's parity).
    float parity = 1.0;
    uint x;
    if (a > b) { x = a; a = b; b = x; parity = -parity; }
    if (b > c) { x = b; b = c; c = x; parity = -parity; }
    if (a > b) { x = a; a = b; b = x; parity = -parity; }
    vec3 t0 = weldedPositions[a].xyz;
    t[0] = vec4(t0, parity);
    t[1] = vec4(cross(weldedPositions[b].xyz - t0, weldedPositions[c].xyz - t0), 0.0);
}
#endif

#endif // PENUMBRA_LIB_WEDGE_CORNERS_GLSL
