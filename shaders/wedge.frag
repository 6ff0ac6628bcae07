// Wedge pass, per fragment: the G-buffer point P, the wedge's hull planes as an early out, then
// the signed light coverage of the edge (Assarsson & Akenine-Möller 2003; the arithmetic of
// geometry::edgeCoverage, shaders/shared/Coverage.h), written for subtractive blending:
// V = V_hard(centre) - sum over the edges' coverage.
#include "lib/Bindings.h"
#include "shared/Coverage.h"
#include "shared/WedgeHull.h"

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
    // The hull's planes carry their own float margins (geometry/shadow/WedgeHull.h); the coverage
    // below is zero outside the exact wedge anyway.
    if (vBounded != 0u && !wedgeHullContains(vPlanes, p)) discard;
    CoverageLight light;
    light.c = frame.lightCenter.xyz;
    light.u = frame.lightU.xyz;
    light.v = frame.lightV.xyz;
    light.n = frame.lightN.xyz;
    light.uStar = frame.lightUStar.xyz;
    light.vStar = frame.lightVStar.xyz;
    float c = edgeCoverage(p, vE0.xyz, vE1.xyz, light);
    if (c == 0.0) discard;
    oCoverage = c;
}
