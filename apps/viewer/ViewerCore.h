// The viewer's CPU-side state, kept apart from the window so it can be tested without one:
// - FlyCamera: eye + yaw/pitch (world up = +Y), moved in its own frame (WASD + QE);
// - OrbitCamera: yaw/pitch/distance around a pivot;
// - LightRig: the rectangular light as centre, half-sizes and yaw/pitch/roll (what the panel
//   edits), with an optional circular animation in the light's plane;
// - flyThrough(): a path through the glTF cameras (spawn points) for scripted captures;
// - lampAhead(): the lamp the viewer (and the soak) hangs at a view.
#pragma once

#include <geometry/core/Types.h>
#include <geometry/reference/Framing.h>

#include <optional>
#include <span>
#include <vector>

namespace geometry {
struct Scene;
class RayTracer;
} // namespace geometry

namespace viewer {

struct FlyCamera {
    glm::vec3 eye{0.0f};
    float yaw = 0.0f;   // radians about +Y; 0 looks along -Z
    float pitch = 0.0f; // radians, clamped to ±89°
    float fovYDeg = 60.0f;
    float speed = 2.0f; // metres per second

    static FlyCamera fromCamera(const geometry::Camera& camera);
    geometry::Camera camera() const;
    glm::vec3 forward() const;
    glm::vec3 right() const;
    // `local`: x right, y world up, z forward; scaled by speed * seconds.
    void move(const glm::vec3& local, float seconds);
    void look(float dYaw, float dPitch);
};

struct OrbitCamera {
    glm::vec3 pivot{0.0f};
    float distance = 5.0f;
    float yaw = 0.0f, pitch = 0.3f;
    float fovYDeg = 60.0f;

    // Orbits around the point `distance` in front of the fly camera.
    static OrbitCamera around(const FlyCamera& fly, float distance);
    geometry::Camera camera() const;
    void rotate(float dYaw, float dPitch);
    void zoom(float factor); // distance *= factor, kept positive
};

struct LightRig {
    glm::vec3 center{0.0f};
    float halfU = 0.5f, halfV = 0.5f;          // half-widths along the light's axes
    float yawDeg = 0.0f, pitchDeg = 0.0f, rollDeg = 0.0f; // 0,0,0: u = +X, v = +Z, facing -Y

    // Exact for lights with perpendicular axes (every scene in data/ and the levels' framing);
    // a skewed parallelogram is squared up (its axes' lengths are kept).
    static LightRig fromLight(const geometry::RectLight& light);
    geometry::RectLight light() const;
    // The light moved along a circle of radius `radius` in its own plane, `seconds` into a
    // 6-second period.
    geometry::RectLight animated(float seconds, float radius) const;
};

// The camera `t` frames along a path visiting `cameras` in order (eye lerped, view direction
// slerped), `framesPerLeg` frames from one to the next; wraps around. Needs at least one camera.
geometry::Camera flyThrough(std::span<const geometry::Camera> cameras, int frame, int framesPerLeg);

// The viewer's lamp for a view (geometry::lampAhead, beside hangLight in Framing.h).
using geometry::lampAhead;

} // namespace viewer
