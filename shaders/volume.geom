// Shadow-volume triangles, passed through with the depth range of their visible part, which
// volume.frag clamps the fragment depth to.
//
// Why: the z-fail count of a pixel is only right if every volume face covering its sample gets
// a depth consistent with where that face really is. A side quad seen edge-on (the camera close
// to its plane) is a sliver on screen; the rasteriser decides coverage from snapped vertex
// positions but interpolates depth over the unsnapped, nearly degenerate triangle, so a sample
// just outside the true sliver gets an extrapolated depth far from the face's own depths: a face
// lying wholly behind a lit wall was counted as in front of it. The count then misses one face
// of a closed volume: isolated V = 0 pixels on lit walls (and rows of them where a wall meets a
// ceiling edge-on from the camera). Clamping to the range of the triangle's own depths keeps the
// coverage (which stays watertight) and makes the depth test agree with the face's position.
#include "lib/Bindings.h"

layout(triangles) in;
layout(triangle_strip, max_vertices = 3) out;

in float vFinite[];

flat out vec2 gDepthRange; // x: farthest (smallest) depth, y: nearest (largest)

void main() {
    // Reversed Z: depth = z / w in [0, 1], 1 at the near plane, 0 at infinity.
    float lo = 1.0, hi = 0.0;
    bool frontCap = true;
    for (int i = 0; i < 3; ++i) {
        int j = (i + 1) % 3;
        vec4 a = gl_in[i].gl_Position, b = gl_in[j].gl_Position;
        frontCap = frontCap && vFinite[i] == 1.0;
        if (a.w > 0.0) {
            float d = clamp(a.z / a.w, 0.0, 1.0);
            lo = min(lo, d);
            hi = max(hi, d);
        }
        // An edge crossing the camera plane (w = 0) is clipped; the visible end runs towards the
        // camera plane, where the depth of a finite point grows without bound (clamped: 1) and
        // that of a point at infinity stays 0.
        if ((a.w > 0.0) != (b.w > 0.0)) {
            if (vFinite[i] == 1.0 || vFinite[j] == 1.0) hi = 1.0; else lo = 0.0;
        }
    }
    // Front caps carry the polygon offset that pushes them away from the camera (Renderer): only
    // the near bound applies to them, so that the offset is kept.
    if (frontCap) lo = 0.0;
    for (int i = 0; i < 3; ++i) {
        gl_Position = gl_in[i].gl_Position;
        gDepthRange = vec2(lo, hi);
        EmitVertex();
    }
    EndPrimitive();
}
