// Automatic camera and light for a model given without a scene file.
#pragma once

#include <geometry/Scene.h>

namespace geometry {

// For an enclosed model (a game level): finds the most open point of its interior by casting
// rays from a grid of candidate points, puts the camera there looking along its longest free
// horizontal view, and hangs the light under the ceiling above the viewed spot. Returns false,
// leaving the scene unchanged, when no candidate point is enclosed (an object seen from outside:
// then defaultCamera/defaultLight frame its bounds from outside).
bool frameInterior(Scene& scene);

} // namespace geometry
