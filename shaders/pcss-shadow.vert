// PCSS, shadow pass: the casters from the light's centre, into the map of one face of the cube
// around it (depth zNear / z along that face's axis; geometry::PcssFrame::projection).
#include "lib/Bindings.h"

layout(location = 0) in vec3 aPosition;
layout(location = 3) in vec2 aTexcoord;

layout(location = UNIFORM_PCSS_SIDE) uniform int uSide;

out vec2 vTexcoord;

void main() {
    vTexcoord = aTexcoord;
    gl_Position = pcss.shadowProj[uSide] * vec4(aPosition, 1.0);
}
