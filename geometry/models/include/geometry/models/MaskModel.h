// The CPU model of one silhouette group's light-sample mask (wedges-bitmask; the method and
// its pattern are described in geometry/shadow/LightMask.h): double precision, exact projected
// polygons, point-in-polygon per sample by parity and by signed counts. Tests compare the GPU's
// masks with it bit for bit.
#pragma once

#include <geometry/core/Types.h>

#include <glm/glm.hpp>

#include <array>
#include <cstdint>
#include <span>
#include <utility>
#include <vector>

namespace geometry {

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

// The model of wedges-bitmask silhouettes=potential, the definition itself: per sample y, D(p, y),
// the number of `triangles` (any winding: counted two-sided) the segment p -> y crosses, each
// triangle clipped to the slab between p's level and the light's plane and its projection from
// p tested exactly (double). `ambiguous`: per sample, within `tolerance` (light coordinates) of
// the projection of a triangle's edge, where float arithmetic may decide either way;
// `centreAmbiguous`: the light centre within `centreTolerance` of one (the GPU's centre count
// comes from the rasterised volumes). Call with p already moved off its own surface (towards
// the camera, as the GPU takes a receiver on a two-sided surface).
struct CountModel {
    std::vector<int> count;
    std::vector<std::uint32_t> ambiguous; // bit i % 32 of word i / 32
    int centreCount = 0;
    bool centreAmbiguous = false;
};
CountModel potentialCountModel(const glm::dvec3& p,
                               std::span<const std::array<glm::dvec3, 3>> triangles,
                               const RectLight& light, std::span<const glm::vec2> samples,
                               double tolerance = 1e-4, double centreTolerance = 0.01);

} // namespace geometry
