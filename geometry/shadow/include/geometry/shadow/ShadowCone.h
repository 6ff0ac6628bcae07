// A cone that holds everything an occluder can shade from a rectangular light: every point X
// on a line from a light point L through an occluder point Y, beyond Y (X = Y + t (Y - L),
// t >= 0). Both the hard shadow from the light centre (the z-fail volume) and every penumbra
// wedge of the occluder's silhouette edges are such points, so a surface point outside the cone
// is left alone by the occluder's whole silhouette group.
//
// Built from bounding spheres: the light's (centre, half diagonal s) and the occluder box's
// (centre c, half diagonal r). The apex is their internal centre of similitude
// P = (r lc + s c) / (r + s), the axis points from the light to c, and sin(half angle) =
// (r + s) / |c - lc|. Why it holds: the light sphere lies in the cone's backward nappe and the
// occluder's in its forward one, so L - P is in -K and Y - P in K (K the forward cone, convex);
// X - P = (1 + t)(Y - P) + t (P - L) is a sum of vectors of K, hence in K.
// When the spheres touch or overlap there is no such cone: `whole` (the test always passes).
#pragma once

#include <geometry/core/Types.h>

#include <glm/glm.hpp>

namespace geometry {

struct ShadowCone {
    bool whole = true;
    glm::vec3 apex{0.0f};
    glm::vec3 axis{0.0f, 0.0f, 1.0f}; // unit
    float sinHalf = 1.0f, cosHalf = 0.0f;
};

ShadowCone shadowCone(const Aabb& occluder, const RectLight& light);

// Conservative: false only if no point of the sphere (centre, radius) lies in the cone.
bool sphereMayMeetCone(const ShadowCone& cone, const glm::vec3& centre, float radius);

} // namespace geometry
