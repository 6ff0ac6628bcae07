// Float twin of shaders/lib/Parts.glsl: for one directed silhouette edge seen from p, what a
// wedge fragment adds per radial part of the light. edgeParts4: R = 4 (quadrant q is
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

// Every R (1, 4, 8), with the first moments, one set of at most four parts at a time: parts
// 4 set + k of geometry::blend::radialPart(parts, ·) (R = 1: the one part, k = 0): the float
// counterparts of partCoverage, partMoment, partEdgeBounds and cornerWinding. The windings of a
// part come as one number, Σ_j 16^j w_j over its corners j that are not the light centre (R = 1:
// corners 0..3, R = 4: 1..3, R = 8: 1, 2), each w_j = the edge's sign when corner j is in R_e,
// else 0 (shaders/lib/Parts.glsl explains the layout).
struct EdgePartSet {
    glm::vec4 coverage; // per part of the set: signed |R_e ∩ part| / |part|
    glm::vec4 momentX; // per part: signed ∫ x dA over R_e ∩ part, over |part| (part coordinates)
    glm::vec4 momentY;   // the same for y
    glm::vec4 bounds[4]; // per part: (min x, min y, max x, max y), empty = (1, 1, 0, 0)
    glm::vec4 windings;  // per part: Σ_j 16^j w_j over its corners j that are not the centre
};

EdgePartSet edgePartSet(glm::vec3 p, glm::vec3 e0, glm::vec3 e1, const CoverageLight& light,
                        int parts, int set);

} // namespace geometry
