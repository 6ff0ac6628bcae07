// C++ view of shaders/lib/Bindings.h (binding slots and std140 blocks shared with GLSL).
#pragma once

#include <glm/glm.hpp>

#include <cstdint>

#include "../../shaders/lib/Bindings.h"
