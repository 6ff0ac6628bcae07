// sample-maps, lookup: V at each G-buffer point P = the share of the N light samples from which
// P is seen (geometry/shadow/SampleMapFrame.h). For sample y_i:
// - hidden by P's own surface where y_i lies behind P's plane (the G-buffer's facet normal,
//   facing the viewer), as `raytrace` counts it (OWN_PLANE, plane=on; without it, in auto's
//   composition whose wedge path counts the plane, such a sample is tested against the maps
//   like any other);
// - else P is moved OFFSET_FLOOR + bias sin(a) map texels (their world size at P's depth
//   from y_i; a the angle between the normal and the direction to y_i) along that normal,
//   towards y_i: a plane tilted by a from the ray changes depth by tan(a) texels per texel,
//   which the bilinear footprint of one texel and the texel centres' half texel must clear; and
//   compared with map i: hidden where the map holds a surface
//   nearer to y_i along P's ray (its depth zNear / z above P's by the share DEPTH_BIAS), with
//   the 2 x 2 texels around P's ray weighted bilinearly (the comparison sampler), so that V
//   changes continuously as P moves. Outside the map's extent or nearer to the light than every
//   caster, lit.
// A receiver in reach whose pyramid to the light holds no caster is lit from every sample in
// front of its plane too (EARLY_OUT, early_out=on): a caster point X on a segment from P to a
// light point y, at depth z_X in [zNear, z_P] along n, lies in map k (the sample y_k nearest
// the centre) at m_k(X) = m_k(P) + s (d_y - d_k), s = 1 / z_X - 1 / z_P in
// [0, 1 / zNear - 1 / z_P] (d: the samples' lateral offsets): within the rectangle from m_k(P)
// spanned by s times the range of d_y - d_k over the samples, per axis, and map k holds X or a
// caster nearer to y_k (zNear / z >= zNear / z_X). So where the largest stored value over that
// rectangle (its max N-buffer, four reads) — with z_P the offset receiver's largest depth zHi,
// widened by the offset's shift and the texels' footprints — is below zNear / zHi, no sample's
// 2 x 2 texels can hide the receiver and the loop would count every sample in front of the
// plane lit. Where it is not, the same test runs for each quadrant of the light (the range of
// that quadrant's samples), and a quadrant whose pyramid is empty skips its samples' maps. A
// receiver whose own texel of map k holds a caster at its depth (a leaf, on a tree) fails every
// such test, so one read of that texel skips them. Exact up to the maps' rasterisation: a
// sliver that covers a texel centre of map i but none of map k's within the margin is missed
// (tests/gpu/SampleMapsMethodTest.cpp counts differing pixels). Counted: SAMPLE_MAP_STAT_*.
// LINEAR_LIGHTS (linear-light-sm, Heidrich, Brabec & Seidel 2000): the samples are the end
// points of parallel linear lights, two per light (2k and 2k + 1), and each counts with its
// weight: twice its skin layer's value at P's texel (linear-light-skin.frag: the visibility ramp
// where only this end point sees P) or, without a skin there, 1 (the paper's 0.5 per end point:
// both end points seeing P make 1). V = the mean over the linear lights.
// A receiver outside the frame's reach (geometry::inReach, the same test: from the light's
// centre, the casters' extent widened by the light's half extent times the spread of 1 / z
// between the receiver and the casters) is lit from every sample in front of its plane: only
// that test is made.
#include "lib/Bindings.h"

layout(binding = TEXUNIT_POSITION) uniform sampler2D tPosition;
layout(binding = TEXUNIT_NORMAL) uniform sampler2D tNormal;
layout(binding = TEXUNIT_SAMPLE_MAPS) uniform sampler2DArray tMaps; // zNear / z; 0: nothing
#ifdef LINEAR_LIGHTS
layout(binding = TEXUNIT_LINEAR_SKINS) uniform sampler2DArray tSkins; // ramp; > 1.5: no skin
#endif

#ifdef EARLY_OUT
layout(binding = TEXUNIT_SAMPLE_MAP_NBUFFER) uniform sampler2DArray tNBuffer; // layer = level
layout(std430, binding = BINDING_SAMPLE_MAP_STATS) buffer SampleMapStats {
    uint sampleMapStats[SAMPLE_MAP_STAT_COUNT];
};
#endif

