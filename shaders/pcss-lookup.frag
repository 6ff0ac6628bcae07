// Percentage-closer soft shadows (Fernando 2005), per G-buffer point P, in the shadow map of
// P's face of the cube around the light's centre (geometry/shadow/PcssFrame.h: faceOf picks it;
// map coordinates m = lateral / depth z in the face's axes):
// 1. blocker search over the light seen from P through the casters' near plane: the search
//    pattern's points on the light, each where its segment to P crosses depth zSearch
//    (throughLight; on the front faces the paper's rectangle of half extent
//    halfSize (1/zSearch - 1/zP), searchWidth = lightSize (zP - near) / zP); texels in front of
//    P (below) are blockers, their depths averaged, but only if one of them, or one found by
//    a second search at the deepest of them, lies in P's pyramid to the light (inPyramid, not
//    in the paper; below);
// 2. penumbra estimate: the light seen through the blockers' mean depth zBlocker (on the front
//    faces half extent halfSize (1/zBlocker - 1/zP), the paper's
//    w = lightSize (zP - zBlocker) / zBlocker per axis);
// 3. percentage-closer filtering over it: V = the share of the filter's points not in front.
// Each sample reads the 2 × 2 texels around it (one textureGather) weighted bilinearly, so V is
// continuous as P moves. The two patterns are fixed (PcssUniforms::pattern,
// geometry::scrambledNet): no noise, the same every frame and pixel.
//
// In front of P: a texel's surface point, on the ray from the light's centre through the
// texel's centre, lies on the light's side of P's own plane (the G-buffer's facet normal) moved
// NORMAL_OFFSET texels (the world size of a map texel at P's depth, along the finer of the
// map's axes: the side faces' maps are 3x finer towards ±n) towards the light, with a
// relative margin DEPTH_BIAS for rounding. Comparing with P's plane rather than P's depth
// keeps a tilted receiver from shadowing itself however wide the kernel (a receiver-plane
// bias); the offset along the normal is the slope-scaled part (along a ray it grows as
// 1 / cos of the ray's angle to the normal), for the rasteriser's rounding on surfaces seen
// edge-on from the light and for the neighbouring facets of concave corners.
//
// HORIZON (not in the paper): V is also multiplied by the share of the light in front of P's
// plane; a shadow map cannot see that a surface hides part of the light from itself, so curved
// surfaces near their terminator would be lit, or self-shadowed in facet-wide stripes.
// A receiver whose segment to the light's centre misses every box around the casters grown by
// the light's half extents (PcssUniforms::reach) has no blocker and skips the search. Receivers
// within zNear of the light's centre (in no face) get V = 1, and those a caster could reach are
// counted.
//
// DEEP_SHADOW_MAP (the deep-sm method, geometry/shadow/DeepShadowMap.h): the faces' maps are
// deep shadow maps. Where pcss asks whether a texel's surface is in front of P (1 or 0), deep-sm
// reads the texel's transmittance T along its ray at P's (offset) plane and takes its opacity
// 1 - T: the blocker search weights each texel's nearest depth by it, the filter sums T. The
// same frame, patterns, offsets and horizon as pcss's.
//
// Drawn over tiles (tile-rects.vert) where the frame's surface tiles are known: a tile whose
// surface box, swept to the light's centre, meets no reach box (geometry::sweepMeetsBox: no
// pixel of it passes the reach test below) skips this lookup, and with HORIZON gets the horizon
// term alone (HORIZON_ONLY).
//
// OUTSIDE_OCCLUSION: the occlusion method's fallback. Only the pixels its slicing frustum does
// not cover (occlusionCovers: behind or in the light's plane, beyond the capped frustum) are
// written, and counted; the others keep the occlusion textures' V.
#include "lib/Bindings.h"
#include "lib/Horizon.glsl"
#ifdef OUTSIDE_OCCLUSION
#include "lib/Occlusion.glsl"
#endif

