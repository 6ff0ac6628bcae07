// Percentage-closer soft shadows (Fernando 2005), per G-buffer point P, in the shadow map of
// P's side of the light (geometry/shadow/PcssFrame.h: map coordinates m = lateral / depth z):
// 1. blocker search over the light seen from P through the casters' near plane: half extent
//    halfSize (1/zSearch - 1/zP) in m per light axis (the paper's searchWidth =
//    lightSize (zP - near) / zP, a rectangle for a rectangular light); texels in front of P
//    (below) are blockers, their depths averaged;
// 2. penumbra estimate: w = lightSize (zP - zBlocker) / zBlocker on the receiver, per axis; in
//    m, half extent halfSize (1/zBlocker - 1/zP);
// 3. percentage-closer filtering over that rectangle: V = the share of samples not in front.
// Each sample reads the 2 × 2 texels around it (one textureGather) weighted bilinearly, so V is
// continuous as P moves. The two patterns are fixed (PcssUniforms::pattern,
// geometry::scrambledNet): no noise, the same every frame and pixel.
//
// In front of P: a texel's surface point, on the ray from the light's centre through the
// texel's centre, lies on the light's side of P's own plane (the G-buffer's facet normal) moved
// NORMAL_OFFSET texels (the world size of a map texel at P's depth) towards the light, with a
// relative margin DEPTH_BIAS for rounding. Comparing with P's plane rather than P's depth
// keeps a tilted receiver from shadowing itself however wide the kernel (a receiver-plane
// bias); the offset along the normal is the slope-scaled part (along a ray it grows as
// 1 / cos of the ray's angle to the normal), for the rasteriser's rounding on surfaces seen
// edge-on from the light and for the neighbouring facets of concave corners.
//
// HORIZON (not in the paper): V is also multiplied by the share of the light in front of P's
// plane; a shadow map cannot see that a surface hides part of the light from itself, so curved
// surfaces near their terminator would be lit, or self-shadowed in facet-wide stripes.
// Receivers outside the map (beyond the frustum's cap) or in the light's plane get V = 1 and
// are counted.
#include "lib/Bindings.h"
#include "lib/Horizon.glsl"

layout(binding = TEXUNIT_POSITION) uniform sampler2D tPosition;
layout(binding = TEXUNIT_NORMAL) uniform sampler2D tNormal;
layout(binding = TEXUNIT_PCSS) uniform sampler2DArray tShadow; // zNear / z; 0: nothing

layout(std430, binding = BINDING_PCSS_STATS) buffer PcssStats {
    uint outside;
} stats;

layout(location = 0) out float oVisibility;

#ifndef NORMAL_OFFSET
#define NORMAL_OFFSET 1.5
#endif
// A texel is in front if its stored d = zNear / z exceeds the plane's by this share.
#define DEPTH_BIAS 1e-3
// The blocker search reaches no nearer to the light than this share of P's depth: a level's
// walls reach the light's plane, and a search region sized from there would cover the map.
#define SEARCH_DEPTH_RATIO (1.0 / 16.0)

struct Receiver {
    int layer;
    vec2 m;       // P's map coordinates
    vec2 lo, inv; // the side's map extent: uv = (m - lo) * inv
    float z;      // P's depth
    vec3 plane;   // P's (offset) plane along the ray through m: 1 / z = dot(plane, (m, 1))
};

// d = zNear / z of P's plane along the ray from the light's centre through m (0 where the ray
// does not meet the plane in front of the light: every surface there is in front of P).
float planeDepth(Receiver r, vec2 m) {
    return max(pcss.normal.w * dot(r.plane, vec3(m, 1.0)), 0.0);
}

// The 2 × 2 texels around map point m: their stored depths and the centres' coordinates.
struct Texels {
    vec4 d;      // textureGather order: (0, 1), (1, 1), (1, 0), (0, 0)
    vec2 m0, m1; // centres of column / row 0 and of column / row 1, in m
    vec4 weight; // bilinear
};

Texels texelsAround(Receiver r, vec2 m) {
    float R = pcss.params.z;
    vec2 t = (m - r.lo) * r.inv * R - 0.5;
    vec2 base = floor(t);
    vec2 f = t - base;
    Texels x;
    // Gathered at the four texels' shared corner, so that no rounding can pick other ones.
    x.d = textureGather(tShadow, vec3((base + 1.0) * pcss.params.w, float(r.layer)));
    x.m0 = r.lo + (base + 0.5) * pcss.params.w / r.inv;
    x.m1 = r.lo + (base + 1.5) * pcss.params.w / r.inv;
    x.weight = vec4((1.0 - f.x) * f.y, f.x * f.y, f.x * (1.0 - f.y), (1.0 - f.x) * (1.0 - f.y));
    return x;
}

