// Analytic shapes of the scene JSON, built as closed (box, sphere) or two-sided open (quad)
// triangle meshes with outward counter-clockwise winding, plus the closed test and benchmark
// shapes (icosphere, torus, radially displaced "noisy" spheres).
#pragma once

#include <geometry/core/Types.h>

#include <cstddef>
#include <cstdint>

namespace geometry {

// Axis-aligned box: 12 triangles, 8 shared corner positions (closed 2-manifold).
MeshData makeBox(const glm::vec3& center, const glm::vec3& size);
// Parallelogram center ± u ± v: 2 triangles, normal along cross(u, v) (open, two-sided use).
MeshData makeQuad(const glm::vec3& center, const glm::vec3& u, const glm::vec3& v);
// UV sphere with `segments` around (>= 3) and segments/2 rings; poles are single vertices so the
// mesh is a closed 2-manifold.
MeshData makeSphere(const glm::vec3& center, float radius, int segments);

// Triangles makeSphere / makeTorus build for these segment counts (known before building, to
// refuse a request over a budget up front: geometry/core/Limits.h). Segments must be >= 3.
std::size_t sphereTriangleCount(int segments);
std::size_t torusTriangleCount(int majorSegments, int minorSegments);

// Geodesic sphere: an icosahedron whose faces are split 4:1 `subdivisions` times (0..9), new
// vertices pushed onto the sphere. 20 * 4^s triangles, 10 * 4^s + 2 vertices, every vertex shared
// (closed 2-manifold), outward CCW. Triangles are near-equal in size, unlike the UV sphere's
// pole fans, which makes it the uniform test and benchmark mesh.
MeshData makeIcosphere(const glm::vec3& center, float radius, int subdivisions);
// Ring torus around the axis through `center` along +y: majorRadius > minorRadius > 0,
// majorSegments around the axis and minorSegments around the tube (each >= 3).
// 2 * major * minor triangles, major * minor vertices, closed 2-manifold of genus 1, outward CCW.
MeshData makeTorus(const glm::vec3& center, float majorRadius, float minorRadius,
                   int majorSegments, int minorSegments);
// Moves every vertex along its direction from `center` by a pseudo-random distance in
// [-amplitude, amplitude] (the "noisy sphere"). The noise is a hash of `seed` and the vertex
// position, so it is deterministic, and vertices at the same position move together (an unwelded
// closed mesh stays closed after welding). Requires amplitude >= 0 and every vertex farther than
// amplitude from `center`: radial moves then keep each vertex's direction, so a mesh that is
// star-shaped about `center` (sphere, icosphere) stays embedded and outward-oriented.
void displaceRadially(MeshData& mesh, const glm::vec3& center, float amplitude,
                      std::uint32_t seed);

} // namespace geometry
