// Debug view "error": |V - V_ref| as geometry::errorHeatMap colours it (lib/Debug.glsl), against
// the progressive reference: TEXUNIT_DEBUG0 holds Σ 1/N over the light samples done so far where
// lit, uRefScale = N / done makes it their mean. No surface: errorHeatMap's grey.
#include "lib/Bindings.h"
#include "lib/Debug.glsl"

layout(binding = TEXUNIT_POSITION) uniform sampler2D tPosition;
layout(binding = TEXUNIT_VISIBILITY) uniform sampler2D tVisibility;
layout(binding = TEXUNIT_DEBUG0) uniform sampler2D tReference;

layout(location = 0) uniform float uRefScale;
layout(location = 1) uniform float uErrorScale; // |dV| at the top of the ramp

layout(location = 0) out vec4 oColor;

void main() {
    ivec2 px = ivec2(gl_FragCoord.xy);
    if (texelFetch(tPosition, px, 0).w == 0.0) {
        oColor = vec4(vec3(96.0 / 255.0), 1.0);
        return;
    }
    float v = texelFetch(tVisibility, px, 0).r;
    float ref = texelFetch(tReference, px, 0).r * uRefScale;
    oColor = vec4(debugHeatColour(abs(v - ref) / uErrorScale), 1.0);
}
