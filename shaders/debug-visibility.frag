// Debug view "visibility": V as grey, linear (the 8-bit image holds round(255 V)); no surface
// dark blue.
#include "lib/Bindings.h"
#include "lib/Debug.glsl"

layout(binding = TEXUNIT_POSITION) uniform sampler2D tPosition;
layout(binding = TEXUNIT_VISIBILITY) uniform sampler2D tVisibility;

layout(location = 0) out vec4 oColor;

void main() {
    ivec2 px = ivec2(gl_FragCoord.xy);
    if (texelFetch(tPosition, px, 0).w == 0.0) {
        oColor = vec4(kDebugNoSurface, 1.0);
        return;
    }
    oColor = vec4(vec3(texelFetch(tVisibility, px, 0).r), 1.0);
}