layout(binding = TEXUNIT_POSITION) uniform sampler2D tPosition;
layout(binding = TEXUNIT_NORMAL) uniform sampler2D tNormal;
#ifdef DEEP_SHADOW_MAP
#include "lib/Pdsm.glsl"
// per face and texel: first group of points, point count | nearest depth code << 16
layout(binding = TEXUNIT_DEEP_SM_INDEX) uniform usampler2DArray tDeepIndex;
#else
layout(binding = TEXUNIT_PCSS) uniform sampler2DArray tShadow; // per face zNear / z; 0: nothing
#endif

layout(std430, binding = BINDING_PCSS_STATS) buffer PcssStats {
    uint outside;  // pixels in no face
    uint fallback; // OUTSIDE_OCCLUSION: pixels written
    uint unconfirmed; // pixels whose texels in front lay outside their pyramid to the light: lit
    uint searched; // pixels a caster's box could reach (the others are lit without a search)
} stats;

layout(location = 0) out float oVisibility;

#ifndef NORMAL_OFFSET
#define NORMAL_OFFSET 1.5
#endif
// The normal offset's move along the ray from the light, at most, in texels at P.
#define RAY_SHIFT_CAP 8.0
// A texel is in front if its stored d = zNear / z exceeds the plane's by this share.
#define DEPTH_BIAS 1e-3
// The blocker search reaches no nearer to the light than this share of P's depth: a level's
// walls reach the light's plane, and a search region sized from there would cover the map.
#define SEARCH_DEPTH_RATIO (1.0 / 16.0)
// inPyramid's margin around the light, in its half extents.
#ifndef PYRAMID_SLACK
#define PYRAMID_SLACK 0.02
#endif

struct Receiver {
    int face;
    vec3 p;       // P in the face's coordinates: lateral, then depth
    vec2 m;       // P's map coordinates
    vec2 lo, inv; // the face's map extent: uv = (m - lo) * inv
    float z;      // P's depth
    vec3 plane;   // P's (offset) plane along the ray through m: 1 / z = dot(plane, (m, 1))
    vec3 lu, lv;  // the light's half axes in the face's coordinates
    vec3 N;       // P's normal, facing the light's centre
    float np;     // dot(N, P - c) moved by the offset (< 0; 0 at the centre)
#ifndef DEEP_SHADOW_MAP
    vec3 ln, lus, lvs; // the light's normal and dual axes in the face's coordinates
    vec3 pl;           // P's height over the light's plane and its (s, t) along the dual axes
#endif
};

// Where the segment from P to the light's point s (in [-1, 1]^2 over its half axes) crosses
// depth z, in map coordinates (geometry::throughLight, its CPU twin).
vec2 throughLight(Receiver r, vec2 s, float z) {
    vec3 l = s.x * r.lu + s.y * r.lv;
    float t = clamp((r.p.z - z) / (r.p.z - l.z), 0.0, 1.0);
    vec3 q = mix(r.p, l, t);
    return q.xy / q.z;
}

// d = zNear / z of P's plane (`plane`, in a face's coordinates) along the ray from the light's
// centre through m (0 where the ray does not meet the plane in front of the light: every
// surface there is in front of P).
float planeDepth(vec3 plane, vec2 m) {
    return max(pcss.normal.w * dot(plane, vec3(m, 1.0)), 0.0);
}

// The face a direction from the light's centre falls in (faceOf without the zNear test).
int faceOfDirection(vec3 d) {
    float x = dot(d, pcss.basisU.xyz), y = dot(d, pcss.basisV.xyz), z = dot(d, pcss.normal.xyz);
    float a = max(abs(x), abs(y));
    if (a <= pcss.basisU.w * abs(z)) return z > 0.0 ? 0 : 1;
    if (abs(x) >= abs(y)) return x >= 0.0 ? 2 : 3;
    return y >= 0.0 ? 4 : 5;
}

// P's offset plane in face g's coordinates: 1 / z = dot(plane, (m, 1)).
vec3 planeIn(Receiver r, int g) {
    return r.np == 0.0 ? vec3(0.0)
                       : vec3(dot(r.N, pcss.faceB1[g].xyz), dot(r.N, pcss.faceB2[g].xyz),
                              dot(r.N, pcss.faceAxis[g].xyz)) / r.np;
}

