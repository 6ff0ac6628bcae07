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

} // namespace geometry
