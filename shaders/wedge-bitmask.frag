// wedges-bitmask, per wedge fragment: the G-buffer point P, the hull planes as an early out,
// then the light samples the edge's region R holds (shared/LightMask.h), XORed into the group's
// mask by the fixed-function logic op (WedgePass::Output::Bitmask): the order of the edges does
// not matter and nothing is read back. Samples: the light-samples buffer (geometry
// lightMaskPattern, ordered by angle about the centre: only the run between the region's rays is
// tested), shifted per pixel with BITMASK_ROTATED (then all of them). Words 0-3 in target 0, 4-7 in
// target 1 (256 samples).
#include "lib/Bindings.h"
#include "shared/Coverage.h"
#include "shared/LightMask.h"
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
#ifdef BITMASK_COUNTS
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

void main() {
    ivec2 px = ivec2(gl_FragCoord.xy);
    vec4 position = texelFetch(tPosition, px, 0);
    if (position.w == 0.0) discard; // no surface
    vec3 p = position.xyz;
    if (vBounded != 0u && !wedgeHullContains(vPlanes, p)) discard;
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
}
