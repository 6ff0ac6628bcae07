// Percentage-closer soft shadows (Fernando 2005), the CPU side: the frame of the shadow maps.
// shaders/pcss-lookup.frag does the per-pixel blocker search and filtering in it.
//
// - One perspective shadow map per side of the light, from the light's centre looking along its
//   normal n (side 0) or along -n (side 1): the rectangular light emits to both sides (DESIGN.md
//   §2 has no facing term), and a room's ceiling above a light hung under it is lit. A side is
//   drawn only when some receiver lies on it.
// - Map coordinates m = (x, y) / z: x, y along the orthonormal lateral axes eu = u / |u| and
//   ev = n × eu, z the depth along the side's axis. Each side's map covers the box [lo, hi] of
//   m over every receiver triangle clipped to z >= zNear, clamped to |m| <= maxTan (a room whose
//   walls reach the light's plane would otherwise need a 180° frustum; receivers beyond it get
//   no shadow, and the lookup counts their pixels).
// - Depth zNear / z (reversed, float: precise far from the light; 0 = nothing drawn), written
//   by projection(side) with glClipControl(LOWER_LEFT, ZERO_TO_ONE), which the renderer sets.
// - casterNear: the least depth of caster geometry inside a side's frustum (triangles clipped to
//   it): the near plane that sizes the blocker search (the paper's "near plane").
#pragma once

#include <geometry/scene/Scene.h>

#include <glm/glm.hpp>

#include <cstddef>
#include <span>

namespace geometry {

struct PcssSide {
    bool present = false;          // a receiver lies on this side, deeper than zNear
    glm::vec2 lo{-1.0f}, hi{1.0f}; // the map's extent in m
    float casterNear = 0.0f;       // least caster depth inside the frustum; 0: no caster in it
    bool clamped = false;          // receivers reach beyond |m| = maxTan (not in the map)
};

struct PcssFrame {
    glm::vec3 center{0.0f};
    glm::vec3 normal{0.0f, -1.0f, 0.0f}; // unit, cross(u, v)
    glm::vec3 eu{1.0f, 0.0f, 0.0f};      // lateral axes: eu = u / |u|, ev = n × eu
    glm::vec3 ev{0.0f, 0.0f, 1.0f};
    // Half extents of the light along eu and ev: |u| and |v| for a rectangle (the brief's
    // "rectangular light": the search and filter regions are rectangles of these proportions,
    // not discs); for a parallelogram light, its bounding rectangle in (eu, ev).
    glm::vec2 halfSize{0.5f};
    float zNear = 1e-3f;
    PcssSide sides[2]; // 0: the side n points to, 1: the other

    glm::vec3 axis(int side) const { return side == 0 ? normal : -normal; }
    float depth(const glm::vec3& q, int side) const { return glm::dot(q - center, axis(side)); }
    glm::vec2 lateral(const glm::vec3& q) const {
        return {glm::dot(q - center, eu), glm::dot(q - center, ev)};
    }
    // Where q lands in side's map ([0, 1]^2 over [lo, hi]); q must be deeper than 0.
    glm::vec2 textureCoord(const glm::vec3& q, int side) const;
    // World -> clip of side's shadow pass: clip = ((2m - lo - hi) / (hi - lo) * z, zNear, z):
    // depth zNear / z, clipped where z < zNear.
    glm::mat4 projection(int side) const;
};

struct PcssFitSettings {
    float maxTan = 3.0f;         // the frustum's half-angle cap, tan (71.6°)
    float zNearFraction = 1e-4f; // zNear = this × the scene's bounding diagonal
};

// The frame for `scene`: every object receives (fits the maps), the objects in casterObjects
// (indices into scene.objects) cast (fit casterNear).
PcssFrame fitPcssFrame(const Scene& scene, std::span<const std::size_t> casterObjects,
                       const PcssFitSettings& settings = {});
// The same for another light than the scene's (RenderSettings::light).
PcssFrame fitPcssFrame(const Scene& scene, const RectLight& light,
                       std::span<const std::size_t> casterObjects,
                       const PcssFitSettings& settings = {});

} // namespace geometry
