// Wedge pass, vertex pulling: 6 hull corners per wedge (gl_VertexID / 6 = the edge's index; an
// index buffer makes the hull's 8 triangles of them: WedgePass), in
// two draws (uPass) so that every pixel is processed once per wedge:
// - WEDGE_PASS_ENTRY: bounded hulls with the camera outside: the 8 triangles of the hull,
//   outward wound, w = 0 at infinity; the pass culls back faces, so a pixel whose eye ray meets
//   the hull gets one fragment where it enters (a convex polyhedron), depth-tested against the
//   surface (hulls behind the visible surface, the common case in levels, cost nothing);
// - WEDGE_PASS_EXIT: bounded hulls around the camera, by their back faces (the one face each
//   ray leaves through), and full-screen wedges: one clockwise (back-facing) triangle at
//   infinite depth over the screen rectangle of the group's influence bounds;
// - anything else: every vertex at one point outside the view, nothing is rasterised.
// WEDGE_DEPTH_BIAS (the wedges debug view): depth scaled by 1 + bias.
#include "lib/Bindings.h"
#include "shared/WedgeHull.h"

layout(std430, binding = BINDING_WEDGES) readonly buffer Wedges {
    GpuWedge wedges[];
};
layout(std430, binding = BINDING_GROUPS) readonly buffer Groups {
    GpuGroup groups[];
};

// The fragment shader's inputs, flat: reading the wedge buffer per fragment costs far more.
flat out vec4 vE0;
flat out vec4 vE1;
flat out vec4 vPlanes[4];
flat out uint vBounded;
#ifdef WEDGE_APEXES
// wedges-bitmask silhouettes=potential (engine/PotentialSet.h): the edge's (at most two)
// triangles as lib/WedgeCorners.glsl's trianglePlane gives them (a corner, the sign, the
// normal). The same triangle reaches the fragment shader as the same floats from each of its
// edges, so its orientation about P is computed bit for bit alike on all three (the counts of
// its edges cancel exactly).
layout(std430, binding = BINDING_WELDED_POSITIONS) readonly buffer WeldedPositions {
    vec4 weldedPositions[];
};
layout(std430, binding = BINDING_EDGES) readonly buffer Edges {
    GpuEdge edges[];
};
layout(std430, binding = BINDING_EDGE_APEXES) readonly buffer EdgeApexes {
    uvec2 edgeApexes[];
};
flat out vec4 vTri0[2];
flat out vec4 vTri1[2];
#endif

#define WEDGE_PASS_ENTRY 0u
#define WEDGE_PASS_EXIT 1u
layout(location = 0) uniform uint uPass;

#include "lib/WedgeCorners.glsl"

void main() {
    uint w = uint(gl_VertexID) / 6u;
    int corner = gl_VertexID % 6; // 0 e0, 1 e1, 2..5 the rays g1..g4
    // Most wedges draw nothing in a given pass (culled, or drawn by the other pass): decide from
    // two words before reading the whole wedge (on a software rasteriser, vertex shading runs
    // for all 24 vertices of every wedge of the set, twice, and dominated the frame).
    uint kind = wedges[w].kind;
    bool bounded = kind == WEDGE_BOUNDED;
    bool inside = bounded && wedges[w].eyeInside != 0u;
    bool drawn = uPass == WEDGE_PASS_ENTRY ? bounded && !inside
                                           : inside || kind == WEDGE_FULLSCREEN;
    if (!drawn) {
        gl_Position = vec4(2.0, 2.0, 2.0, 1.0); // outside the view: nothing, not even a point
        vE0 = vec4(0.0);
        vE1 = vec4(0.0);
        for (int i = 0; i < 4; ++i) vPlanes[i] = vec4(0.0);
        vBounded = 0u;
#ifdef WEDGE_APEXES
        for (int i = 0; i < 2; ++i) {
            vTri0[i] = vec4(0.0);
            vTri1[i] = vec4(0.0);
        }
#endif
        return;
    }
    GpuWedge wedge = wedges[w];
    vE0 = wedge.e0;
    vE1 = wedge.e1;
    for (int i = 0; i < 4; ++i) vPlanes[i] = wedge.planes[i];
    vBounded = wedge.kind == WEDGE_BOUNDED ? 1u : 0u;
#ifdef WEDGE_APEXES
    GpuEdge edge = edges[wedge.edge]; // a twin slot's edge is another slot's
    uvec2 apex = edgeApexes[wedge.edge];
    trianglePlane(edge.v0, edge.v1, apex.x, vTri0);
    trianglePlane(edge.v0, edge.v1, apex.y, vTri1);
#endif
    bool entry = wedge.kind == WEDGE_BOUNDED && wedge.eyeInside == 0u;
    bool exit = wedge.kind == WEDGE_BOUNDED && wedge.eyeInside != 0u;
    if ((uPass == WEDGE_PASS_ENTRY && entry) || (uPass == WEDGE_PASS_EXIT && exit)) {
        // A silhouette cone cut to its box (WedgeHull::cone, reach > 0): both end-point corners
        // at its apex, the others the points apex + reach g (wedgeHullVertex's).
        float reach = wedge.rays[3].w;
        vec3 coneApex = vec3(wedge.rays[0].w, wedge.rays[1].w, wedge.rays[2].w);
        vec4 world = reach > 0.0 && corner >= 2
                         ? vec4(coneApex + reach * wedge.rays[corner - 2].xyz, 1.0)
                     : reach > 0.0 ? vec4(coneApex, 1.0)
                     : corner >= 2 ? vec4(wedge.rays[corner - 2].xyz, 0.0)
                     : corner == 0 ? vec4(wedge.e0.xyz, 1.0)
                                   : vec4(wedge.e1.xyz, 1.0);
        gl_Position = frame.viewProj * world;
    } else if (uPass == WEDGE_PASS_EXIT && wedge.kind == WEDGE_FULLSCREEN) {
        GpuGroup g = groups[wedge.group];
        vec4 r = screenRect(g.influenceMin.xyz, g.influenceMax.xyz);
        vec2 size = max(r.zw - r.xy, vec2(0.0));
        // The hull's first triangle (corners 1, 0, 2) becomes (x0, y0), (x0, y0 + 2h),
        // (x0 + 2w, y0): clockwise, covering the rectangle. Corners 3..5 sit on corner 2, so every
        // other triangle is degenerate except (0, 1, 5), the same one counter-clockwise, which
        // the exit pass culls as a front face.
        vec2 p = r.xy + vec2(corner >= 2 ? 2.0 * size.x : 0.0, corner == 0 ? 2.0 * size.y : 0.0);
        gl_Position = vec4(p, 0.0, 1.0); // depth 0: infinitely far, behind every surface
    } else {
        gl_Position = vec4(2.0, 2.0, 2.0, 1.0);
    }
#ifdef WEDGE_DEPTH_BIAS
    // The wedges debug view's lines: pulled nearer by a relative distance (reversed Z), so that
    // hull edges on the occluder pass the depth test (a polygon offset in line mode scales with
    // the face's slope, which is huge for hull faces seen edge-on).
    gl_Position.z *= 1.0 + WEDGE_DEPTH_BIAS;
#endif
}
