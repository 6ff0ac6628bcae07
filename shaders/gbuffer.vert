// G-buffer: world position, flat geometric normal and shading normal of the visible surface.
#include "lib/Bindings.h"

layout(location = 0) in vec3 aPosition;
layout(location = 1) in vec3 aNormal; // face normal (vertices are expanded per triangle)
layout(location = 2) in vec3 aAlbedo;
layout(location = 3) in vec2 aTexcoord;
layout(location = 4) in vec3 aShading; // the file's vertex normal (else the face normal)

out vec3 vWorld;
out vec2 vTexcoord;
out vec3 vShading;
flat out vec3 vNormal;
flat out vec3 vAlbedo;

// The shadow-volume front caps are drawn with the same matrix; invariance keeps their depth
// as close as the compiler allows (the volume pass adds a small offset on top).
invariant gl_Position;

void main() {
    vWorld = aPosition;
    vTexcoord = aTexcoord;
    vNormal = aNormal;
    vShading = aShading;
    vAlbedo = aAlbedo;
    gl_Position = frame.viewProj * vec4(aPosition, 1.0);
}
