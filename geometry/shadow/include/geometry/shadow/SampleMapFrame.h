// The `sample-maps` method's frame: one shadow map per light sample (the reference's stratified
// points for the same N and seed), each a perspective view from its sample point, fitted to the
// casters' bounding box. V at a receiver is the share of the N points from which it is seen: the
// `reference` method's average of hard shadows, with shadow maps instead of volumes so that
// alpha-tested casters (leaf cards, grates) cut their texels out (Heckbert & Herf 1997 average
// hard shadows from light samples in the same way).
//
// Every map looks along the light's normal n (towards the casters) with the light's lateral axes
// (eu, ev): a receiver's map coordinates from sample y are m = (x, y) / z of q - y in (eu, ev, n).
// A map only has to hold the casters, not the receivers: a receiver whose ray to y misses the
// casters' box is lit from y, so a point outside a map's extent, or nearer to the light than the
// casters (z <= zNear), is lit from that sample. The fit is exact while every box corner lies in
// front of every sample by at least kSampleMapMinDepthShare of the box's depth; otherwise the box
// is clipped there and at the lateral cap, and the frame says so (`clipped`), since casters
// outside the frusta would then be missed.
#pragma once

#include <geometry/core/Types.h>

#include <glm/glm.hpp>

#include <span>
#include <vector>

namespace geometry {

// A map's extent is capped at |m| <= this (71.6 degrees off the light's normal), as pcss's front
// faces are.
inline constexpr float kSampleMapMaxTan = 3.0f;
// The nearest box corner must lie at least this share of the farthest one's depth in front of
// every sample point (else the perspective maps would need texels without bound).
inline constexpr float kSampleMapMinDepthShare = 0.02f;

struct SampleMapView {
    glm::vec2 st{0.0f};     // the sample in [-1, 1]^2 over the light's half axes
    glm::vec3 origin{0.0f}; // the sample point on the light
    glm::vec2 lo{0.0f}, hi{0.0f}; // the map's extent in m
    // The origin's depth along n from the light's centre: 0 for samples of a map looking along
    // the light's normal (every sample lies in the light's plane); a map looking along one of
    // the light's lateral axes (pdsm's cube faces) sees its samples ahead of or behind the
    // centre.
    float depth = 0.0f;
    // The view's near plane, from its origin along n (SampleMapFrame::viewNear); it stores
    // near / z of its own depth z. 0: at the frame's zNear from the centre, zNear - depth from
    // the origin. pdsm's cube faces give a view behind the centre a nearer plane of its own, so
    // that it sees the casters between it and the frame's zNear (a shelf beside the light).
    float near = 0.0f;
};

struct SampleMapFrame {
    glm::vec3 eu{1, 0, 0}, ev{0, 0, 1}, n{0, -1, 0}; // orthonormal, n towards the casters
    std::vector<SampleMapView> views;
    // Where a receiver can be hidden from some sample at all (inReach): in m from the light's
    // centre, m_c(P) = (x, y) / z of P - c. From sample y = c + d (d in the light's plane, so
    // depths along n are the same from every sample), m_y(P) = m_c(P) - d / z_P and a box
    // corner's m_y(q) = m_c(q) - d / z_q with z_q in [zNear, zFar]: P can lie in map y's extent
    // only if m_c(P) lies within the centre's extent [centreLo, centreHi] widened by
    // |d| max(|1/z_P - 1/zNear|, |1/z_P - 1/zFar|) per axis (|d| <= half), plus the maps' own
    // margins. The lookup skips the maps for every other receiver. A clipped frame has no such
    // bound (reachAll).
    glm::vec2 centreLo{0.0f}, centreHi{0.0f};
    glm::vec2 half{0.0f}; // the light's half extent along eu and ev
    float zFar = 0.0f;
    bool reachAll = true;
    bool empty = true;   // no casters: nothing to draw, V = 1
    // The casters' least depth along n (> 0), the near plane of every view: depth along n is
    // the same from every point of the light (n is its normal).
    float zNear = 0.0f;
    bool clipped = false; // the box reached behind a sample or past the cap (see above)

    // View i's near plane from its origin along n: its own (SampleMapView::near) or zNear - depth.
    float viewNear(std::size_t i) const {
        const SampleMapView& v = views[i];
        return v.near > 0.0f ? v.near : zNear - v.depth;
    }
    // World -> clip of view i's shadow pass, for glClipControl(LOWER_LEFT, ZERO_TO_ONE):
    // x, y over [lo, hi], depth near_i / z (1 at near_i = viewNear(i), 0 infinitely far;
    // reversed).
    glm::mat4 projection(std::size_t i) const;
};

// `samples` in [-1, 1]^2 on the light (stratifiedSquare). `casters`: their world bounds (empty:
// an empty frame).
SampleMapFrame fitSampleMapFrame(const RectLight& light, std::span<const glm::vec2> samples,
                                 const Aabb& casters);

// Whether a receiver at p can be hidden from any of the frame's samples (see centreLo above);
// the lookup's test, in shaders/sample-maps-lookup.frag, is the same.
bool inReach(const SampleMapFrame& f, const glm::vec3& lightCenter, const glm::vec3& p);

// True when every light point sees the whole box in front of it within the cap (the fit is then
// exact for any samples): the rule by which `auto` gives an alpha-tested object to sample maps.
bool sampleMapsHold(const RectLight& light, const Aabb& casters);

} // namespace geometry
