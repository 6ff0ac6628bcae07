// Hard shadow-volume geometry for a point light, robust for open and non-manifold meshes by the
// two-sided multiplicity rule (DESIGN.md §4):
// - every triangle is a two-sided occluder: one facing away from the light is flipped so that it
//   faces the light ("light-oriented");
// - edge e gets multiplicity m_e = sum over its uses of (use sign) * (+1 unflipped, -1 flipped),
//   so consistent interior edges cancel (0), boundary edges get ±1 and an edge between a flipped
//   and an unflipped triangle gets ±2;
// - each edge is extruded |m_e| times away from the light (w = 0, to infinity), oriented by the
//   sign of m_e; all light-oriented triangles form the front cap, and their reversed copies
//   projected to infinity the back cap.
// The result is a set of closed, consistently oriented volumes whose z-fail stencil count at a
// point is the number of triangles between that point and the light.
#pragma once

#include <geometry/shadow/Topology.h>

#include <cstdint>
#include <span>
#include <vector>

namespace geometry {

struct ShadowVolumeGeometry {
    // Triangle list, counter-clockwise seen from outside the volume. w = 1: a point; w = 0: a
    // direction (p - light), i.e. the point at infinity that p is extruded to.
    std::vector<glm::vec4> vertices;
    std::size_t capTriangles = 0;     // front + back caps
    std::size_t sideTriangles = 0;    // 2 per extruded edge copy
    std::size_t silhouetteEdges = 0;  // edges with m_e != 0

    void clear() {
        vertices.clear();
        capTriangles = sideTriangles = silhouetteEdges = 0;
    }
};

// +1 if triangle t faces the light point (or the light lies in its plane), -1 otherwise.
// Writes one value per topology triangle into `facing` (size = triangles().size()).
void classifyFacing(const Topology& topology, const glm::vec3& light, std::span<std::int8_t> facing);

// Edge multiplicities m_e for the given facing (size = edges().size()).
void edgeMultiplicities(const Topology& topology, std::span<const std::int8_t> facing,
                        std::span<std::int32_t> multiplicity);

// Appends the closed volume of all triangles of `topology` for a point light at `light`.
// Each call appends, in this order: the T front caps (w = 1), the T back caps (w = 0), then |m_e|
// side quads (2 triangles each) per edge with m_e != 0. Not thread-safe per `out`; scratch is
// per thread, so concurrent calls on different outputs are fine.
void appendHardShadowVolume(const Topology& topology, const glm::vec3& light,
                            ShadowVolumeGeometry& out);

} // namespace geometry
