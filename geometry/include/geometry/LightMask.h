// Light-sample masks (wedges-bitmask): the fixed sample pattern, its optional per-pixel shift,
// and the CPU model of one silhouette group's mask.
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

#include <geometry/Types.h>

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

// The per-pixel shift (the `rotated` pattern): a Cranley-Patterson rotation in [0, 2)^2 by a
// hash of the pixel (x, y from the lower left), and a point shifted and wrapped back into
// [-1, 1)^2. The shaders' own code (shaders/shared/LightMask.h).
glm::vec2 maskPixelShift(int x, int y);
glm::vec2 maskShifted(glm::vec2 y, glm::vec2 shift);

// One directed silhouette edge of a group, in world space (the group's light-oriented triangles
// to its left seen from the light centre, as geometry::SilhouetteEdge).
using MaskEdge = std::pair<glm::dvec3, glm::dvec3>;

struct GroupMaskModel {
    // Per sample i (bit i % 32 of word i / 32): hidden by the parity rule (the method's).
    std::vector<std::uint32_t> parity;
    // Per sample: the centre's count plus the signed crossings; hidden where non-zero.
    std::vector<int> count;
    // Per sample: within `tolerance` (in light coordinates, the light being [-1, 1]^2) of a
    // projected edge or of a ray from the centre through a projected vertex, where float
    // arithmetic may decide either way.
    std::vector<std::uint32_t> ambiguous;
    // The light centre within `centreTolerance` of a projected edge: the group's centre state
    // may go either way on the GPU, where it comes from the rasterised volume's depth test
    // (grazing at a receiver near the occluder's own terminator), not from this arithmetic.
    bool centreAmbiguous = false;
};

// The model at receiver point p for one group: its directed silhouette edges and the centre's
// count (the group's z-fail count for the centre: the light-oriented triangles the segment
// p -> centre crosses; 0 or 1 for a convex occluder). `samples` in light coordinates.
GroupMaskModel groupMaskModel(const glm::dvec3& p, std::span<const MaskEdge> edges,
                              int centreCount, const RectLight& light,
                              std::span<const glm::vec2> samples, double tolerance = 1e-5,
                              double centreTolerance = 1e-5);

// Light-oriented triangles (world space, wound counter-clockwise seen from the light centre)
// crossed by the segment a -> b, leaving out 1e-4 of its length at either end (a receiver on
// an occluder's face): the centre's count of groupMaskModel.
int segmentCrossings(const glm::dvec3& a, const glm::dvec3& b,
                     std::span<const std::array<glm::dvec3, 3>> triangles);

} // namespace geometry
