// Percentage-closer soft shadows (Fernando 2005), the CPU side: the frame of the shadow maps.
// shaders/pcss-lookup.frag does the per-pixel blocker search and filtering in it.
//
// - Up to six perspective shadow maps from the light's centre, the faces of a cube around it
//   (the rectangular light emits to both sides, DESIGN.md §2 has no facing term, and a lamp hung
//   in a room lights every wall, ceiling and floor around it):
//   - faces 0 and 1 look along the light's normal n and along -n, each fitted to the receivers
//     on its side within |m| <= maxTan (71.6° off the axis);
//   - faces 2..5 look along ±eu and ±ev, in the light's plane, and take every receiver beyond
//     that cap (walls reaching the light's plane): each covers the directions whose largest
//     lateral component is its axis, |m| <= 1 across and |m| <= 1 / maxTan towards ±n.
//   faceOf() is the rule that picks a point's face; the lookup applies the same one, to P and
//   to every search and filter sample (a kernel crossing a face's edge reads on in the next
//   face: the maps form one cube). A face is drawn when casters lie in it and receivers lie in
//   it or beside it.
// - Map coordinates m = (x, y) / z in a face's own axes (b1, b2, axis): x, y lateral, z the depth
//   along its axis. The front faces' lateral axes are the light's, eu = u / |u| and ev = n × eu.
// - Depth zNear / z (reversed, float: precise far from the light; 0 = nothing drawn), written
//   by projection(face) with glClipControl(LOWER_LEFT, ZERO_TO_ONE), which the renderer sets.
// - casterNear: the least depth of caster geometry inside a face's frustum (triangles clipped to
//   it): the near plane that sizes the blocker search (the paper's "near plane").
// - lightU / lightV: the light's half axes halfSize.x eu and halfSize.y ev in a face's
//   coordinates. The search and filter regions are the light seen from P through a plane of the
//   face, sample by sample (throughLight): on the front faces the paper's rectangle
//   halfSize (1/z - 1/zP), on the side faces the light seen edge-on.
#pragma once

#include <geometry/scene/AlphaMask.h>

#include <geometry/scene/Scene.h>

#include <glm/glm.hpp>

#include <cstddef>
#include <span>
#include <vector>

namespace geometry {

inline constexpr int kPcssFaces = 6;

struct PcssFace {
    glm::vec3 axis{0.0f, -1.0f, 0.0f}; // unit depth axis
    glm::vec3 b1{1.0f, 0.0f, 0.0f};    // unit lateral axes, orthogonal to it and each other
    glm::vec3 b2{0.0f, 0.0f, 1.0f};
    bool present = false;          // a receiver lies in this face, deeper than zNear
    glm::vec2 lo{-1.0f}, hi{1.0f}; // the map's extent in m
    float casterNear = 0.0f;       // least caster depth inside the frustum; 0: no caster in it
    bool drawn = false;            // its map is drawn: casters in it, and receivers in it or
                                   // in a face beside it (whose kernels read on into it)
    bool clamped = false;          // front faces: receivers reach beyond |m| = maxTan (they go
                                   // to the side faces)
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
    float maxTan = 3.0f;
    PcssFace faces[kPcssFaces]; // 0: along n, 1: along -n, 2..5: along eu, -eu, ev, -ev

    float depth(const glm::vec3& q, int face) const {
        return glm::dot(q - center, faces[face].axis);
    }
    glm::vec2 lateral(const glm::vec3& q, int face) const {
        return {glm::dot(q - center, faces[face].b1), glm::dot(q - center, faces[face].b2)};
    }
    // q - center in face's coordinates (b1, b2, axis).
    glm::vec3 local(const glm::vec3& q, int face) const {
        return {lateral(q, face), depth(q, face)};
    }
    // The face whose map holds q, or -1 for points within zNear of the centre (counted, V = 1).
    int faceOf(const glm::vec3& q) const;
    // Where q lands in face's map ([0, 1]^2 over [lo, hi]); q must be deeper than 0.
    glm::vec2 textureCoord(const glm::vec3& q, int face) const;
    // World -> clip of face's shadow pass: clip = ((2m - lo - hi) / (hi - lo) * z, zNear, z):
    // depth zNear / z, clipped where z < zNear.
    glm::mat4 projection(int face) const;
    // The light's half axes halfSize.x eu, halfSize.y ev in face's coordinates.
    glm::vec3 lightU(int face) const;
    glm::vec3 lightV(int face) const;
};

// Where the segment from P (face coordinates p, depth p.z) to a point L of the light (face
// coordinates l) crosses depth z, in map coordinates: the texel a blocker at depth z between
// them covers. The share along the segment is clamped to it (z beyond P or behind L).
glm::vec2 throughLight(const glm::vec3& p, const glm::vec3& l, float z);

struct PcssFitSettings {
    float maxTan = 3.0f;         // the front faces' half-angle cap, tan (71.6°)
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

// The least depth along face `face`'s axis of the triangles of `objects` (indices into
// scene.objects) clipped to the frustum z >= zMin, lo z <= (x, y) <= hi z in that face's
// coordinates; 0 when none reaches it.
float casterNearInFrustum(const PcssFrame& f, int face, glm::vec2 lo, glm::vec2 hi, float zMin,
                          const Scene& scene, std::span<const std::size_t> objects);

// At most maxBoxes boxes that together hold every point of the objects (indices into
// scene.objects) that occludes: each triangle's occlusionBounds (geometry/scene/AlphaMask.h: an
// alpha-tested triangle only around its texels at or over the cutoff, none where it has none),
// split at the median of their centres along the longest axis of their bounds, recursively,
// each leaf's bounds a box. One object spread over a whole level (a textured level's
// alpha-tested part: grates and flames in every room) gets boxes around its clusters instead of
// the level's bounds, and a light beam around a lamp a box around its few opaque texels
// instead of one holding the lamp. Empty where nothing occludes. `rule`: which points hide
// light (deep-sm's transmittance rule: every point of opacity above 0).
std::vector<Aabb> casterClusters(const Scene& scene, std::span<const std::size_t> objects,
                                 int maxBoxes, AlphaRule rule = AlphaRule::Cutoff);

// Whether a segment from some point of box `from` to the point `to` meets `box`: the union of
// the boxes (1 - s) from + s to, s in [0, 1] (the hull of `from` and `to`), tested per axis as
// an interval of s. Exact up to rounding. pcss's reach test per pixel is the case of a box of
// one point (to the light's centre, against a caster box grown by the light's half extents);
// per screen tile, of the tile's surface box.
bool sweepMeetsBox(const Aabb& from, const glm::vec3& to, const Aabb& box);

} // namespace geometry
