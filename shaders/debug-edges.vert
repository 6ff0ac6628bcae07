// Debug view "silhouettes": the light centre's directed silhouette edges (lib/Casters.glsl) as
// GL_LINES, two pulled vertices per edge (gl_VertexID / 2 = the edge). Depth is pulled towards
// the camera by a relative amount (reversed Z: depth = near / distance, so scaling it is a
// relative distance bias) so that edges on the surface they bound pass the depth test.
#include "lib/Bindings.h"
#include "lib/Casters.glsl"

layout(location = 1) uniform float uDepthBias;

void main() {
    GpuEdge e = edges[gl_VertexID / 2];
    vec3 p = weldedPositions[(gl_VertexID & 1) == 0 ? e.v0 : e.v1].xyz;
    gl_Position = frame.viewProj * vec4(p, 1.0);
    gl_Position.z *= 1.0 + uDepthBias;
}
