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
// A receiver outside the frame's reach (geometry::inReach, the same test: from the light's
// centre, the casters' extent widened by the light's half extent times the spread of 1 / z
// between the receiver and the casters) is lit from every sample in front of its plane: only
// that test is made.
#include "lib/Bindings.h"

layout(binding = TEXUNIT_POSITION) uniform sampler2D tPosition;
layout(binding = TEXUNIT_NORMAL) uniform sampler2D tNormal;
layout(binding = TEXUNIT_SAMPLE_MAPS) uniform sampler2DArray tMaps; // zNear / z; 0: nothing

layout(std430, binding = BINDING_SAMPLE_MAP_VIEWS) readonly buffer SampleMapViews {
    vec4 views[]; // per sample: (s, t, its lateral offset from the centre), (lo, 1 / (hi - lo))
};

layout(location = 0) out float oVisibility;

#define DEPTH_BIAS 1e-3
#ifndef OFFSET_FLOOR
#define OFFSET_FLOOR 0.25
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
        lit += dot(w, vec4(lessThanEqual(d, vec4((zNear / z) * (1.0 + DEPTH_BIAS)))));
    }
    oVisibility = lit / float(samples);
}
