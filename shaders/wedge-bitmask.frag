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
#include "shared/WedgeHull.h"

layout(early_fragment_tests) in;

layout(binding = TEXUNIT_POSITION) uniform sampler2D tPosition;
layout(binding = TEXUNIT_NORMAL) uniform sampler2D tNormal;
layout(std430, binding = BINDING_LIGHT_SAMPLES) readonly buffer LightSamples {
    vec4 lightSamples[]; // (s, t, angle about the centre, 0), by angle (geometry/shadow/LightMask.h)
};
#define LIGHT_SAMPLE(i) lightSamples[i]

#include "lib/BitmaskEdge.glsl"

flat in vec4 vE0;
flat in vec4 vE1;
flat in vec4 vPlanes[4];
flat in uint vBounded;
#ifdef BITMASK_POTENTIAL
flat in vec4 vTri0[2];
flat in vec4 vTri1[2];
// The edge's share of A_q = (1/|L_q|) integral of D over quadrant q of the light, per quadrant:
// m_P(e) times the share of the quadrant in R (regionQuadrantCoverage of the R the samples
// take; their mean is edgeCoverage's), summed over the wedges by additive blending.
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

void main() {
    ivec2 px = ivec2(gl_FragCoord.xy);
    vec4 position = texelFetch(tPosition, px, 0);
    if (position.w == 0.0) discard; // no surface
#ifdef BITMASK_POTENTIAL
    vec3 p = potentialReceiver(position.xyz, texelFetch(tNormal, px, 0).xyz);
#else
    vec3 p = position.xyz;
#endif
    if (vBounded != 0u && !wedgeHullContains(vPlanes, p)) discard;
    CoverageLight light;
    vec3 h0, h1, h2;
    float sg;
    uint words[8];
    uint any;
#ifdef BITMASK_POTENTIAL
    int m;
    if (!bitmaskEdge(px, p, vE0.xyz, vE1.xyz, vTri0, vTri1, m, light, h0, h1, h2, sg, words, any))
        discard;
    oArea = float(m) * regionQuadrantCoverage(h0, h1, h2);
    if (any != 0u) {
        ivec2 sums = bitmaskChecksums(words);
        imageAtomicAdd(iCounts, ivec3(px, BITMASK_SAMPLES / 8), uint(m * sums.x));
        imageAtomicAdd(iCounts, ivec3(px, BITMASK_SAMPLES / 8 + 1), uint(m * sums.y));
    }
    for (int w = 0; w < BITMASK_WORDS; ++w) {
        for (int k = 0; k < 4; ++k) {
            uint lanes = (words[w] >> uint(8 * k)) & 0xFFu;
            if (lanes == 0u) continue;
            imageAtomicAdd(iCounts, ivec3(px, 4 * w + k), uint(m) * bitmaskLanes(lanes));
        }
    }
#else
    if (!bitmaskEdge(px, p, vE0.xyz, vE1.xyz, light, h0, h1, h2, sg, words, any)) discard;
    if (any == 0u) discard; // XOR with nothing
#ifdef BITMASK_COUNTS
    bool positive = (dot(light.n, p - light.c) > 0.0) == (sg > 0.0);
    for (int w = 0; w < BITMASK_WORDS; ++w) {
        for (int k = 0; k < 4; ++k) {
            uint lanes = (words[w] >> uint(8 * k)) & 0xFFu;
            if (lanes == 0u) continue;
            uint spread = bitmaskLanes(lanes);
            imageAtomicAdd(iCounts, ivec3(px, 4 * w + k), positive ? spread : 0u - spread);
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
