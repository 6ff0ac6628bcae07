// Debug view "group-parts" (wedges-blend): one group's per-part visibility 1 - vCoef =
// 1 - clamp(C + coverage) (blend-parts.frag's resolvePart) from the per-part accumulation of
// that group's wedges alone, for one set of parts, one part per channel. Drawn twice, the
// stencil (the group's own z-fail count) selecting where the light centre is occluded
// (uCentre = 1) or not (0).
#ifndef BLEND_PARTS
#define BLEND_PARTS 4
#endif

#include "lib/Bindings.h"

layout(binding = TEXUNIT_PARTS0 + 0) uniform sampler2D tCoverage; // R = 1: (coverage, ...)

layout(location = 0) uniform float uCentre;

layout(location = 0) out vec4 oParts;

void main() {
    vec4 state = texelFetch(tCoverage, ivec2(gl_FragCoord.xy), 0);
#if BLEND_PARTS == 1
    oParts = vec4(1.0 - clamp(uCentre + state.x, 0.0, 1.0), 1.0, 1.0, 1.0);
#else
    oParts = vec4(1.0) - clamp(vec4(uCentre) + state, 0.0, 1.0);
#endif
}
