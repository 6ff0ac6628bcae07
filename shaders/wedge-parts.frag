// Wedge pass of wedges-blend, per fragment: what one directed silhouette edge adds to its group's
// per-part state at the G-buffer point P (the four quadrants of the light; geometry/BlendModel.h,
// shaders/lib/Parts.glsl). Every output is a sum or a minimum, so fixed-function blending
// accumulates them in any fragment order with no read-modify-write:
// - oCoverage (ADD): the signed coverage of each quadrant;
// - oWinding0..2 (ADD): for each quadrant its corners 1, 2, 3 in R_e (±1), 12 values in order;
// - oBounds0..3 (MIN): each quadrant's clipped edge bounds as (min x, min y, -max x, -max y).
#include "lib/Bindings.h"
#include "lib/Coverage.glsl"
#include "lib/Parts.glsl"
#include "lib/WedgeHull.glsl"

layout(early_fragment_tests) in;

layout(binding = TEXUNIT_POSITION) uniform sampler2D tPosition;

flat in vec4 vE0;
flat in vec4 vE1;
flat in vec4 vPlanes[4];
flat in uint vBounded;

layout(location = 0) out vec4 oCoverage;
layout(location = 1) out vec4 oWinding0;
layout(location = 2) out vec4 oWinding1;
layout(location = 3) out vec4 oWinding2;
layout(location = 4) out vec4 oBounds0;
layout(location = 5) out vec4 oBounds1;
layout(location = 6) out vec4 oBounds2;
layout(location = 7) out vec4 oBounds3;

vec4 minForm(vec4 b) { return vec4(b.xy, -b.zw); }

void main() {
    vec4 position = texelFetch(tPosition, ivec2(gl_FragCoord.xy), 0);
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
    EdgeParts4 e = edgeParts4(p, vE0.xyz, vE1.xyz, light);
    oCoverage = e.coverage;
    oWinding0 = vec4(e.windings[0], e.windings[1].x);
    oWinding1 = vec4(e.windings[1].yz, e.windings[2].xy);
    oWinding2 = vec4(e.windings[2].z, e.windings[3]);
    oBounds0 = minForm(e.bounds[0]);
    oBounds1 = minForm(e.bounds[1]);
    oBounds2 = minForm(e.bounds[2]);
    oBounds3 = minForm(e.bounds[3]);
}
