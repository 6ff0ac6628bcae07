// Debug view "stencil": the light centre's z-fail count class uCount (0 lit, 1, 2, 3 = 3 or
// more), selected by the stencil test of the draw, as a colour shaded by a headlight (the view
// direction, independent of V and the light) so the geometry stays readable. Count 0 is grey.
#include "lib/Bindings.h"
#include "lib/Debug.glsl"

layout(binding = TEXUNIT_POSITION) uniform sampler2D tPosition;
layout(binding = TEXUNIT_NORMAL) uniform sampler2D tNormal;

layout(location = 0) uniform int uCount;

layout(location = 0) out vec4 oColor;

void main() {
    ivec2 px = ivec2(gl_FragCoord.xy);
    vec4 position = texelFetch(tPosition, px, 0);
    if (position.w == 0.0) {
        oColor = vec4(kDebugNoSurface, 1.0);
        return;
    }
    const vec3 ramp[4] = vec3[4](vec3(0.90, 0.90, 0.90), vec3(0.25, 0.55, 1.00),
                                 vec3(0.20, 0.85, 0.25), vec3(1.00, 0.20, 0.12));
    vec3 n = texelFetch(tNormal, px, 0).xyz;
    float light = 0.45 + 0.55 * max(dot(n, normalize(frame.eye.xyz - position.xyz)), 0.0);
    oColor = vec4(ramp[clamp(uCount, 0, 3)] * light, 1.0);
}