layout(std430, binding = BINDING_SAMPLE_MAP_VIEWS) readonly buffer SampleMapViews {
    vec4 views[]; // per sample: (s, t, its lateral offset from the centre), (lo, 1 / (hi - lo))
};

layout(location = 0) out float oVisibility;

#define DEPTH_BIAS 1e-3
#ifndef OFFSET_FLOOR
#define OFFSET_FLOOR 0.25
#endif

#ifdef EARLY_OUT
// P in map k, once per pixel for every test below.
struct MapK {
    vec2 m;        // m_k(P)
    vec4 window;   // map k's lo (xy), 1 / (hi - lo) (zw)
    float zHi;     // the offset receiver's largest depth
    float reach;   // 1 / zNear - 1 / zHi: the range of s = 1 / z_X - 1 / z_P
    float margin;  // the offset's shift and the texels' footprints, in map coordinates
    float nearest; // zNear / zHi: a stored value at least this may hide the receiver
};

MapK mapK(vec2 lateral, float zP, float zNear) {
    int k = int(sampleMaps.emptyTest.x);
    MapK q;
    q.m = (lateral - views[2 * k].zw) / zP;
    q.window = views[2 * k + 1];
    q.zHi = zP * (1.0 + sampleMaps.emptyTest.z);
    q.reach = max(1.0 / zNear - 1.0 / q.zHi, 0.0);
    q.margin = sampleMaps.emptyTest.z * (1.0 + length(q.m)) / (1.0 - sampleMaps.emptyTest.z) +
               sampleMaps.emptyTest.w;
    q.nearest = zNear / q.zHi;
    return q;
}

// Whether the largest stored value over the rectangle of map k that holds the segments from P
// to the light points y with d_y - d_k in [offLo, offHi] (see above) may hide the offset
// receiver from one of them.
bool pyramidMayHoldCaster(MapK q, vec2 offLo, vec2 offHi) {
    int levels = int(sampleMaps.emptyTest.y);
    float R = sampleMaps.params.y;
    vec2 lo = (q.m + min(offLo * q.reach, 0.0) - q.margin - q.window.xy) * q.window.zw;
    vec2 hi = (q.m + max(offHi * q.reach, 0.0) + q.margin - q.window.xy) * q.window.zw;
    if (any(lessThan(hi, vec2(0.0))) || any(greaterThan(lo, vec2(1.0))))
        return false; // beyond the map: no caster there
    ivec2 i0 = ivec2(floor(clamp(lo, 0.0, 1.0) * R));
    ivec2 i1 = ivec2(floor(clamp(hi, 0.0, 1.0) * R));
    i0 = min(i0, ivec2(int(R) - 1));
    i1 = min(i1, ivec2(int(R) - 1));
    ivec2 span = i1 - i0 + 1;
    int level = min(findMSB(max(span.x, span.y)), levels - 1); // 2^level <= the longer side
    int w = 1 << level;
    ivec2 j = max(i1 - w + 1, ivec2(0)); // windows [i0, i0 + w) and [j, j + w) cover [i0, i1]
    float d = max(max(texelFetch(tNBuffer, ivec3(i0, level), 0).r,
                      texelFetch(tNBuffer, ivec3(j.x, i0.y, level), 0).r),
                  max(texelFetch(tNBuffer, ivec3(i0.x, j.y, level), 0).r,
                      texelFetch(tNBuffer, ivec3(j, level), 0).r));
    return d >= q.nearest;
}

// Whether P's own texel of map k holds a caster at P's depth or nearer (P is a caster itself):
// that texel lies in every rectangle above, so every test would say "may hold".
bool ownTexelHoldsCaster(MapK q) {
    vec2 uv = (q.m - q.window.xy) * q.window.zw;
    if (any(lessThan(uv, vec2(0.0))) || any(greaterThanEqual(uv, vec2(1.0)))) return false;
    return texelFetch(tNBuffer, ivec3(ivec2(uv * sampleMaps.params.y), 0), 0).r >= q.nearest;
}

// The light's quadrant of sample st (st in [-1, 1]^2), as SampleMapsMethod.cpp assigns them.
int sampleQuadrant(vec2 st) {
    return (st.x >= 0.0 ? 1 : 0) + (st.y >= 0.0 ? 2 : 0);
}
#endif

