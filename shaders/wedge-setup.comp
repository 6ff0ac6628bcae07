// Wedge set-up: one invocation per directed silhouette edge of a range of the frame's edges.
// - The wedge is built here, on the GPU, from the edge and the light (no CPU wedges): the
//   conservative hull of geometry/shadow/WedgeHull.h (shaders/shared/WedgeHull.h);
// - a wedge whose group's influence bounds miss the view frustum is culled (draws nothing);
// - kinds are counted for the report.
#include "lib/Bindings.h"
#include "lib/Casters.glsl"
#include "lib/Frustum.glsl"
#include "shared/WedgeHull.h"

layout(local_size_x = 64) in;

layout(std430, binding = BINDING_WEDGES) writeonly buffer Wedges {
    GpuWedge wedges[];
};
layout(std430, binding = BINDING_WEDGE_STATS) buffer WedgeStats {
    uint wedgeStats[];
};

layout(location = 0) uniform uvec2 uRange; // first edge, edge count

#ifdef WEDGE_APEXES
// wedges-bitmask silhouettes=potential: the third vertices of the edge's triangles
// (engine/PotentialSet.h); with two, the hull is narrowed to the receivers that can see the edge
// as a silhouette (wedgeHullNarrowed), and where the whole hull would be Fullscreen, two
// silhouette cones take its place (wedgeHullSilhouetteCone), the second in the twin slot
// uTwinOffset further on (Degenerate when unused).
layout(std430, binding = BINDING_EDGE_APEXES) readonly buffer EdgeApexes {
    uvec2 edgeApexes[];
};
layout(location = 1) uniform uint uTwinOffset;
#endif

// The hull into the wedge: planes, rays (a silhouette cone's apex in rays[0..2].w, its reach,
// > 0, in rays[3].w: wedge.vert), and whether the camera may be inside.
void storeHull(inout GpuWedge w, WedgeHull h) {
    // kWedgeHull{Bounded, Fullscreen, Degenerate} are WEDGE_{BOUNDED, FULLSCREEN, DEGENERATE}
    w.kind = uint(h.kind);
    for (int k = 0; k < 4; ++k) {
        w.planes[k] = h.planes[k];
        w.rays[k] = vec4(h.g[k], 0.0);
    }
    if (h.cone != 0) {
        w.rays[0].w = h.apex.x;
        w.rays[1].w = h.apex.y;
        w.rays[2].w = h.apex.z;
        w.rays[3].w = h.reach;
    }
    w.eyeInside = 0u;
    if (w.kind == WEDGE_BOUNDED) {
        // Conservative: a camera within float slack of the hull counts as inside (drawing by
        // exit faces is right either way; by entry faces only from outside).
        vec3 eye = frame.eye.xyz;
        float slack = 1e-4 * (1.0 + length(eye - w.e0.xyz));
        bool inside = true;
        for (int k = 0; k < 4; ++k)
            inside = inside && dot(w.planes[k].xyz, eye) + w.planes[k].w <= slack;
        w.eyeInside = inside ? 1u : 0u;
        if (inside) atomicAdd(wedgeStats[WEDGE_STAT_EYE_INSIDE], 1u);
    }
}

void main() {
    if (gl_GlobalInvocationID.x >= uRange.y) return;
    uint i = uRange.x + gl_GlobalInvocationID.x;
    GpuEdge edge = edges[i];
    GpuWedge w;
    w.e0 = vec4(weldedPositions[edge.v0].xyz, 1.0);
    w.e1 = vec4(weldedPositions[edge.v1].xyz, 1.0);
    w.group = edge.group;
    w.eyeInside = 0u;
    w.edge = i; // (wedge.vert reads a twin slot's edge from it)
    GpuGroup g = groups[edge.group];
    bool culled = boxOutsideFrustum(g.influenceMin.xyz, g.influenceMax.xyz);
#ifdef WEDGE_APEXES
    GpuWedge twin = w;
    twin.kind = WEDGE_DEGENERATE;
    for (int k = 0; k < 4; ++k) {
        twin.planes[k] = vec4(0.0);
        twin.rays[k] = vec4(0.0);
    }
#endif
    if (culled) {
        w.kind = WEDGE_CULLED;
        for (int k = 0; k < 4; ++k) {
            w.planes[k] = vec4(0.0);
            w.rays[k] = vec4(0.0);
        }
    } else {
#ifdef WEDGE_APEXES
        uvec2 apex = edgeApexes[i];
        bool two = apex.x != 0xFFFFFFFFu && apex.y != 0xFFFFFFFFu;
        vec3 w0 = two ? weldedPositions[apex.x].xyz : vec3(0.0);
        vec3 w1 = two ? weldedPositions[apex.y].xyz : vec3(0.0);
        WedgeHull h = wedgeHullNarrowed(w.e0.xyz, w.e1.xyz, frame.lightCenter.xyz,
                                        frame.lightU.xyz, frame.lightV.xyz, two, w0, w1);
        if (h.kind == kWedgeHullFullscreen && two) {
            // Each cut to where its receivers can be (the caster's influence box, the edge's
            // wedge): finite, it covers the screen they may; one that holds none draws nothing.
            WedgeHull c0 = wedgeHullSilhouetteCone(w.e0.xyz, w.e1.xyz, frame.lightCenter.xyz,
                                                   frame.lightU.xyz, frame.lightV.xyz, w0, w1, 0);
            if (c0.kind == kWedgeHullBounded) {
                WedgeHull c1 = wedgeHullSilhouetteCone(w.e0.xyz, w.e1.xyz, frame.lightCenter.xyz,
                                                       frame.lightU.xyz, frame.lightV.xyz, w0, w1,
                                                       1);
                WedgeHull t0 = wedgeHullTruncateCone(c0, frame.lightCenter.xyz, frame.lightU.xyz,
                                                     frame.lightV.xyz, g.influenceMin.xyz,
                                                     g.influenceMax.xyz);
                WedgeHull t1 = wedgeHullTruncateCone(c1, frame.lightCenter.xyz, frame.lightU.xyz,
                                                     frame.lightV.xyz, g.influenceMin.xyz,
                                                     g.influenceMax.xyz);
                // Both cut (or shown empty), or neither used: wedge.vert draws a cone only cut
                // (reach > 0), and the full-screen wedge must not overlap a cone of its edge.
                bool cut0 = t0.kind == kWedgeHullDegenerate || t0.reach > 0.0;
                bool cut1 = t1.kind == kWedgeHullDegenerate || t1.reach > 0.0;
                if (cut0 && cut1) {
                    h = t0;
                    storeHull(twin, t1);
                    atomicAdd(wedgeStats[WEDGE_STAT_CONES], 1u);
                }
            }
        }
#else
        WedgeHull h = wedgeHull(w.e0.xyz, w.e1.xyz, frame.lightCenter.xyz, frame.lightU.xyz,
                                frame.lightV.xyz);
#endif
        storeHull(w, h);
    }
    wedges[i] = w;
    atomicAdd(wedgeStats[w.kind], 1u);
#ifdef WEDGE_APEXES
    wedges[i + uTwinOffset] = twin;
#endif
}
