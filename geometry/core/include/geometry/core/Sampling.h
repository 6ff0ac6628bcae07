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

// n = 2^k points, k in [0, 16], forming a (0, k, 2)-net in base 2: every elementary interval of
// area 1/n (the 2^a x 2^(k-a) grids of the square, for each a) holds exactly one point, so the
// points are stratified along either axis and in every such grid at once. The first two Sobol'
// dimensions, Owen-scrambled (each binary digit flipped by a hash of the digits above it and
// the seed), which keeps the net and places the points irregularly within their cells.
// Deterministic for a given seed. Throws std::invalid_argument for other n.
std::vector<glm::vec2> scrambledNet(int n, std::uint32_t seed);

} // namespace geometry
