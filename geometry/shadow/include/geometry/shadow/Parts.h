// Per radial part of the light, what one wedge fragment of wedges-blend adds for one directed
// silhouette edge seen from p: the shaders' own source (shaders/shared/Parts.h, whose comment
// explains the layout), compiled here as C++ for the CPU tests. The double model it is tested
// against is geometry/models/BlendModel.h.
//
// edgeParts4(p, e0, e1, light): the paper's four quadrants (coverage, bounds, corner windings).
// edgePartSet(p, e0, e1, light, parts, set): one set of at most four parts of R = 1, 4 or 8,
// with the first moments.
#pragma once

#include <geometry/shadow/Coverage.h>

#include <shared/Parts.h>

namespace geometry {

using shader::EdgeParts4;
using shader::edgeParts4;
using shader::EdgePartSet;
using shader::edgePartSet;

} // namespace geometry
