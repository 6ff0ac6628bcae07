// Wedge pass of wedges-blend, per fragment: what one directed silhouette edge adds to its group's
// per-part state at the G-buffer point P (geometry/models/BlendModel.h, shaders/shared/Parts.h), for one
// set of at most four radial parts (gpu/src/methods/BlendWedgesMethod.cpp explains the layout).
// Every output is a sum or a minimum, so fixed-function blending accumulates them in any fragment
// order with no read-modify-write: locations 0-3 by ADD, 4-7 by MIN (WedgePass's state).
// Variants (#defines prepended by the loader; the defaults are the paper's):
//   BLEND_PARTS 1 | 4 | 8  radial parts R (8: two sets, uPartSet selects one)
//   BLEND_CENTROID 0 | 1   first moments too (overlap = centroid)
// Sets of four parts (R = 4, 8):
//   0 oCoverage: per part the signed coverage;  1 oWindings: per part the corner windings as
//   one mixed-radix number (Parts.glsl);  2, 3 oMomentX, oMomentY: per part the signed first
//   moments (centroid only);  4-7 oBounds0..3: per part the clipped edge bounds as
//   (min x, min y, -max x, -max y).
// R = 1: 0 oState = (coverage, windings, moment x, moment y); 4 oBounds0.
#ifndef BLEND_PARTS
#define BLEND_PARTS 4
#endif
#ifndef BLEND_CENTROID
#define BLEND_CENTROID 0
#endif

#include "lib/Bindings.h"
#include "shared/Coverage.h"
#include "shared/Parts.h"
#include "shared/WedgeHull.h"

layout(early_fragment_tests) in;

layout(binding = TEXUNIT_POSITION) uniform sampler2D tPosition;

#if BLEND_PARTS == 8
layout(location = 1) uniform int uPartSet; // parts 4 uPartSet .. 4 uPartSet + 3
#endif

flat in vec4 vE0;
flat in vec4 vE1;
flat in vec4 vPlanes[4];
flat in uint vBounded;

#if BLEND_PARTS == 1
layout(location = 0) out vec4 oState;
layout(location = 4) out vec4 oBounds0;
#else
layout(location = 0) out vec4 oCoverage;
layout(location = 1) out vec4 oWindings;
#if BLEND_CENTROID
layout(location = 2) out vec4 oMomentX;
layout(location = 3) out vec4 oMomentY;
#endif
layout(location = 4) out vec4 oBounds0;
layout(location = 5) out vec4 oBounds1;
layout(location = 6) out vec4 oBounds2;
layout(location = 7) out vec4 oBounds3;
#endif

vec4 minForm(vec4 b) { return vec4(b.xy, -b.zw); }

// Corner windings 1, 2, 3 of a quadrant as edgePartSet packs them.
float packWindings(vec3 w) { return w.x + 16.0 * w.y + 256.0 * w.z; }

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
#if BLEND_PARTS == 4 && !BLEND_CENTROID
    // The paper's configuration: the four quadrants without moments.
    EdgeParts4 e = edgeParts4(p, vE0.xyz, vE1.xyz, light);
    oCoverage = e.coverage;
    oWindings = vec4(packWindings(e.windings[0]), packWindings(e.windings[1]),
                     packWindings(e.windings[2]), packWindings(e.windings[3]));
    oBounds0 = minForm(e.bounds[0]);
    oBounds1 = minForm(e.bounds[1]);
    oBounds2 = minForm(e.bounds[2]);
    oBounds3 = minForm(e.bounds[3]);
#else
#if BLEND_PARTS == 8
    int set = uPartSet;
#else
    int set = 0;
#endif
    EdgePartSet e = edgePartSet(p, vE0.xyz, vE1.xyz, light, BLEND_PARTS, set);
#if BLEND_PARTS == 1
#if BLEND_CENTROID
    oState = vec4(e.coverage.x, e.windings.x, e.momentX.x, e.momentY.x);
#else
    oState = vec4(e.coverage.x, e.windings.x, 0.0, 0.0);
#endif
    oBounds0 = minForm(e.bounds[0]);
#else
    oCoverage = e.coverage;
    oWindings = e.windings;
#if BLEND_CENTROID
    oMomentX = e.momentX;
    oMomentY = e.momentY;
#endif
    oBounds0 = minForm(e.bounds[0]);
    oBounds1 = minForm(e.bounds[1]);
    oBounds2 = minForm(e.bounds[2]);
    oBounds3 = minForm(e.bounds[3]);
#endif
#endif
}
