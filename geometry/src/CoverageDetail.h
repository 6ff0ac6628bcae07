// The helpers of the float edge coverage (Coverage.cpp, twins of shaders/lib/Coverage.glsl's),
// shared with the per-part twin (Parts.cpp) as Parts.glsl shares Coverage.glsl's. Internal to
// geometry/src.
#pragma once

#include <geometry/Coverage.h>

namespace geometry::coverage_detail {

float coverageCross2(glm::vec2 a, glm::vec2 b);
bool coverageClipLe0(float f0, float f1, float& lo, float& hi);
bool coverageClipHalf(glm::vec3 h, glm::vec2 a, glm::vec2 b, float& lo, float& hi);
float coverageSegment(glm::vec2 a, glm::vec2 b, float lo, float hi, glm::vec3 h0, glm::vec3 h1);
float coverageSquareEdge(glm::vec2 a, glm::vec2 b, float fa, float fb, glm::vec3 h0, glm::vec3 h1,
                         glm::vec2& leave, glm::vec2& enter);
glm::vec3 coverageProject(float l, glm::vec3 k0, glm::vec3 k1, glm::vec3 d0, glm::vec3 d1, float z0,
                          float z1, float w0, float w1, glm::vec3 pc, const CoverageLight& light);

} // namespace geometry::coverage_detail
