// Occlusion textures, slicing pass: the scene from the centre of projection behind the light.
#include "lib/Bindings.h"

layout(location = 0) in vec3 aPosition;
layout(location = 1) in vec3 aNormal; // face normal (vertices are expanded per triangle)
layout(location = 3) in vec2 aTexcoord;

out vec3 vWorld;
out vec2 vTexcoord;
flat out vec3 vNormal;

void main() {
    vWorld = aPosition;
    vTexcoord = aTexcoord;
    vNormal = aNormal;
    gl_Position = occlusion.sliceProj * vec4(aPosition, 1.0);
}
