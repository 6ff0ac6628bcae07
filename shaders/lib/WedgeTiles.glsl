// wedges-bitmask evaluate=tiles: the wedges binned to 16 x 16 pixel screen tiles
// (wedge-tiles.comp), then evaluated per pixel over its tile's list (wedge-bitmask-tiles.comp)
// instead of rasterising their hulls. What a wedge slot needs for both, gathered once per frame.
#ifndef PENUMBRA_LIB_WEDGE_TILES_GLSL
#define PENUMBRA_LIB_WEDGE_TILES_GLSL

#ifndef WEDGE_TILE
#define WEDGE_TILE 8 // pixels per tile side (WedgeTilePass::kTile, its surface-tiles.comp's)
#endif

#define TILE_WEDGE_TEXELS 12 // vec4s in a TileWedge
struct TileWedge {
    vec4 e0;        // xyz: the edge's start (GpuWedge::e0); w: GpuWedge::kind's bits
                    // (WEDGE_BOUNDED, WEDGE_FULLSCREEN; others add nothing)
    vec4 e1;        // xyz: its end; w: GpuWedge::eyeInside's bits (the evaluation reads the
                    // kind with the ends it needs anyway: a texel fewer a pair)
    vec4 planes[4]; // the hull's planes (GpuWedge::planes): P inside all four, or no change;
                    // a full-screen wedge's let every P through (its rectangle decides)
    vec4 tri0[2];   // the edge's triangles as wedge.vert hands them to wedge-bitmask.frag
    vec4 tri1[2];   // (lib/WedgeCorners.glsl trianglePlane)
    vec4 bound;     // WEDGE_FULLSCREEN: the NDC rectangle of its group's influence (wedge.vert's);
                    // WEDGE_BOUNDED: a cut silhouette cone's far face (WedgeHull::reach) as a
                    // fifth plane (inside: dot(far.xyz, P) + far.w <= 0), else (0, 0, 0, -1),
                    // not a bound on P: see tileWedgeHolds. (One texel for both: the
                    // evaluation reads it once a pair; a texel costs a SIMD vector about 100
                    // instructions on llvmpipe, read by every lane whatever its branch.)
    ivec4 tiles;    // the tiles its hull's screen rectangle touches: x0, y0, x1, y1 (inclusive)
};
uint tileWedgeKind(TileWedge w) {
    return floatBitsToUint(w.e0.w);
}

#ifndef WEDGE_TILES_TEXELS // (the evaluation reads them as texels)
layout(std430, binding = BINDING_WEDGE_TILE_RECORDS) buffer TileWedges {
    TileWedge tileWedges[]; // per wedge slot (GpuWedge's index)
};
#endif
// Per tile t of T: heads[t] the count, heads[T + t] the first entry (from uListBase), heads[2 T
// + t] the fill cursor; heads[3 T + WEDGE_TILES_*] the totals; from heads[3 T +
// WEDGE_TILES_HEADER] the ids of the tiles whose list is not empty (WEDGE_TILES_ACTIVE of them,
// in no order: the evaluation's work groups), from heads[4 T + WEDGE_TILES_HEADER] the frame's
// wedge slots to bin (uRun); the lists of wedge slots from heads[uListBase].
layout(std430, binding = BINDING_WEDGE_TILE_LISTS) buffer TileLists {
    uint heads[];
};
layout(location = 3) uniform uint uListBase; // where the lists start in heads[]

// Whether any point of the box [lo, hi] may lie inside all four planes: false when the whole
// box is outside one of them (its nearest corner outside, by more than rounding).
bool boxOutsidePlane(vec4 plane, vec3 lo, vec3 hi) {
    vec3 n = plane.xyz;
    vec3 nearest = mix(hi, lo, greaterThan(n, vec3(0.0)));
    float d = dot(n, nearest) + plane.w;
    float scale = dot(abs(n), max(abs(lo), abs(hi))) + abs(plane.w);
    return d > 1e-5 * scale;
}
bool boxMayMeetHull(vec4 planes[4], vec3 lo, vec3 hi) {
    for (int i = 0; i < 4; ++i)
        if (boxOutsidePlane(planes[i], lo, hi)) return false;
    return true;
}

// Whether the raster pass gives receiver p (the surface at the pixel whose eye ray is eye -> p)
// a fragment of a bounded wedge that its fragment shader keeps: p inside the four planes, and
// the ray meets the drawn hull on the way to p (entry faces, the camera outside) or leaves it
// behind p (exit faces, the camera perhaps inside: eyeInside). The drawn hull is the four
// planes' region, cut by the far face where a silhouette cone is cut to its reach; the shader
// tests the four planes only, so a receiver beyond the far face counts where the ray enters the
// hull in front of it. (That face is computed in float from nearly dependent directions and can
// fall short of a receiver by a fraction of a percent: the rasterised hull still covers it.)
bool tileWedgeHolds(vec4 planes[4], vec4 far, bool eyeInside, vec3 eye, vec3 p) {
    if (!wedgeHullContains(planes, p)) return false;
    if (dot(far.xyz, p) + far.w <= 0.0) return true;
    if (eyeInside) return false;
    // Where the segment eye -> p enters the four planes' region (p is inside every one).
    float t0 = 0.0;
    for (int i = 0; i < 4; ++i) {
        float fe = dot(planes[i].xyz, eye) + planes[i].w;
        float fp = dot(planes[i].xyz, p) + planes[i].w;
        if (fe > 0.0) t0 = max(t0, fe / (fe - fp));
    }
    vec3 entry = mix(eye, p, t0);
    return dot(far.xyz, entry) + far.w <= 0.0;
}

#endif // PENUMBRA_LIB_WEDGE_TILES_GLSL
