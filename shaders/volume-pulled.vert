// The light centre's hard shadow volume by vertex pulling from the casters' welded geometry and
// this frame's silhouettes (lib/Casters.glsl); one variant per part, selected by a define:
// - CAP_FRONT: gl_VertexID = 3 * cap entry + corner: the light-oriented triangle itself;
// - CAP_BACK:  the same triangle reversed, extruded to infinity (w = 0) away from the light
//              centre (counter-clockwise seen from beyond it);
// - otherwise sides: gl_VertexID = 6 * edge + k: the quad (q, p, p∞), (q, p∞, q∞) of directed
//   edge p -> q, as geometry::appendHardShadowVolume builds it on the CPU.
#include "lib/Bindings.h"
#include "lib/Casters.glsl"

invariant gl_Position; // front caps must land where the G-buffer put the surface

out float vFinite; // 1 for a point, 0 for a point at infinity (volume.geom)

void main() {
    vec3 lc = frame.lightCenter.xyz;
    vec4 world;
#if defined(CAP_FRONT)
    world = vec4(capCorner(capTriangles[gl_VertexID / 3], gl_VertexID % 3), 1.0);
#elif defined(CAP_BACK)
    int k = gl_VertexID % 3;
    world = vec4(capCorner(capTriangles[gl_VertexID / 3], k == 0 ? 0 : 3 - k) - lc, 0.0);
#else
    GpuEdge e = edges[gl_VertexID / 6];
    int k = gl_VertexID % 6;
    bool isQ = k == 0 || k == 3 || k == 5;
    bool atInfinity = k == 2 || k == 4 || k == 5;
    vec3 x = weldedPositions[isQ ? e.v1 : e.v0].xyz;
    world = atInfinity ? vec4(x - lc, 0.0) : vec4(x, 1.0);
#endif
    vFinite = world.w;
    gl_Position = frame.viewProj * world;
}
