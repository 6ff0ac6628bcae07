// wedges-bitmask silhouettes=potential, before the light centre's volumes: the depth of each
// receiver whose plane holds the centre becomes that of the point its wedge passes evaluate
// (lib/PotentialReceiver.glsl), so that D(P, c) is counted there too. Drawn only in frames where
// a caster triangle's plane holds the centre exactly (PotentialSet::flatTriangles); the others
// are discarded (depth test GL_ALWAYS, depth writes on, no colour).
#include "lib/Bindings.h"
#include "lib/PotentialReceiver.glsl"

layout(binding = TEXUNIT_POSITION) uniform sampler2D tPosition;
layout(binding = TEXUNIT_NORMAL) uniform sampler2D tNormal;

void main() {
    ivec2 px = ivec2(gl_FragCoord.xy);
    vec4 position = texelFetch(tPosition, px, 0);
    if (position.w == 0.0) discard;
    vec3 n = texelFetch(tNormal, px, 0).xyz;
    if (!planeHoldsLightCentre(position.xyz, n)) discard;
    vec4 clip = frame.viewProj * vec4(potentialReceiver(position.xyz, n), 1.0);
    gl_FragDepth = clip.z / clip.w; // glClipControl ZERO_TO_ONE: depth = z / w
}
