// wedges-bitmask, per wedge fragment: the G-buffer point P, the hull planes as an early out,
// then the light samples the edge's region R holds (lib/LightMask.glsl), XORed into the group's
// mask by the fixed-function logic op (WedgePass::Output::Bitmask): the order of the edges does
// not matter and nothing is read back. Samples: the light-samples buffer (geometry
// lightMaskPattern), shifted per pixel with BITMASK_ROTATED. Words 0-3 in target 0, 4-7 in
// target 1 (256 samples).
#include "lib/Bindings.h"
#include "lib/Coverage.glsl"
#include "lib/LightMask.glsl"
#include "lib/WedgeHull.glsl"

layout(early_fragment_tests) in;

layout(binding = TEXUNIT_POSITION) uniform sampler2D tPosition;
layout(std430, binding = BINDING_LIGHT_SAMPLES) readonly buffer LightSamples {
    vec2 lightSamples[];
};

flat in vec4 vE0;
flat in vec4 vE1;
flat in vec4 vPlanes[4];
flat in uint vBounded;
layout(location = 0) out uvec4 oMask0;
#if BITMASK_WORDS > 4
layout(location = 1) out uvec4 oMask1;
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
#ifdef BITMASK_ROTATED
    vec2 shift = maskPixelShift(px);
#endif
    uint words[8] = uint[8](0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u);
    uint any = 0u;
    for (int w = 0; w < BITMASK_WORDS; ++w) {
        uint bits = 0u;
        for (int b = 0; b < 32; ++b) {
            vec2 y = lightSamples[32 * w + b];
#ifdef BITMASK_ROTATED
            y = maskShifted(y, shift);
#endif
            if (regionHolds(h0, h1, h2, sg, y)) bits |= 1u << uint(b);
        }
        words[w] = bits;
        any |= bits;
    }
    if (any == 0u) discard; // XOR with nothing
    oMask0 = uvec4(words[0], words[1], words[2], words[3]);
#if BITMASK_WORDS > 4
    oMask1 = uvec4(words[4], words[5], words[6], words[7]);
#endif
}
