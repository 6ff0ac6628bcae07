// PCSS, shadow pass: the casters from the light's centre, into the map of one face of the cube
// around it (depth zNear / z along that face's axis; geometry::PcssFrame::projection).
// SAMPLE_MAP: the sample-maps method's pass, into the map of one light sample
// (geometry::SampleMapFrame::projection, the same depth convention).
#include "lib/Bindings.h"

layout(location = 0) in vec3 aPosition;
layout(location = 3) in vec2 aTexcoord;

#ifdef SAMPLE_MAP
layout(location = UNIFORM_SAMPLE_MAP_VIEW) uniform mat4 uView;
#else
layout(location = UNIFORM_PCSS_SIDE) uniform int uSide;
#endif

out vec2 vTexcoord;

void main() {
    vTexcoord = aTexcoord;
#ifdef SAMPLE_MAP
    gl_Position = uView * vec4(aPosition, 1.0);
#else
    gl_Position = pcss.shadowProj[uSide] * vec4(aPosition, 1.0);
#endif
}
