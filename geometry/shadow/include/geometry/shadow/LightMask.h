// Light-sample masks (wedges-bitmask): the fixed sample pattern and its optional per-pixel
// shift. The CPU model of one silhouette group's mask is geometry/models/MaskModel.h.
//
// The method keeps, per pixel and silhouette group, which of the light's N samples the group
// hides: the centre's state from the group's z-fail volume, toggled by every silhouette edge
// whose region R (geometry::edgeCoverage: the light points beyond the projected edge, between
// the rays from the centre to its ends) holds the sample. That is point-in-polygon by crossings
// of the segment centre -> sample with the projected silhouette: exact (up to the centre's
// silhouette, the wedge methods' shared approximation) while the group's projection covers no
// sample twice. The model below does it in double with exact projected polygons and also keeps
// the signed crossing counts, whose non-zero test stays exact where the projection folds
// (several layers: a torus seen obliquely); comparing the two measures what parity loses.
// Groups combine exactly: a sample is hidden when any group hides it.
#pragma once

#include <geometry/core/Types.h>

#include <glm/glm.hpp>

#include <array>
#include <cstdint>
#include <span>
#include <utility>
#include <vector>

namespace geometry {

// Sample counts the method offers (a multiple of 32: whole 32-bit words).
inline constexpr int kLightMaskSampleCounts[] = {32, 64, 128, 256};

// The fixed pattern: the points of stratifiedSquare(n, seed), the `reference` method's for the
// same n and seed (so that the two estimate the same sum), ordered by their angle about the
// light centre (maskSampleAngle, ascending): bit i of a mask is the i-th in that order. n must
// be one of kLightMaskSampleCounts (an InputError otherwise).
std::vector<glm::vec2> lightMaskPattern(int n, std::uint32_t seed);
// The angle of a sample about the centre, atan2(t, s) in (-pi, pi], as the GPU's table holds it.
float maskSampleAngle(glm::vec2 y);

// The quadrant of the light (shaders/shared/Parts.h's numbering: signs (+,+), (-,+), (-,-),
// (+,-) of (s, t)) of each run of 8 consecutive samples of a lightMaskPattern: the 4-bit counts
// of wedges-bitmask are stored eight to a 32-bit word, and its estimate=quadrants keeps its
// sums per such word. The stratified pattern's strata never straddle an axis (its grid has an
// even number of cells each way) and the angle order keeps each quadrant's N / 4 samples
// together, so every run lies in one quadrant; a pattern where one does not is an internal
// error (std::logic_error).
std::vector<int> lightMaskRunQuadrants(std::span<const glm::vec2> pattern);

// The per-pixel shift (the `rotated` pattern): a Cranley-Patterson rotation in [0, 2)^2 by a
// hash of the pixel (x, y from the lower left), and a point shifted and wrapped back into
// [-1, 1)^2. The shaders' own code (shaders/shared/LightMask.h).
glm::vec2 maskPixelShift(int x, int y);
glm::vec2 maskShifted(glm::vec2 y, glm::vec2 shift);

} // namespace geometry
