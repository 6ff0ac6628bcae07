#include "lib/Bindings.h"
#include "lib/Material.glsl"

in vec3 vWorld;
in vec2 vTexcoord;
in vec3 vShading;
flat in vec3 vNormal;
flat in vec3 vAlbedo;

layout(location = 0) out vec4 oPosition; // xyz world, w = 1 where there is a surface
layout(location = 1) out vec4 oNormal;   // xyz normal facing the viewer
layout(location = 2) out vec4 oAlbedo;
layout(location = 3) out vec4 oShading;  // xyz shading normal on the viewer's side (n.l only)

void main() {
    vec4 texel = materialTexel(vTexcoord);
#ifdef ALPHA_TEST
    if (materialCutOut(texel)) discard; // see through the card where it has no leaf
#endif
    // Every surface is two-sided: shade the side the camera sees.
    // The shading normal turns with it (it lies on the winding's side: SceneGeometry).
    vec3 n = vNormal;
    vec3 s = vShading;
    if (dot(n, frame.eye.xyz - vWorld) < 0.0) {
        n = -n;
        s = -s;
    }
    float len = length(s);
    oPosition = vec4(vWorld, 1.0);
    oNormal = vec4(n, 0.0);
    oShading = vec4(len > 0.0 ? s / len : n, 0.0);
    oAlbedo = vec4(vAlbedo * texel.rgb, 1.0);
}
