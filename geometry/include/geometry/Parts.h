// Float twin of shaders/lib/Parts.glsl: for one directed silhouette edge seen from p, what a
// wedge fragment adds per quadrant of the light (R = 4; quadrant q is
// geometry::blend::radialPart(4, q), part coordinates [0, 1]^2 with the light centre at (0, 0)):
// the float counterparts of blend::partCoverage, blend::partEdgeBounds and blend::cornerWinding
// (geometry/BlendModel.h explains them), all four quadrants at once, sharing the projection of
// edgeCoverage (geometry/Coverage.h). Same names and statements as the GLSL; change both together.
#pragma once

#include <geometry/Coverage.h>

#include <glm/glm.hpp>

namespace geometry {

struct EdgeParts4 {
    glm::vec4 coverage;    // per quadrant: signed |R_e ∩ part| / |part| (Σ / 4 = edgeCoverage)
    glm::vec4 bounds[4];   // per quadrant: (min x, min y, max x, max y), empty = (1, 1, 0, 0)
    glm::vec3 windings[4]; // per quadrant: corners 1, 2, 3: the edge's sign when in R_e, else 0
};

EdgeParts4 edgeParts4(glm::vec3 p, glm::vec3 e0, glm::vec3 e1, const CoverageLight& light);

} // namespace geometry
