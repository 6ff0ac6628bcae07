// Conservative hull of a penumbra wedge with a fixed topology: the shaders' own source
// (shaders/shared/WedgeHull.h, whose comment explains the construction and its float-safety
// margins), compiled here as C++ so that the CPU tests run the statements the GPU runs.
#pragma once

#include <glm/glm.hpp>

#include <shared/WedgeHull.h>

namespace geometry {

using shader::kWedgeHullBounded;
using shader::kWedgeHullDegenerate;
using shader::kWedgeHullFullscreen;
using shader::kWedgeHullIndex;
using shader::kWedgeHullVertexCount;
using shader::WedgeHull;
using shader::wedgeHull;
using shader::wedgeHullClipVertex;
using shader::wedgeHullContains;
using shader::wedgeHullEmpty;
using shader::wedgeHullNarrowed;
using shader::wedgeHullSilhouetteCone;
using shader::wedgeHullTruncateCone;
using shader::wedgeHullVertex;

// The face (index into planes; 4 = the plane at infinity) of each of the 8 triangles.
inline constexpr int kWedgeHullTriangleFace[kWedgeHullVertexCount / 3] = {0, 0, 1, 1, 2, 3, 4, 4};

} // namespace geometry
