// Conservative hull of a penumbra wedge with a fixed topology, built per vertex on the GPU
// (vertex pulling: no CPU wedge building). This is the float C++ twin of
// shaders/lib/WedgeHull.glsl: same names, same order, same float arithmetic, so the two can be
// read side by side and a GL test can compare the GPU against this code. Change both together.
//
// The exact wedge of edge E = [e0, e1] for the light c + s u + t v (s, t in [-1, 1]) is
// W = E + cone{e_i - c_j} (geometry/Wedge.h). With a = unit(e1 - e0), every ray e_i - c_j is
// P_j + A_j a (P_j ⟂ a; e1's rays have the same P_j and A_j + |e1 - e0|). When the P_j lie in a
// sector narrower than 180° (the edge's line misses the light's projection along a), its two
// boundary directions F and B give W's exact front and back planes span(a, F), span(a, B)
// through E. The side plane at e0 is a plane A = dot(P, h0) below every ray (A_j >=
// dot(P_j, h0)), the one at e1 a plane A = dot(P, h1) above every ray of e1; each is one of W's
// own side facets (a plane through the end point and two light corners), the one leaving the
// hull the smallest solid angle. Then with
//     g1 = F + dot(F, h0) a,  g2 = F + dot(F, h1) a,  g3 = B + dot(B, h0) a,  g4 = B + dot(B, h1) a
// (normalised) the cone K = cone(g1..g4) = { P + A a : P in the sector, dot(P, h0) <= A <=
// dot(P, h1) } holds every ray, and H = E + K ⊇ W. H is bounded by the front quad (E, g1, g2),
// the back quad (E, g3, g4), one side triangle at each end point and a quad at infinity:
// 8 triangles, 24 vertices, whatever the edge and light. (One slope per side against the
// sector's bisector, tried first, was looser: for generic edges far out, a median of 0.89 of the
// hull inside W and a 10th percentile of 0.66, against 0.95 and 0.80 here.)
//
// Float safety: the sector is widened and h0, h1 moved outward by amounts derived from a bound
// on the rounding of every ray coordinate, and the planes are pushed outward, so that every
// exact point of W lies inside the float planes (tested in tests/geometry/WedgeHullTest.cpp,
// which also shows the margins are needed: a 16th of them fails). The hull is Fullscreen
// instead where that bound is too weak (the edge's line passes within 3e-4 (|e0 - c| + |u| + |v|)
// + 1.5e-4 |e1 - e0| of a light corner, seen along the edge), where the sector is wider than 178°,
// or where the side planes would cross inside the sector (a ray nearly along the edge). Quads are
// split into two triangles whose planes agree only to the rounding of their vertices (~1e-7 of
// the scene).
//
// The kind is a plain int, not an enum class, so that it reads the same as in GLSL.
#pragma once

#include <glm/glm.hpp>

namespace geometry {

inline constexpr int kWedgeHullBounded = 0;    // the 24 vertices below bound W
inline constexpr int kWedgeHullFullscreen = 1; // no useful bound (the edge touches or crosses
                                               // the light, sees it over ~180°, or points at a
                                               // corner): test every pixel (scissored)
inline constexpr int kWedgeHullDegenerate = 2; // zero-length (or non-finite) edge: draw nothing
inline constexpr int kWedgeHullVertexCount = 24;

struct WedgeHull {
    int kind = kWedgeHullDegenerate;
    glm::vec3 e0{0.0f};
    glm::vec3 e1{0.0f};
    glm::vec3 g[4] = {};      // g1..g4: unit directions of the cone's edges (Bounded only)
    glm::vec4 planes[4] = {}; // front, back, side at e0, side at e1: xyz unit outward normal,
                              // w = -dot(n, point); inside when dot(n, p) + w <= 0
};

// Vertex slots of the 24 hull vertices: 0 e0, 1 e1, 2..5 g1..g4 (w = 0). Outward winding
// (counter-clockwise seen from outside; a triangle at infinity counts as seen from any finite
// point, which is inside):
//   front  (e1, e0, g1) (e1, g1, g2)    back   (e0, e1, g4) (e0, g4, g3)
//   side 0 (e0, g3, g1)                 side 1 (e1, g2, g4)
//   far    (g1, g3, g4) (g1, g4, g2)
inline constexpr int kWedgeHullIndex[kWedgeHullVertexCount] = {
    1, 0, 2, 1, 2, 3, // front
    0, 1, 5, 0, 5, 4, // back
    0, 4, 2,          // side at e0
    1, 3, 5,          // side at e1
    2, 4, 5, 2, 5, 3, // far
};
// The face (index into planes; 4 = the plane at infinity) of each of the 8 triangles.
inline constexpr int kWedgeHullTriangleFace[kWedgeHullVertexCount / 3] = {0, 0, 1, 1, 2, 3, 4, 4};

// "Front" is the plane with the sector on its counter-clockwise side about a = e1 - e0: with the
// loop orientation of geometry/Silhouette.h (occluder to the left of e0 -> e1 seen from the
// light centre) it borders the lit side and "back" the umbra side.
WedgeHull wedgeHull(glm::vec3 e0, glm::vec3 e1, glm::vec3 c, glm::vec3 u, glm::vec3 v);

// Vertex `index` (0..23) as a homogeneous point (w = 1) or direction (w = 0); vec4(0) for every
// index unless the hull is Bounded.
glm::vec4 wedgeHullVertex(const WedgeHull& hull, int index);

// Clip-space position for a draw of 24 vertices per edge: Bounded: viewProj times the vertex;
// Fullscreen: vertices 0..2 a triangle covering the viewport, wound clockwise in NDC (back-facing
// under glFrontFace(GL_CCW), like the hull's own back faces), the others vec4(0); Degenerate:
// vec4(0) (no fragments).
glm::vec4 wedgeHullClipVertex(const WedgeHull& hull, int index, const glm::mat4& viewProj);

// The plane test (early-out in the fragment shader): true when p is inside all four planes.
// The pushes in the planes cover float rounding here; a Fullscreen hull's planes are zero, so
// every point is inside, and so are a Degenerate hull's (callers draw nothing for it).
bool wedgeHullContains(const glm::vec4 planes[4], glm::vec3 p);

} // namespace geometry
