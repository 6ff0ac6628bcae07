#include "lib/Bindings.h"

in vec3 vWorld;
flat in vec3 vNormal;
flat in vec3 vAlbedo;

layout(location = 0) out vec4 oPosition; // xyz world, w = 1 where there is a surface
layout(location = 1) out vec4 oNormal;   // xyz normal facing the viewer
layout(location = 2) out vec4 oAlbedo;

void main() {
    // Every surface is two-sided: shade the side the camera sees.
    vec3 n = vNormal;
    if (dot(n, frame.eye.xyz - vWorld) < 0.0) n = -n;
    oPosition = vec4(vWorld, 1.0);
    oNormal = vec4(n, 0.0);
    oAlbedo = vec4(vAlbedo, 1.0);
}