void main() {
    ivec2 px = ivec2(gl_FragCoord.xy);
    vec4 position = texelFetch(tPosition, px, 0);
    int samples = int(sampleMaps.params.x);
    if (position.w == 0.0 || samples == 0) {
        oVisibility = 1.0; // no surface, or no casters
        return;
    }
    vec3 P = position.xyz;
    vec3 N = texelFetch(tNormal, px, 0).xyz;
    float R = sampleMaps.params.y;
    float offsetTexels = sampleMaps.params.z;
    float zNear = sampleMaps.params.w;
    vec3 eu = sampleMaps.eu.xyz, ev = sampleMaps.ev.xyz, n = sampleMaps.n.xyz;
    // Per pixel, so that each sample costs a few scalar operations: sample y = c + s U + t V
    // lies in the light's plane, so P's depth along n is the same from every sample, and its
    // lateral coordinates from y are those from c minus y's offset (views[2i].zw).
    vec3 U = frame.lightU.xyz, V = frame.lightV.xyz;
    vec3 cp = frame.lightCenter.xyz - P;
    float nc = dot(N, cp), nu = dot(N, U), nv = dot(N, V); // dot(N, y - P) = nc + s nu + t nv
    float cu = dot(cp, U), cv = dot(cp, V), cc = dot(cp, cp);
    float uu = dot(U, U), vv = dot(V, V), uvDot = dot(U, V);
    float zP = -dot(cp, n);
    vec2 lateral = -vec2(dot(cp, eu), dot(cp, ev));
    vec3 Nm = vec3(dot(N, eu), dot(N, ev), dot(N, n));
    vec2 mc = lateral / zP;
    float spread = max(abs(1.0 / zP - 1.0 / zNear), abs(1.0 / zP - sampleMaps.reachSpread.z));
    vec2 slack = 0.01 * (sampleMaps.reach.zw - sampleMaps.reach.xy) +
                 sampleMaps.reachSpread.xy * spread;
    bool inReach = sampleMaps.reachSpread.w != 0.0 ||
                   (zP > zNear && all(greaterThanEqual(mc, sampleMaps.reach.xy - slack)) &&
                    all(lessThanEqual(mc, sampleMaps.reach.zw + slack)));
    // Every sample in front of P's plane, or every one behind (the light's corners decide):
    // outside the reach V is then 1 or 0 without the loop.
    float leastFacing = nc - abs(nu) - abs(nv), mostFacing = nc + abs(nu) + abs(nv);
#ifdef OWN_PLANE
    if (!inReach && (leastFacing > 0.0 || mostFacing <= 0.0)) {
        oVisibility = leastFacing > 0.0 ? 1.0 : 0.0;
        return;
    }
#else
    if (!inReach) {
        oVisibility = 1.0;
        return;
    }
#endif
#ifdef EARLY_OUT
    // The whole light first, then (where some caster may lie in the pyramid) each quadrant's:
    // the samples of a quadrant whose pyramid holds no caster are lit without their maps.
    // As a loop with a per-pixel bound (0: no test), so that llvmpipe, which runs both sides of
    // a branch under a lane mask, skips the tests where no pixel of a SIMD group makes them.
    uint emptyQuadrants = 0u;
    MapK q = mapK(lateral, zP, zNear);
    int tests = inReach && sampleMaps.emptyTest.y > 0.0 && !ownTexelHoldsCaster(q) ? 5 : 0;
    for (int t = 0; t < tests; ++t) {
        vec2 lo, hi;
        if (t == 0) { // the whole light: the range over the four quadrants
            lo = min(min(sampleMaps.emptyQuadrant[0].xy, sampleMaps.emptyQuadrant[1].xy),
                     min(sampleMaps.emptyQuadrant[2].xy, sampleMaps.emptyQuadrant[3].xy));
            hi = max(max(sampleMaps.emptyQuadrant[0].zw, sampleMaps.emptyQuadrant[1].zw),
                     max(sampleMaps.emptyQuadrant[2].zw, sampleMaps.emptyQuadrant[3].zw));
        } else {
            lo = sampleMaps.emptyQuadrant[t - 1].xy;
            hi = sampleMaps.emptyQuadrant[t - 1].zw;
        }
        if (!pyramidMayHoldCaster(q, lo, hi)) {
            if (t == 0) {
                emptyQuadrants = 15u;
                break;
            }
            emptyQuadrants |= 1u << uint(t - 1);
        }
    }
    // (Four empty quadrants make an empty light even where the whole light's rectangle, their
    // bounding box, holds a caster.)
    if (emptyQuadrants != 0u)
        atomicAdd(sampleMapStats[emptyQuadrants == 15u ? SAMPLE_MAP_STAT_EMPTY
                                                       : SAMPLE_MAP_STAT_QUADRANTS],
                  1u);
    if (emptyQuadrants == 15u) {
#ifdef OWN_PLANE
        float front = 0.0;
        for (int i = 0; i < samples; ++i) {
            vec2 st = views[2 * i].xy;
            front += nc + st.x * nu + st.y * nv > 0.0 ? 1.0 : 0.0;
        }
        oVisibility = front / float(samples);
#else
        oVisibility = 1.0;
#endif
        return;
    }
#endif
    float lit = 0.0;
    for (int i = 0; i < samples; ++i) {
        vec4 a = views[2 * i]; // s, t, y's lateral offset from c
        float facing = nc + a.x * nu + a.y * nv;
#ifdef OWN_PLANE
        if (facing <= 0.0) continue; // behind P's own plane
#endif
        if (!inReach) {
            lit += 1.0;
            continue;
        }
#ifdef EARLY_OUT
        if ((emptyQuadrants & (1u << uint(sampleQuadrant(a.xy)))) != 0u) {
            lit += 1.0; // no caster in this quadrant's pyramid
            continue;
        }
#endif
        vec4 b = views[2 * i + 1];
        float d2 = cc + 2.0 * (a.x * cu + a.y * cv) + a.x * a.x * uu + a.y * a.y * vv +
                   2.0 * a.x * a.y * uvDot; // |y - P|^2
        float cosA = abs(facing) * inversesqrt(d2);
        float sinA = sqrt(max(1.0 - cosA * cosA, 0.0));
        // The world size of a texel at P's depth, along the map's coarser axis.
        float texelWorld = zP / (R * min(b.z, b.w));
        // Along the normal towards the sample (behind the plane, without OWN_PLANE: away from
        // the viewer's side).
        float offset = (facing > 0.0 ? 1.0 : -1.0) * (OFFSET_FLOOR + offsetTexels * sinA) *
                       max(texelWorld, 0.0);
        float z = zP + offset * Nm.z;
        if (z <= zNear) {
            lit += 1.0; // nearer to the light than every caster
            continue;
        }
        vec2 uv = ((lateral + offset * Nm.xy - a.zw) / z - b.xy) * b.zw;
        if (any(lessThan(uv, vec2(0.0))) || any(greaterThan(uv, vec2(1.0)))) {
            lit += 1.0; // its ray misses the casters' box
            continue;
        }
        // The 2 x 2 texels around P's ray (one textureGather at their shared corner), each lit
        // where P's depth (times 1 + DEPTH_BIAS) >= the stored one, weighted bilinearly.
        vec2 t = uv * R - 0.5;
        vec2 base = floor(t);
        vec2 f = t - base;
        vec4 d = textureGather(tMaps, vec3((base + 1.0) / R, float(i)));
        vec4 w = vec4((1.0 - f.x) * f.y, f.x * f.y, f.x * (1.0 - f.y), (1.0 - f.x) * (1.0 - f.y));
#ifdef LINEAR_LIGHTS
        // The skin's ramp at the same 2 x 2 texels, each seen texel weighted by its own.
        vec4 skin = textureGather(tSkins, vec3((base + 1.0) / R, float(i)));
        vec4 weight = mix(vec4(1.0), 2.0 * skin, vec4(lessThan(skin, vec4(1.5))));
        lit += dot(w * weight, vec4(lessThanEqual(d, vec4((zNear / z) * (1.0 + DEPTH_BIAS)))));
#else
        lit += dot(w, vec4(lessThanEqual(d, vec4((zNear / z) * (1.0 + DEPTH_BIAS)))));
#endif
    }
#ifdef LINEAR_LIGHTS
    // The end points' weights need not sum to at most 1 per linear light (a skin's ramp where
    // both end points see P): V held in [0, 1].
    oVisibility = clamp(lit / float(samples), 0.0, 1.0);
#else
    oVisibility = lit / float(samples);
#endif
}
