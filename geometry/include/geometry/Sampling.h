// Stratified sample points on the unit square [-1, 1]^2 (light coordinates s, t), shared by the
// GPU reference and the Embree reference so that both estimate the same integral the same way.
#pragma once

#include <glm/glm.hpp>

#include <cstdint>
#include <vector>

namespace geometry {

// n jittered-stratified points: an nx * ny grid with nx * ny = n, nx the largest divisor of n not
// above sqrt(n); one uniformly jittered point per cell. Deterministic for a given seed. n >= 1.
std::vector<glm::vec2> stratifiedSquare(int n, std::uint32_t seed);

} // namespace geometry
