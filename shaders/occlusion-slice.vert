// Occlusion textures, slicing pass: the scene from the centre of projection behind the light.
#include "lib/Bindings.h"

layout(location = 0) in vec3 aPosition;
layout(location = 3) in vec2 aTexcoord;

out vec3 vWorld;
out vec2 vTexcoord;

void main() {
    vWorld = aPosition;
    vTexcoord = aTexcoord;
    gl_Position = occlusion.sliceProj * vec4(aPosition, 1.0);
}
