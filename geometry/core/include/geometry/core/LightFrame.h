// The rectangular light's frame in double precision, as every CPU model and oracle uses it:
// centre, half-axes, unit normal and the dual basis of the half-axes, so that a point y of the
// light's plane has light coordinates s = dot(uStar, y - c), t = dot(vStar, y - c) (the light
// is [-1, 1]^2), also for a parallelogram. The shaders' float frame is shader::CoverageLight
// (shaders/shared/Coverage.h), filled the same way.
#pragma once

#include <geometry/core/Types.h>

#include <glm/glm.hpp>

namespace geometry {

struct LightFrame {
    glm::dvec3 c, u, v, n;   // centre, half-axes, unit normal along cross(u, v)
    glm::dvec3 uStar, vStar; // dual basis: dot(uStar, u) = 1, dot(uStar, v) = 0, both ⟂ n
};

inline LightFrame lightFrame(const RectLight& light) {
    LightFrame f;
    f.c = glm::dvec3(light.center);
    f.u = glm::dvec3(light.u);
    f.v = glm::dvec3(light.v);
    const glm::dvec3 n = glm::cross(f.u, f.v);
    f.n = n / glm::length(n);
    const glm::dvec3 a = glm::cross(f.v, f.n), b = glm::cross(f.n, f.u);
    f.uStar = a / glm::dot(f.u, a);
    f.vStar = b / glm::dot(f.v, b);
    return f;
}

} // namespace geometry