// The 2 × 2 texels around a sample, map point m of P's face, read in the face its direction
// falls in (the maps form one cube): their stored depths, the centres' coordinates in that
// face, P's plane there, and the factor from that face's depths to P's face's.
struct Texels {
    vec4 d;      // textureGather order: (0, 1), (1, 1), (1, 0), (0, 0); 0: nothing
#ifdef DEEP_SHADOW_MAP
    uvec4 first, counts; // deep: the texels' index entries (counts: count | nearest << 16)
    vec2 range;          // deep: the face's zc and sFar
#endif
    vec2 m0, m1; // centres of column / row 0 and of column / row 1, in the face's m
    vec4 weight; // bilinear
    vec3 plane;  // P's plane in the face's coordinates
    float scale; // depth along P's face's axis per depth along this face's
};

Texels texelsAround(Receiver r, vec2 m) {
    Texels x;
    int g = r.face;
    x.plane = r.plane;
    x.scale = 1.0;
    vec3 dir = m.x * pcss.faceB1[g].xyz + m.y * pcss.faceB2[g].xyz + pcss.faceAxis[g].xyz;
    int h = faceOfDirection(dir);
    if (h != g) {
        float ah = dot(dir, pcss.faceAxis[h].xyz);
        m = vec2(dot(dir, pcss.faceB1[h].xyz), dot(dir, pcss.faceB2[h].xyz)) / ah;
        x.scale = 1.0 / ah;
        x.plane = planeIn(r, h);
        g = h;
    }
    vec2 lo = pcss.extent[g].xy, inv = pcss.extent[g].zw;
    float R = pcss.params.z;
    vec2 t = (m - lo) * inv * R - 0.5;
    vec2 base = floor(t);
    vec2 f = t - base;
    // Gathered at the four texels' shared corner, so that no rounding can pick other ones. A
    // face whose map is not drawn holds nothing.
#ifdef DEEP_SHADOW_MAP
    // d from each texel's nearest code t: s = zc / z = 1 - t (1 - sFar), d = zNear s / zc.
    vec3 at = vec3((base + 1.0) * pcss.params.w, float(g));
    bool built = pcss.faceDeep[g].z != 0.0;
    x.first = built ? textureGather(tDeepIndex, at, 0) : uvec4(0u);
    x.counts = built ? textureGather(tDeepIndex, at, 1) : uvec4(0u);
    x.range = pcss.faceDeep[g].xy;
    vec4 nearT = vec4(x.counts >> 16u) / PDSM_DEPTH_CODES;
    x.d = mix(vec4(0.0),
              pcss.normal.w * (1.0 - nearT * (1.0 - x.range.y)) / x.range.x,
              vec4(notEqual(x.counts & 0xFFFFu, uvec4(0u))));
#else
    x.d = pcss.faceB1[g].w >= 2.0
              ? textureGather(tShadow, vec3((base + 1.0) * pcss.params.w, float(g)))
              : vec4(0.0);
#endif
    x.m0 = lo + (base + 0.5) * pcss.params.w / inv;
    x.m1 = lo + (base + 1.5) * pcss.params.w / inv;
    x.weight = vec4((1.0 - f.x) * f.y, f.x * f.y, f.x * (1.0 - f.y), (1.0 - f.x) * (1.0 - f.y));
    return x;
}

