// Adds the weight of one hard-shadow sample where the stencil says "lit" (the stencil test,
// EQUAL 0, does the selection; additive blending does the sum).
// OWN_PLANE (the reference's passes): not where the light point lies behind the receiver's own
// plane (the G-buffer's facet normal, facing the viewer), as raytrace counts it. A closed mesh's
// volume already holds such points; open and thin geometry's does not (a wall's front would be
// lit from behind its plane).
#include "lib/Bindings.h"

#ifdef OWN_PLANE
layout(binding = TEXUNIT_POSITION) uniform sampler2D tPosition;
layout(binding = TEXUNIT_NORMAL) uniform sampler2D tNormal;
layout(location = 0) uniform vec3 uLightPoint;
#endif

layout(location = 0) out float oVisibility;

void main() {
#ifdef OWN_PLANE
    ivec2 px = ivec2(gl_FragCoord.xy);
    vec4 position = texelFetch(tPosition, px, 0);
    if (position.w != 0.0 &&
        dot(texelFetch(tNormal, px, 0).xyz, uLightPoint - position.xyz) <= 0.0)
        discard;
#endif
    oVisibility = frame.params.y;
}
