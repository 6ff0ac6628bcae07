// wedges-bitmask, per wedge fragment: the G-buffer point P, the hull planes as an early out,
// then the light samples the edge's region R holds (shared/LightMask.h), XORed into the group's
// mask by the fixed-function logic op (WedgePass::Output::Bitmask): the order of the edges does
// not matter and nothing is read back. Samples: the light-samples buffer (geometry
// lightMaskPattern, ordered by angle about the centre: only the run between the region's rays is
// tested), shifted per pixel with BITMASK_ROTATED (then all of them). Words 0-3 in target 0, 4-7 in
// target 1 (256 samples). BITMASK_COUNTS: signed counts by image atomics instead (combine=counts).
// BITMASK_POTENTIAL (silhouettes=potential): the edge's m_P(e) from its triangles, added to the
// counts of R's samples, m_P(e) times R's share of each quadrant into an RGBA float target, and
// checksums of the adds.
#include "lib/Bindings.h"
#include "shared/Coverage.h"
#include "shared/LightMask.h"
#include "shared/Parts.h"
#include "shared/WedgeHull.h"

layout(early_fragment_tests) in;

layout(binding = TEXUNIT_POSITION) uniform sampler2D tPosition;
layout(std430, binding = BINDING_LIGHT_SAMPLES) readonly buffer LightSamples {
    vec4 lightSamples[]; // (s, t, angle about the centre, 0), by angle (geometry/shadow/LightMask.h)
};

// The first sample whose angle is >= a (BITMASK_SAMPLES when none).
int firstAtOrAfter(float a) {
    int lo = 0;
    int hi = BITMASK_SAMPLES;
    while (lo < hi) {
        int mid = (lo + hi) >> 1;
        if (lightSamples[mid].z < a)
            lo = mid + 1;
        else
            hi = mid;
    }
    return lo;
}

flat in vec4 vE0;
flat in vec4 vE1;
flat in vec4 vPlanes[4];
flat in uint vBounded;
#ifdef BITMASK_POTENTIAL
flat in vec4 vTri0[3];
flat in vec4 vTri1[3];
// The edge's share of A_q = (1/|L_q|) integral of D over quadrant q of the light, per quadrant:
// m_P(e) times the share of the quadrant in R (edgeQuadrantCoverage; their mean is
// edgeCoverage's), summed over the wedges by additive blending.
layout(location = 0) out vec4 oArea;
#endif
#if defined(BITMASK_COUNTS) || defined(BITMASK_POTENTIAL)
// combine=counts: per sample a 4-bit count biased by 8, eight to a layer; the edge adds its sign
// (edgeCoverage's) to the samples R holds by atomic adds, which never carry between counts
// while each stays in [-8, 7] relative to the bias.
layout(binding = IMAGE_GROUP_COUNTS, r32ui) uniform coherent uimage2DArray iCounts;
#else
layout(location = 0) out uvec4 oMask0;
#if BITMASK_WORDS > 4
layout(location = 1) out uvec4 oMask1;
#endif
#endif

#ifdef BITMASK_POTENTIAL
// One triangle's share of m_P(e): +1 when its third vertex lies on the far side of the plane
// through P and the edge from the light centre (crossing the edge's projection, a segment from P
// starts crossing the triangle), -1 on the centre's side (it stops), 0 without a triangle.
// sc: the centre's side, as sign(orient(P, e0, e1, c)). orient(P, a, b, c) = dot(a - P,
// (b - a) x (c - a)): the plane's normal from the triangle alone, so that far small triangles
// keep their sign. P in the triangle's plane (within float noise: P's own triangle, a coplanar
// neighbour) is taken a little towards the camera, as the stencil's polygon offset takes it
// (the visible side of a two-sided surface): the orientation of the eye instead.
// (triangleSide: the sign of orient(P, e0, e1, apex); triangleShare: its share given sc.)
int triangleSide(vec4 t[3], vec3 p) {
    if (t[0].w == 0.0) return 0;
    vec3 a = t[0].xyz;
    vec3 n = cross(t[1].xyz - a, t[2].xyz - a);
    float d = t[0].w * dot(a - p, n);
    float tol = 4e-6 * length(n) * (length(a - p) + length(p));
    if (!(abs(d) > tol)) {
        vec3 eye = frame.eye.xyz;
        d = t[0].w * dot(a - eye, n);
        if (!(abs(d) > 4e-6 * length(n) * (length(a - eye) + length(eye)))) return 0;
    }
    return d > 0.0 ? 1 : -1;
}
int triangleShare(int side, float sc) {
    return side == 0 ? 0 : (side > 0) == (sc < 0.0) ? 1 : -1;
}
#endif