#ifndef DEEP_SHADOW_MAP
// 1 where the line from P through the texel's surface point meets the light's rectangle with
// the point between P and the light (the point taken on the ray of map point m, the sample's, at
// the texel's depth): a surface that can hide part of the light from P. PCSS alone takes every
// texel in front of P's plane that its search or filter region reads; around a lamp in a room
// those regions reach far to the sides, and walls and ledges beside P's pyramid to the light
// shadowed lit floors (kaos2's twelfth spawn view: 0.24 mean). With X = z (m, 1) in P's face
// and s_X = 1 / z: the line P + l (X - P) meets the light's plane at l = h_P / (h_P - h_X), and
// X lies between when l > 1; the meeting point's (s, t) from the same terms, per texel only s_X.
vec4 inPyramid(Receiver r, vec2 m, Texels x) {
    vec3 A = vec3(m, 1.0);
    float an = dot(r.ln, A), au = dot(r.lus, A), av = dot(r.lvs, A);
    vec4 s = x.d / (pcss.normal.w * x.scale); // 0: nothing
    vec4 w = 1.0 / (r.pl.x * s - an);
    vec4 l = r.pl.x * s * w;
    vec4 su = r.pl.y + r.pl.x * w * (au - r.pl.y * s);
    vec4 sv = r.pl.z + r.pl.x * w * (av - r.pl.z * s);
    return vec4(greaterThan(l, vec4(1.0))) *
           vec4(lessThanEqual(max(abs(su), abs(sv)), vec4(1.0 + PYRAMID_SLACK)));
}
#endif

// 1 where the texel's surface is in front of P (deep: the opacity in front of P).
vec4 inFront(Texels x) {
    vec4 plane = vec4(planeDepth(x.plane, vec2(x.m0.x, x.m1.y)), planeDepth(x.plane, x.m1),
                      planeDepth(x.plane, vec2(x.m1.x, x.m0.y)), planeDepth(x.plane, x.m0));
#ifdef DEEP_SHADOW_MAP
    // The plane's depth code along each texel's ray, moved by DEPTH_BIAS towards the light:
    // s = zc / z = zc d / zNear (d = 0, no plane in front of the light: past every depth).
    vec4 t = (1.0 - x.range.x * plane * (1.0 + DEPTH_BIAS) / pcss.normal.w) / (1.0 - x.range.y);
    vec4 opacity = vec4(0.0);
    for (int k = 0; k < 4; ++k) {
        uint count = x.counts[k] & 0xFFFFu;
        float nearT = float(x.counts[k] >> 16u) / PDSM_DEPTH_CODES;
        if (count != 0u && t[k] >= nearT)
            opacity[k] = 1.0 - pdsmFunction(x.first[k], count, t[k]);
    }
    return opacity;
#else
    return vec4(greaterThan(x.d, plane * (1.0 + DEPTH_BIAS)));
#endif
}

// Whether the segment a + t d, t in [0, 1], meets the box [lo, hi] (slabs; invD = 1 / d per
// axis, each component of d kept away from 0 with its sign).
bool segmentMeetsBox(vec3 a, vec3 invD, vec3 lo, vec3 hi) {
    vec3 t0 = (lo - a) * invD, t1 = (hi - a) * invD;
    vec3 near = min(t0, t1), far = max(t0, t1);
    return max(max(near.x, near.y), max(near.z, 0.0)) <= min(min(far.x, far.y), min(far.z, 1.0));
}

// The face whose map holds P (geometry::PcssFrame::faceOf), -1 within zNear of the centre.
int faceOf(vec3 toP) {
    float x = dot(toP, pcss.basisU.xyz), y = dot(toP, pcss.basisV.xyz);
    float z = dot(toP, pcss.normal.xyz);
    float a = max(abs(x), abs(y));
    if (a <= pcss.basisU.w * abs(z)) return abs(z) > pcss.normal.w ? (z > 0.0 ? 0 : 1) : -1;
    if (a <= pcss.normal.w) return -1;
    if (abs(x) >= abs(y)) return x >= 0.0 ? 2 : 3;
    return y >= 0.0 ? 4 : 5;
}

