// Float edge coverage: the shaders' own source (shaders/shared/Coverage.h, compiled here as C++),
// so the CPU tests run the statements the GPU runs. The double geometry::edgeCoverage of
// Wedge.h is the exact reference it is tested against (tests/geometry/shadow/WedgeHullTest.cpp).
//
// CoverageLight: the light with its unit normal and dual basis; coverageLight builds it.
// edgeCoverage(p, e0, e1, light): signed fraction of the light hidden by the directed edge
// e0 -> e1 seen from p, relative to the light centre's state: V(p) = V_hard(p) - the sum over a
// silhouette loop. Zero outside the edge's exact wedge.
#pragma once

#include <glm/glm.hpp>

#include <shared/Coverage.h>

namespace geometry {

using shader::CoverageLight;
using shader::coverageLight;
using shader::edgeCoverage;
using shader::edgeHalfPlanes;
using shader::edgeProjection;

} // namespace geometry
