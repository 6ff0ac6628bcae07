// Closed forms used as ground truth in tests.
#pragma once

#include <geometry/core/Types.h>

#include <span>

namespace geometry {

// An axis-aligned rectangle parallel to the XZ plane at height y: [x0,x1] x [z0,z1].
struct HorizontalRect {
    float x0, x1, z0, z1, y;
};

// Light is a horizontal axis-aligned rectangle (u along x, v along z, centre height above every
// occluder), occluders are horizontal rectangles below it, P lies below every occluder.
// Exact V(P) = 1 - |light ∩ union of the occluders' projections from P onto the light plane| /
// |light|. Handles any number of occluders (union computed exactly by coordinate compression).
float visibilityParallelRects(const RectLight& light, std::span<const HorizontalRect> occluders,
                              const glm::vec3& p);

} // namespace geometry