// V from the shadow map alone (1 where P is in no map, counted).
float shadowMapVisibility(vec3 position, vec3 N) {
    int boxes = int(pcss.params2.x);
    bool reached = false; // no boxes: no point of the casters hides light (all cut away)
    vec3 d = frame.lightCenter.xyz - position;
    vec3 invD = 1.0 / (sign(d) * max(abs(d), vec3(1e-20)) + vec3(equal(d, vec3(0.0))) * 1e-20);
    for (int k = 0; k < boxes; ++k)
        reached = reached || segmentMeetsBox(position, invD, pcss.reach[2 * k].xyz,
                                             pcss.reach[2 * k + 1].xyz);
    if (!reached) return 1.0; // no segment to the light meets a caster
    atomicAdd(stats.searched, 1u);
    vec3 toP = position - frame.lightCenter.xyz;
    Receiver r;
    r.face = faceOf(toP);
    bool inMap = r.face >= 0 && mod(pcss.faceB1[max(r.face, 0)].w, 2.0) != 0.0; // present
    vec3 b1 = pcss.faceB1[max(r.face, 0)].xyz, b2 = pcss.faceB2[max(r.face, 0)].xyz;
    vec3 axis = pcss.faceAxis[max(r.face, 0)].xyz;
    if (inMap) {
        r.p = vec3(dot(toP, b1), dot(toP, b2), dot(toP, axis));
        r.z = r.p.z;
        r.m = r.p.xy / r.z;
        r.lo = pcss.extent[r.face].xy;
        r.inv = pcss.extent[r.face].zw;
        vec2 uv = (r.m - r.lo) * r.inv;
        inMap = all(greaterThanEqual(uv, vec2(0.0))) && all(lessThanEqual(uv, vec2(1.0)));
    }
    if (!inMap) {
        atomicAdd(stats.outside, 1u);
        return 1.0;
    }
    float zNear = pcss.normal.w;
    float casterNear = pcss.faceB2[r.face].w;
    // Blockers are searched no nearer than the light reaches along the face's axis (on the
    // side faces the light lies across the depth range, seen edge-on).
    float lightDepth = pcss.faceAxis[r.face].w;
    float zSearch = max(max(casterNear, SEARCH_DEPTH_RATIO * r.z), 1.01 * lightDepth);
    // No caster between P and the light: none in any map, or none in P's face nearer than P.
    if (pcss.basisV.w == 0.0 || zSearch >= r.z) return 1.0;
    r.lu = pcss.lightU[r.face].xyz;
    r.lv = pcss.lightV[r.face].xyz;
#ifndef DEEP_SHADOW_MAP
    r.ln = normalize(cross(r.lu, r.lv));
    r.lus = cross(r.lv, r.ln) / dot(r.lu, cross(r.lv, r.ln));
    r.lvs = cross(r.ln, r.lu) / dot(r.lv, cross(r.ln, r.lu));
    r.pl = vec3(dot(r.ln, r.p), dot(r.lus, r.p), dot(r.lvs, r.p));
#endif

    // P's plane, moved towards the light: points c + z (m.x b1 + m.y b2 + axis) with
    // dot(N, . - P) = offset, so 1 / z = dot(N, (b1, b2, axis) (m, 1)) / (dot(N, P - c) + offset)
    // for N facing the light's centre (dot(N, P - c) < 0). Never past the light's centre.
    float np = dot(N, toP);
    if (np > 0.0) {
        N = -N;
        np = -np;
    }
    float texelWorld = r.z * pcss.params.w / max(r.inv.x, r.inv.y);
    r.N = N;
    // Moving the plane by `offset` along N moves it offset / cos(angle) along a ray from the
    // light: where every light point grazes the surface, that reaches past the blockers near P
    // (a wall's edge, a window's frame) and draws them lit. The move along the least grazing
    // corner's ray is capped at RAY_SHIFT_CAP texels (textured oa_dm5, third spawn view with the
    // lamp: 0.0104 mean without the cap, 0.0082 with it; the other spawn views within 0.0003).
    // Never negative (horizon=off, the light wholly behind the surface).
    float facing = -np / length(toP);
    for (int k = 0; k < 4; ++k) {
        vec3 corner = ((k & 1) != 0 ? 1.0 : -1.0) * frame.lightU.xyz +
                      ((k & 2) != 0 ? 1.0 : -1.0) * frame.lightV.xyz - toP;
        facing = max(facing, dot(N, corner) / length(corner));
    }
    float offset =
        clamp(RAY_SHIFT_CAP * texelWorld * facing, 0.0, NORMAL_OFFSET * texelWorld);
    r.np = min(np + offset, 0.5 * np);
    r.plane = planeIn(r, r.face);

    // 1. Blocker search.
    float blockerDepth = 0.0, blockerWeight = 0.0;
    int searchSamples = int(pcss.params.x);
#ifndef DEEP_SHADOW_MAP
    // Texels in front of P's plane are PCSS's blockers, but the search region is wide (a lamp
    // in a room: most of a face), and a texel in it may lie beside P's pyramid to the light (a
    // wall beside a lit floor): blockers hide nothing unless one of them lies in the pyramid
    // (inPyramid, `confirmed`). A blocker deeper than the search plane may be met by the
    // search's ray from the light's centre only past the pyramid; where none was confirmed, the
    // search runs again at the deepest such texel's depth: a ray through that plane's region
    // meets whatever it meets nearer the light inside the pyramid (which is convex and holds
    // the light's centre), so a blocker that hides part of the light there is confirmed, and a
    // surface beside the pyramid is not. Where a blocker is confirmed, PCSS as before.
    float confirmed = 0.0, candidateDepth = 0.0;
#endif
    for (int i = 0; i < searchSamples; ++i) {
        vec2 m = throughLight(r, pcss.pattern[i].zw, zSearch);
        Texels x = texelsAround(r, m);
        vec4 w = x.weight * inFront(x);
        vec4 depth = x.scale * zNear / max(x.d, 1e-30);
        blockerDepth += dot(w, depth);
        blockerWeight += dot(w, vec4(1.0));
#ifndef DEEP_SHADOW_MAP
        vec4 pyramid = inPyramid(r, m, x);
        confirmed += dot(w, pyramid);
        vec4 outside = mix(vec4(0.0), depth, greaterThan(w * (1.0 - pyramid), vec4(0.0)));
        candidateDepth = max(candidateDepth, max(max(outside.x, outside.y), max(outside.z, outside.w)));
#endif
    }
#ifndef DEEP_SHADOW_MAP
    if (blockerWeight > 0.0 && confirmed == 0.0) {
        float zAgain = clamp(candidateDepth, zSearch, r.z);
        for (int i = 0; i < searchSamples; ++i) {
            vec2 m = throughLight(r, pcss.pattern[i].zw, zAgain);
            Texels x = texelsAround(r, m);
            confirmed += dot(x.weight * inFront(x), inPyramid(r, m, x));
        }
        if (confirmed == 0.0) {
            atomicAdd(stats.unconfirmed, 1u);
            return 1.0;
        }
    }
#endif
    if (blockerWeight == 0.0) return 1.0;
    // No umbra shortcut (every search sample blocked: V = 0 without filtering, the usual one):
    // a wide search region around a lamp in a room finds walls in front of the floor's plane
    // that hide none of the light, and the shortcut drew their false umbra on a lit floor
    // (kaos2's first spawn view with the lamp: 0.071 mean with it, 0.0067 without); the filter
    // region, smaller, does not reach them. The shortcut made the lookup 20-50 % faster on the
    // data scenes, without changing V there.
    float zBlocker = max(blockerDepth / blockerWeight, 1.01 * lightDepth);

    // 2. Penumbra width; 3. filtering.
    int filterSamples = int(pcss.params.y);
    float lit = 0.0;
    for (int i = 0; i < filterSamples; ++i) {
        Texels x = texelsAround(r, throughLight(r, pcss.pattern[i].xy, zBlocker));
        lit += dot(x.weight, vec4(1.0) - inFront(x));
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
#ifdef HORIZON_ONLY
    // A tile no reach box's sweep meets (PcssShadow::drawLookupOverTiles): the horizon alone.
    oVisibility = clamp(horizonFraction(position.xyz, texelFetch(tNormal, px, 0).xyz), 0.0, 1.0);
    return;
#endif
#ifdef OUTSIDE_OCCLUSION
    if (occlusionCovers(position.xyz)) discard;
    atomicAdd(stats.fallback, 1u);
#endif
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