// 1 where the texel's surface is in front of P.
vec4 inFront(Receiver r, Texels x) {
    vec4 plane = vec4(planeDepth(r, vec2(x.m0.x, x.m1.y)), planeDepth(r, x.m1),
                      planeDepth(r, vec2(x.m1.x, x.m0.y)), planeDepth(r, x.m0));
    return vec4(greaterThan(x.d, plane * (1.0 + DEPTH_BIAS)));
}

// V from the shadow map alone (1 where P is outside it, counted).
float shadowMapVisibility(vec3 position, vec3 N) {
    vec3 n = pcss.normal.xyz;
    vec3 toP = position - frame.lightCenter.xyz;
    float signedDepth = dot(toP, n);
    Receiver r;
    r.layer = signedDepth >= 0.0 ? 0 : 1;
    r.z = abs(signedDepth);
    vec3 axis = r.layer == 0 ? n : -n;
    float zNear = pcss.normal.w;
    bool inMap = pcss.sides[r.layer] != 0.0 && r.z > zNear;
    if (inMap) {
        r.m = vec2(dot(toP, pcss.basisU.xyz), dot(toP, pcss.basisV.xyz)) / r.z;
        r.lo = pcss.extent[r.layer].xy;
        r.inv = pcss.extent[r.layer].zw;
        vec2 uv = (r.m - r.lo) * r.inv;
        inMap = all(greaterThanEqual(uv, vec2(0.0))) && all(lessThanEqual(uv, vec2(1.0)));
    }
    if (!inMap) {
        atomicAdd(stats.outside, 1u);
        return 1.0;
    }
    float casterNear = pcss.sides[2 + r.layer];
    float zSearch = max(casterNear, SEARCH_DEPTH_RATIO * r.z);
    if (casterNear == 0.0 || zSearch >= r.z) return 1.0; // no caster between P and the light

    // P's plane, moved towards the light: points c + z (m.x eu + m.y ev + axis) with
    // dot(N, . - P) = offset, so 1 / z = dot(N, (eu, ev, axis) (m, 1)) / (dot(N, P - c) + offset)
    // for N facing the light's centre (dot(N, P - c) < 0). Never past the light's centre.
    float np = dot(N, toP);
    if (np > 0.0) {
        N = -N;
        np = -np;
    }
    float texelWorld = r.z * pcss.params.w / min(r.inv.x, r.inv.y);
    np = min(np + NORMAL_OFFSET * texelWorld, 0.5 * np);
    r.plane = np == 0.0
                  ? vec3(0.0)
                  : vec3(dot(N, pcss.basisU.xyz), dot(N, pcss.basisV.xyz), dot(N, axis)) / np;
    vec2 halfSize = vec2(pcss.basisU.w, pcss.basisV.w);

    // 1. Blocker search.
    vec2 searchHalf = halfSize * (1.0 / zSearch - 1.0 / r.z);
    float blockerDepth = 0.0, blockerWeight = 0.0;
    int searchSamples = int(pcss.params.x);
    for (int i = 0; i < searchSamples; ++i) {
        Texels x = texelsAround(r, r.m + pcss.pattern[i].zw * searchHalf);
        vec4 w = x.weight * inFront(r, x);
        blockerDepth += dot(w, zNear / max(x.d, 1e-30));
        blockerWeight += dot(w, vec4(1.0));
    }
    if (blockerWeight == 0.0) return 1.0;
    // Every search sample blocked: the (smaller) filter rectangle is taken to be umbra too,
    // the usual shortcut (V unchanged on the parallel square, overlap, the demo and the
    // spheres; the lookup 20-50% faster there).
    if (blockerWeight >= float(searchSamples) * (1.0 - 1e-6)) return 0.0;
    float zBlocker = blockerDepth / blockerWeight;

    // 2. Penumbra width; 3. filtering.
    vec2 filterHalf = halfSize * max(1.0 / zBlocker - 1.0 / r.z, 0.0);
    int filterSamples = int(pcss.params.y);
    float lit = 0.0;
    for (int i = 0; i < filterSamples; ++i) {
        Texels x = texelsAround(r, r.m + pcss.pattern[i].xy * filterHalf);
        lit += dot(x.weight, vec4(1.0) - inFront(r, x));
    }
    return lit / float(filterSamples);
}

void main() {
    ivec2 px = ivec2(gl_FragCoord.xy);
    vec4 position = texelFetch(tPosition, px, 0);
    if (position.w == 0.0) {
        oVisibility = 1.0; // no surface
        return;
    }
    vec3 N = texelFetch(tNormal, px, 0).xyz;
#ifdef HORIZON
    float horizon = horizonFraction(position.xyz, N);
    if (horizon == 0.0) {
        oVisibility = 0.0; // the light wholly behind the surface
        return;
    }
#else
    float horizon = 1.0;
#endif
    oVisibility = clamp(horizon * shadowMapVisibility(position.xyz, N), 0.0, 1.0);
}
