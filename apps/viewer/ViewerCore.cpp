#include "ViewerCore.h"

#include <geometry/reference/Framing.h>
#include <geometry/reference/RayTracer.h>
#include <geometry/scene/Scene.h>

#define GLM_ENABLE_EXPERIMENTAL
#include <glm/gtx/euler_angles.hpp>

#include <algorithm>
#include <cmath>

namespace viewer {

namespace {

constexpr float kMaxPitch = glm::radians(89.0f);

glm::vec3 direction(float yaw, float pitch) {
    return {-std::sin(yaw) * std::cos(pitch), std::sin(pitch), -std::cos(yaw) * std::cos(pitch)};
}

} // namespace

FlyCamera FlyCamera::fromCamera(const geometry::Camera& camera) {
    FlyCamera c;
    c.eye = camera.eye;
    const glm::vec3 d = glm::normalize(camera.target - camera.eye);
    c.pitch = std::clamp(std::asin(std::clamp(d.y, -1.0f, 1.0f)), -kMaxPitch, kMaxPitch);
    c.yaw = std::atan2(-d.x, -d.z);
    c.fovYDeg = camera.fovYDeg;
    return c;
}

glm::vec3 FlyCamera::forward() const { return direction(yaw, pitch); }

glm::vec3 FlyCamera::right() const { return {std::cos(yaw), 0.0f, -std::sin(yaw)}; }

geometry::Camera FlyCamera::camera() const {
    // A step float keeps distinct from the eye, far from the origin too.
    const float step = std::max(1.0f, 1e-3f * glm::length(eye));
    return {eye, eye + step * forward(), glm::vec3(0.0f, 1.0f, 0.0f), fovYDeg};
}

void FlyCamera::move(const glm::vec3& local, float seconds) {
    eye += (right() * local.x + glm::vec3(0.0f, local.y, 0.0f) + forward() * local.z) * speed *
           seconds;
}

void FlyCamera::look(float dYaw, float dPitch) {
    yaw = std::remainder(yaw + dYaw, glm::two_pi<float>());
    pitch = std::clamp(pitch + dPitch, -kMaxPitch, kMaxPitch);
}

OrbitCamera OrbitCamera::around(const FlyCamera& fly, float distance) {
    OrbitCamera o;
    o.distance = std::max(distance, 1e-3f);
    o.pivot = fly.eye + fly.forward() * o.distance;
    o.yaw = fly.yaw;
    o.pitch = fly.pitch;
    o.fovYDeg = fly.fovYDeg;
    return o;
}

geometry::Camera OrbitCamera::camera() const {
    const glm::vec3 eye = pivot - direction(yaw, pitch) * distance;
    return {eye, pivot, glm::vec3(0.0f, 1.0f, 0.0f), fovYDeg};
}

void OrbitCamera::rotate(float dYaw, float dPitch) {
    yaw = std::remainder(yaw + dYaw, glm::two_pi<float>());
    pitch = std::clamp(pitch + dPitch, -kMaxPitch, kMaxPitch);
}

void OrbitCamera::zoom(float factor) {
    if (factor > 0.0f && std::isfinite(factor)) distance = std::max(distance * factor, 1e-3f);
}

LightRig LightRig::fromLight(const geometry::RectLight& light) {
    LightRig r;
    r.center = light.center;
    r.halfU = glm::length(light.u);
    r.halfV = glm::length(light.v);
    const glm::vec3 x = light.u / r.halfU;
    const glm::vec3 z = glm::normalize(light.v - glm::dot(light.v, x) * x);
    const glm::vec3 y = glm::cross(z, x); // x × z = -y: the light faces -y of its own frame
    const glm::mat4 m(glm::vec4(x, 0.0f), glm::vec4(y, 0.0f), glm::vec4(z, 0.0f),
                      glm::vec4(0.0f, 0.0f, 0.0f, 1.0f));
    float yaw = 0.0f, pitch = 0.0f, roll = 0.0f;
    glm::extractEulerAngleYXZ(m, yaw, pitch, roll);
    r.yawDeg = glm::degrees(yaw);
    r.pitchDeg = glm::degrees(pitch);
    r.rollDeg = glm::degrees(roll);
    return r;
}

geometry::RectLight LightRig::light() const {
    const glm::mat4 m = glm::eulerAngleYXZ(glm::radians(yawDeg), glm::radians(pitchDeg),
                                           glm::radians(rollDeg));
    geometry::RectLight l;
    l.center = center;
    l.u = glm::vec3(m[0]) * halfU;
    l.v = glm::vec3(m[2]) * halfV;
    return l;
}

geometry::RectLight LightRig::animated(float seconds, float radius) const {
    geometry::RectLight l = light();
    const float phase = glm::two_pi<float>() * seconds / 6.0f;
    l.center += radius * (std::cos(phase) * glm::normalize(l.u) + std::sin(phase) * glm::normalize(l.v));
    return l;
}

geometry::Camera flyThrough(std::span<const geometry::Camera> cameras, int frame, int framesPerLeg) {
    const int n = static_cast<int>(cameras.size());
    if (n == 1 || framesPerLeg < 1) return cameras[0];
    const int leg = (frame / framesPerLeg) % n;
    const float s0 = static_cast<float>(frame % framesPerLeg) / static_cast<float>(framesPerLeg);
    const float s = s0 * s0 * (3.0f - 2.0f * s0); // ease in and out at each camera
    const geometry::Camera& a = cameras[static_cast<std::size_t>(leg)];
    const geometry::Camera& b = cameras[static_cast<std::size_t>((leg + 1) % n)];
    const glm::vec3 da = glm::normalize(a.target - a.eye), db = glm::normalize(b.target - b.eye);
    glm::vec3 d = glm::mix(da, db, s);
    d = glm::length(d) > 1e-3f ? glm::normalize(d) : (s < 0.5f ? da : db); // opposite views
    geometry::Camera c;
    c.eye = glm::mix(a.eye, b.eye, s);
    c.target = c.eye + std::max(1.0f, 1e-3f * glm::length(c.eye)) * d;
    c.up = a.up;
    c.fovYDeg = glm::mix(a.fovYDeg, b.fovYDeg, s);
    return c;
}

} // namespace viewer
