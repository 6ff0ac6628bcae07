// Float twin of shaders/lib/Coverage.glsl: the per-fragment coverage of one directed silhouette
// edge (DESIGN.md §4), the same arithmetic as the double geometry::edgeCoverage in Wedge.h
// (Wedge.cpp explains it), written statement for statement like the GLSL so that a GL test can
// compare the GPU against this code and a reviewer can read the two side by side. Change both
// together.
//
// Differences from the double version, all for float: differences of positions are taken before
// anything else (the scene may be far from the origin), the projection of an edge point is
// computed from the light centre or from p, whichever is nearer (so that p close to the edge
// does not cancel), the depths below p's level come from e - p rather than 1 - z, the light's
// frame is computed once (CoverageLight) rather than per call, and the area of the light square
// clipped by three half-planes is integrated along its boundary instead of clipping a polygon
// (no arrays, which are slow on GPUs; each vertex shared by two boundary pieces computed once).
#pragma once

#include <glm/glm.hpp>

namespace geometry {

// The light c + s u + t v (s, t in [-1, 1]) with its unit normal n (along cross(u, v)) and the
// dual basis: s = dot(uStar, y - c), t = dot(vStar, y - c) for y in the light's plane.
struct CoverageLight {
    glm::vec3 c;
    glm::vec3 u;
    glm::vec3 v;
    glm::vec3 n;
    glm::vec3 uStar;
    glm::vec3 vStar;
};

CoverageLight coverageLight(glm::vec3 c, glm::vec3 u, glm::vec3 v);

// Signed fraction of the light hidden by the directed edge e0 -> e1 seen from p, relative to the
// light centre's state: V(p) = V_hard(p) - sum over a silhouette loop of edgeCoverage. Zero
// outside the edge's exact wedge. (Overloads the double version in Wedge.h; this one is float.)
float edgeCoverage(glm::vec3 p, glm::vec3 e0, glm::vec3 e1, const CoverageLight& light);

} // namespace geometry
