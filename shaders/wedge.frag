// Wedge pass, per fragment: the G-buffer point P, the wedge's hull planes as an early out, then
// the signed light coverage of the edge (Assarsson & Akenine-Möller 2003; the arithmetic of
// geometry::edgeCoverage, shaders/lib/Coverage.glsl), written for subtractive blending:
// V = V_hard(centre) - sum over the edges' coverage.
#include "lib/Bindings.h"
#include "lib/Coverage.glsl"

// The depth test (hull exit behind the surface) runs before the shader: no depth is written.
layout(early_fragment_tests) in;

layout(binding = TEXUNIT_POSITION) uniform sampler2D tPosition;

flat in vec4 vE0;
flat in vec4 vE1;
flat in vec4 vPlanes[4];
flat in uint vBounded;
layout(location = 0) out float oCoverage;

void main() {
    vec4 position = texelFetch(tPosition, ivec2(gl_FragCoord.xy), 0);
    if (position.w == 0.0) discard; // no surface
    vec3 p = position.xyz;
    if (vBounded != 0u) {
        // Float slack on the conservative side: the coverage below is exactly zero outside.
        float slack = 1e-5 * (1.0 + length(p));
        for (int i = 0; i < 4; ++i)
            if (dot(vPlanes[i].xyz, p) + vPlanes[i].w > slack) discard;
    }
    float c = edgeCoverage(p, vE0.xyz, vE1.xyz, frame.lightCenter.xyz, frame.lightN.xyz,
                           frame.lightUStar.xyz, frame.lightVStar.xyz);
    if (c == 0.0) discard;
    oCoverage = c;
}
