// linear-light-sm, skin pass (Heidrich, Brabec & Seidel 2000): the skin polygons of one end
// point's shadow map (the source), drawn into the other end point's view (the target). For
// every pair of neighbouring texels of the source map (along rows, then columns: vertex-pulled,
// six vertices per pair) whose depths jump by more than the discontinuity ratio and by more
// than SLOPE_JUMP times the steps to their other neighbours on the same line (a surface the
// point sees at a grazing angle steps in depth from texel to texel, by about as much each
// time: without this its texels made skins, noise over a room's walls), a quad along
// the texels' shared side from the near depth to the far one: the sheet of the source point's
// rays that graze the occluder's edge, from the edge (value 0) to the surface behind it (value
// 1). Seen from the target point, it covers the receivers in the penumbra that the source point
// cannot see and the target point can, the value falling from 1 where the source point starts to
// see them to 0 at the umbra. Every other pair gives a degenerate quad (no fragment).
#include "lib/Bindings.h"

layout(binding = TEXUNIT_SAMPLE_MAPS) uniform sampler2DArray tMaps; // zNear / z; 0: nothing

layout(location = UNIFORM_SKIN_TARGET_VIEW) uniform mat4 uTargetView;
layout(location = UNIFORM_SKIN_LAYERS) uniform ivec2 uLayers;   // source, target
layout(location = UNIFORM_SKIN_ORIGIN) uniform vec3 uOrigin;    // the source end point
layout(location = UNIFORM_SKIN_EXTENT) uniform vec4 uExtent;    // source map's lo, hi in m
layout(location = UNIFORM_SKIN_AXES) uniform vec3 uAxes[3];     // eu, ev, n
layout(location = UNIFORM_SKIN_PARAMS) uniform vec4 uParams;    // zNear, zFar, R, ratio

// Interpolated linearly in the target's image (the paper's Gouraud shading): over a receiver
// parallel to the light the ramp is then linear across it, as a linear light's visibility is.
noperspective out float vValue;

#define SLOPE_JUMP 3.0

// Depth along n of a stored value (0: nothing there, taken as the deepest caster's depth).
float depthOf(float d) {
    return d > 0.0 ? uParams.x / d : uParams.y;
}

// The world point at depth z along the source map's ray through texel corner c (in texels).
vec3 unproject(vec2 c, float z) {
    vec2 m = uExtent.xy + c / uParams.z * (uExtent.zw - uExtent.xy);
    return uOrigin + z * (m.x * uAxes[0] + m.y * uAxes[1] + uAxes[2]);
}

void main() {
    int R = int(uParams.z);
    int pairsPerAxis = (R - 1) * R;
    int pair = gl_VertexID / 6, corner = gl_VertexID % 6;
    bool columns = pair >= pairsPerAxis; // vertical neighbours
    int p = columns ? pair - pairsPerAxis : pair;
    ivec2 a = columns ? ivec2(p % R, p / R) : ivec2(p % (R - 1), p / (R - 1));
    ivec2 b = a + (columns ? ivec2(0, 1) : ivec2(1, 0));
    ivec2 step = b - a;
    float da = texelFetch(tMaps, ivec3(a, uLayers.x), 0).r;
    float db = texelFetch(tMaps, ivec3(b, uLayers.x), 0).r;
    float dp = texelFetch(tMaps, ivec3(clamp(a - step, ivec2(0), ivec2(R - 1)), uLayers.x), 0).r;
    float dq = texelFetch(tMaps, ivec3(clamp(b + step, ivec2(0), ivec2(R - 1)), uLayers.x), 0).r;
    float zNear = uParams.x, zFar = uParams.y;
    // Depths along n (0: nothing, beyond the casters: the deepest caster's depth).
    float za = depthOf(da), zb = depthOf(db), zp = depthOf(dp), zq = depthOf(dq);
    float zn = min(za, zb), zf = max(za, zb);
    float around = max(abs(za - zp), abs(zq - zb));
    if (!(zf > zn * uParams.w) || !(zf - zn > SLOPE_JUMP * around) || (da == 0.0 && db == 0.0)) {
        gl_Position = vec4(2.0, 2.0, 2.0, 1.0); // no skin: outside the view, culled
        vValue = 1.0;
        return;
    }
    // The shared side of the two texels: from corner s0 to s1, in texels.
    vec2 s0 = vec2(b), s1 = columns ? vec2(b) + vec2(1.0, 0.0) : vec2(b) + vec2(0.0, 1.0);
    // Two triangles: (s0 near, s1 near, s1 far), (s0 near, s1 far, s0 far).
    const int side[6] = int[6](0, 1, 1, 0, 1, 0);
    const int far[6] = int[6](0, 0, 1, 0, 1, 1);
    vec2 s = side[corner] == 0 ? s0 : s1;
    bool isFar = far[corner] == 1;
    vec3 world = unproject(s, isFar ? zf : zn);
    vValue = isFar ? 1.0 : 0.0;
    gl_Position = uTargetView * vec4(world, 1.0);
}
