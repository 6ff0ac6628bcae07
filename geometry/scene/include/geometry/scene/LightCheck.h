// Rejects scenes whose rectangular light intersects or touches scene geometry: the visibility
// integral over the light is meaningless when part of the light is inside or on an object.
#pragma once

#include <geometry/scene/Scene.h>

#include <glm/glm.hpp>

#include <cstddef>
#include <optional>
#include <string_view>

namespace geometry {

struct LightContact {
    std::size_t object;   // index into Scene::objects
    std::size_t triangle; // index into that object's MeshData::triangles
    glm::vec2 st;         // light coordinates (s, t) in [-1, 1]^2 of a point of contact
};

// First triangle (objects in order, then triangles in order) that comes within `tolerance` (an
// absolute world distance) of the light rectangle, or nullopt. Every object counts, including
// method None: it is still geometry the light would sit inside. Near the rectangle's edges the
// test is slightly conservative (distance measured per axis, not Euclidean). A light with
// (nearly) parallel u and v has no plane; validateScene rejects it, and here it yields nullopt.
std::optional<LightContact> findLightContact(const Scene& scene, float tolerance);
// The same for another light than the scene's (a moved or scaled one: bench sweeps, viewer).
std::optional<LightContact> findLightContact(const Scene& scene, const RectLight& light,
                                             float tolerance);

// The tolerance validateLightClear uses: 1e-4 of the light's diagonal (scale-invariant, about
// 1e-5 of the scene's diagonal for the framed default light), and at least 4 float epsilons of the
// light's largest coordinate (a light meant to rest on a surface far from the origin is within
// rounding of it). It depends on the light alone: a huge or far-away object elsewhere must not
// make surfaces metres from the light count as touching it.
float contactTolerance(const RectLight& light);

// Throws InputError naming the object, the triangle and where on the light the contact is, with
// contactTolerance(light).
void validateLightClear(const Scene& scene);
// The same for `light`; `what` names it in the message ("light" when empty).
void validateLightClear(const Scene& scene, const RectLight& light, std::string_view what);

} // namespace geometry
