// Errors caused by bad input (scene JSON, glTF, command-line values). Applications map these to
// exit code 2 with the message; everything else is an internal error.
#pragma once

#include <stdexcept>
#include <string>

namespace geometry {

class InputError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

// A light refused because it cannot be rendered: it intersects or touches scene geometry
// (validateLightClear, geometry/scene/LightCheck.h), or it is not finite or has no area (validateLight,
// geometry/scene/Scene.h). An InputError, so every handler of bad input still takes it; code that falls
// back to another light when one is refused (penumbra-soak, the viewer) catches this type.
class LightRefusedError : public InputError {
public:
    using InputError::InputError;
};

} // namespace geometry
