// Analytic shapes of the scene JSON, built as closed (box, sphere) or two-sided open (quad)
// triangle meshes with outward counter-clockwise winding.
#pragma once

#include <geometry/Types.h>

namespace geometry {

// Axis-aligned box: 12 triangles, 8 shared corner positions (closed 2-manifold).
MeshData makeBox(const glm::vec3& center, const glm::vec3& size);
// Parallelogram center ± u ± v: 2 triangles, normal along cross(u, v) (open, two-sided use).
MeshData makeQuad(const glm::vec3& center, const glm::vec3& u, const glm::vec3& v);
// UV sphere with `segments` around (>= 3) and segments/2 rings; poles are single vertices so the
// mesh is a closed 2-manifold.
MeshData makeSphere(const glm::vec3& center, float radius, int segments);

} // namespace geometry
