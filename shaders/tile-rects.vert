// A full-screen pass drawn over some rectangles of the screen only (pcss's lookup over the tiles
// a caster's shadow can reach): rectangle uFirstRect + gl_VertexID / 6 of BINDING_SCREEN_RECTS,
// in NDC,
// as two triangles. Rectangles meeting at an edge share its coordinates exactly, so each pixel
// is shaded once (a multiplying pass must not cover a pixel twice).
#include "lib/Bindings.h"

layout(std430, binding = BINDING_SCREEN_RECTS) readonly buffer ScreenRects {
    vec4 rects[];
};

layout(location = UNIFORM_FIRST_RECT) uniform int uFirstRect;

out vec2 vUv;

void main() {
    vec4 r = rects[uFirstRect + gl_VertexID / 6];
    int k = gl_VertexID % 6; // corners (0, 0) (1, 0) (1, 1), (0, 0) (1, 1) (0, 1)
    vec2 corner = vec2(k == 1 || k == 2 || k == 4 ? 1.0 : 0.0,
                       k == 2 || k == 4 || k == 5 ? 1.0 : 0.0);
    vec2 p = mix(r.xy, r.zw, corner);
    vUv = 0.5 * p + 0.5;
    gl_Position = vec4(p, 0.0, 1.0);
}