void main() {
    ivec2 px = ivec2(gl_FragCoord.xy);
    vec4 position = texelFetch(tPosition, px, 0);
    if (position.w == 0.0) discard; // no surface
    vec3 p = position.xyz;
    if (vBounded != 0u && !wedgeHullContains(vPlanes, p)) discard;
#ifdef BITMASK_POTENTIAL
    // The two triangles on opposite sides of the plane through P and the edge: no silhouette
    // seen from P, m = 0 whatever the centre's side (most fragments of most potential edges):
    // before the projection.
    int side0 = triangleSide(vTri0, p);
    int side1 = triangleSide(vTri1, p);
    if (side0 == -side1) discard;
#endif
    CoverageLight light;
    light.c = frame.lightCenter.xyz;
    light.u = frame.lightU.xyz;
    light.v = frame.lightV.xyz;
    light.n = frame.lightN.xyz;
    light.uStar = frame.lightUStar.xyz;
    light.vStar = frame.lightVStar.xyz;
    vec3 h0, h1, h2;
    float sg;
    if (!edgeRegion(p, vE0.xyz, vE1.xyz, light, h0, h1, h2, sg)) discard;
#ifdef BITMASK_POTENTIAL
    // The centre's side of the plane through P and the edge: -sign(cr) sign(hp) from the same
    // projection that bounds R (R lies on the far side), so the two cannot disagree.
    float hp = dot(light.n, p - light.c);
    float sc = hp > 0.0 ? -sg : sg;
    int m = triangleShare(side0, sc) + triangleShare(side1, sc);
    if (m == 0) discard; // no silhouette seen from P: D does not change across it
#endif
    uint words[8] = uint[8](0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u);
    uint any = 0u;
#ifdef BITMASK_ROTATED
    // Shifted per pixel, the samples are in no order: every one is tested.
    vec2 shift = maskPixelShift(px);
    for (int w = 0; w < BITMASK_WORDS; ++w) {
        uint bits = 0u;
        for (int b = 0; b < 32; ++b) {
            vec2 y = maskShifted(lightSamples[32 * w + b].xy, shift);
            if (regionHolds(h0, h1, h2, sg, y)) bits |= 1u << uint(b);
        }
        words[w] = bits;
        any |= bits;
    }
#else
    // The samples between the rays are a run of the angle-ordered pattern: from the first at
    // or after the sector's start, counter-clockwise, to the first at or after its end (a
    // sample on the start ray is in, on the end ray out: regionHolds' rule). The sector is
    // under pi: a span near 2 pi is the rounding of a sector of almost nothing (empty), one a
    // little over pi that of a sector of almost pi (the edge's line passing by the centre).
    // The rays' directions from their half-planes (h0 = sg (-q0.y, q0.x), h1 = sg (q1.y, -q1.x),
    // exact): counter-clockwise from q0 to q1 when sg > 0, from q1 to q0 otherwise.
    vec2 q0 = sg * vec2(h0.y, -h0.x);
    vec2 q1 = sg * vec2(-h1.y, h1.x);
    vec2 r0 = sg > 0.0 ? q0 : q1; // the start ray's direction
    vec2 r1 = sg > 0.0 ? q1 : q0; // the end ray's
    float from = atan(r0.y, r0.x);
    float to = atan(r1.y, r1.x);
    float span = to - from;
    if (span < 0.0) span += 6.28318530718;
    if (span > 4.71238898038) discard; // over 3 pi / 2: empty
    int first = firstAtOrAfter(from);
    int count = firstAtOrAfter(to) - first;
    if (count < 0) count += BITMASK_SAMPLES;
    for (int k = 0; k < count; ++k) {
        int i = (first + k) & (BITMASK_SAMPLES - 1);
        vec2 y = lightSamples[i].xy;
        if (dot(h2, vec3(y, 1.0)) >= 0.0) words[i >> 5] |= 1u << uint(i & 31);
    }
    for (int w = 0; w < BITMASK_WORDS; ++w) any |= words[w];
#endif
#ifdef BITMASK_POTENTIAL
    oArea = float(m) * abs(edgeQuadrantCoverage(p, vE0.xyz, vE1.xyz, light));
    if (any != 0u) {
        // Checksums of the adds (wedges-bitmask.md): the sum over samples of the added counts,
        // and the same weighted by 1 + the count's place in its 32-bit word, which the resolve
        // compares with the decoded counts: a count past [-8, 7] carries into its neighbour (or
        // out of the word) and changes them.
        int added = 0, weighted = 0;
        for (int w = 0; w < BITMASK_WORDS; ++w) {
            uint x = words[w];
            for (int k = 0; k < 4; ++k) {
                uint b = (x >> uint(8 * k)) & 0xFFu;
                int c = bitCount(b);
                added += c;
                weighted += c + bitCount(b & 0xAAu) + 2 * bitCount(b & 0xCCu) + 4 * bitCount(b & 0xF0u);
            }
        }
        imageAtomicAdd(iCounts, ivec3(px, BITMASK_SAMPLES / 8), uint(m * added));
        imageAtomicAdd(iCounts, ivec3(px, BITMASK_SAMPLES / 8 + 1), uint(m * weighted));
    }
    for (int w = 0; w < BITMASK_WORDS; ++w) {
        for (int k = 0; k < 4; ++k) {
            uint lanes = (words[w] >> uint(8 * k)) & 0xFFu;
            if (lanes == 0u) continue;
            lanes = (lanes | (lanes << 12u)) & 0x000F000Fu;
            lanes = (lanes | (lanes << 6u)) & 0x03030303u;
            lanes = (lanes | (lanes << 3u)) & 0x11111111u;
            imageAtomicAdd(iCounts, ivec3(px, 4 * w + k), uint(m) * lanes);
        }
    }
#else
    if (any == 0u) discard; // XOR with nothing
#ifdef BITMASK_COUNTS
    bool positive = (dot(light.n, p - light.c) > 0.0) == (sg > 0.0);
    for (int w = 0; w < BITMASK_WORDS; ++w) {
        for (int k = 0; k < 4; ++k) {
            uint lanes = (words[w] >> uint(8 * k)) & 0xFFu;
            if (lanes == 0u) continue;
            // Bit j of the byte to bit 4 j: a 1 in each count whose sample R holds.
            lanes = (lanes | (lanes << 12u)) & 0x000F000Fu;
            lanes = (lanes | (lanes << 6u)) & 0x03030303u;
            lanes = (lanes | (lanes << 3u)) & 0x11111111u;
            imageAtomicAdd(iCounts, ivec3(px, 4 * w + k), positive ? lanes : 0u - lanes);
        }
    }
#else
    oMask0 = uvec4(words[0], words[1], words[2], words[3]);
#if BITMASK_WORDS > 4
    oMask1 = uvec4(words[4], words[5], words[6], words[7]);
#endif
#endif
#endif
}
