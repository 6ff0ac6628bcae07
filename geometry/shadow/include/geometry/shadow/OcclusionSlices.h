// Occlusion textures (Eisemann & Décoret 2006), the CPU side: the frustum the scene is sliced in
// and the arithmetic of one point's lookup. shaders/lib/Occlusion.glsl does the same lookup in
// float on the GPU; tests check eq. (4), the fade and the frame fit here.
//
// - Frustum: centre of projection (COP) behind the light at distance d on its axis, fitted to the
//   light (its cross-section in the light's plane is the light itself), so that the image of the
//   light seen from any point is a square kernel in texture space (paper §3.4, Fig. 5). d is the
//   largest that keeps every receiver vertex in the frustum, but not below the value at which the
//   frustum at the deepest receiver grows to `maxMagnification` light sizes (a room whose walls
//   reach the light's plane would otherwise need a 180° frustum). Receivers outside it, or
//   behind the light's plane, are not covered (covers): the method shadows them from PCSS's
//   shadow maps instead (OcclusionMethod, outside=pcss).
// - Slices: `slices` slabs parallel to the light over [zNear, zFar], the depth range that holds
//   caster geometry inside the frustum (z = distance from the light's plane along its axis;
//   computed per triangle from the casters' vertices, conservatively).
// - Lookup (paper §3.1–3.4): slice k is looked up at its middle plane z_k; its kernel is the
//   light seen from P through that plane, of side (z_P - z_k) / z_P light sizes (eq. 4), centred
//   on the segment from P to the light's centre; V = Π_k (1 - w_k I_k) (eq. 5) with I_k the
//   kernel's mean occupancy.
// - Fade, and where this departs from the paper: the slice containing P is never looked up (its
//   content may be P's own surface, Fig. 7: a floor at the far end of its slice would shadow
//   itself completely), and the slice before it fades in linearly with P's position in its own
//   slice: w_k = clamp(u - 1 - k, 0, 1), u = (z_P - zNear) / sliceDepth. V stays continuous
//   across slice planes; the price is a bias of one slice: occluders less than one to two slices
//   in front of P (contact shadows) are missed.
#pragma once

#include <geometry/scene/Scene.h>

#include <glm/glm.hpp>

#include <algorithm>
#include <cstddef>
#include <span>

namespace geometry {

// Relative margin of OcclusionFrame::covers (and its shader twin, OCCLUSION_COVER_MARGIN): the
// vertex that fits the frustum lies on its side plane, up to rounding.
inline constexpr float kOcclusionCoverMargin = 1e-4f;

struct OcclusionFrame {
    glm::vec3 center{0.0f};             // the light's centre
    glm::vec3 axis{0.0f, -1.0f, 0.0f};  // unit normal of the light, towards the sliced side
    glm::vec3 uStar{1.0f, 0.0f, 0.0f};  // dual basis of the light's half-axes: s = dot(q - c, uStar)
    glm::vec3 vStar{0.0f, 0.0f, 1.0f};  // and t = dot(q - c, vStar) are in [-1, 1] over the light
    float copDistance = 1.0f;           // d: the COP is center - d * axis
    float zNear = 0.0f, zFar = 1.0f;    // the sliced depth range
    int slices = 8;
    bool empty = true; // no caster geometry in the frustum in front of the light: V = 1
    bool receiversOutside = false; // some receiver vertex is not covered (see covers)

    float depth(const glm::vec3& q) const { return glm::dot(q - center, axis); }
    glm::vec2 lateral(const glm::vec3& q) const {
        return {glm::dot(q - center, uStar), glm::dot(q - center, vStar)};
    }
    float sliceDepth() const { return (zFar - zNear) / static_cast<float>(slices); }
    // The plane slice k is looked up at: its middle (the paper projects onto the far plane; the
    // middle halves the worst depth error of content spread through the slab).
    float planeDepth(int k) const { return zNear + (static_cast<float>(k) + 0.5f) * sliceDepth(); }
    // Slice of depth z, clamped to the range.
    int sliceOf(float z) const;
    // The frustum's cross-section at depth z, in light sizes (1 at the light's plane).
    float magnification(float z) const { return 1.0f + z / copDistance; }
    // q lies in the frustum, in front of the light: then every segment from q to the light
    // does (the frustum is convex and holds the light), so its lookup reads sliced texels only.
    // Points it does not cover (behind or in the light's plane, beyond the capped frustum: the
    // walls and ceiling of a room around a lamp) the slices cannot shadow.
    bool covers(const glm::vec3& q) const;
    // Where q lands in the occlusion textures ([0, 1]^2 over the frustum's cross-section).
    glm::vec2 textureCoord(const glm::vec3& q) const;
    // Clip coordinates of the slicing pass: (s, t, w / 2, w) with w = (d + z) / d. The depth is
    // unused (no depth test) and kept inside the clip volume; geometry behind the COP is clipped.
    glm::mat4 sliceProjection() const;
};

struct OcclusionFitSettings {
    // The frustum's cross-section at the deepest receiver may grow to this many light sizes.
    float maxMagnification = 16.0f;
};

// The frame for `scene`: every object receives (fits the frustum), the objects listed in
// `casterObjects` (indices into scene.objects) are sliced (fit the depth range).
OcclusionFrame fitOcclusionFrame(const Scene& scene, std::span<const std::size_t> casterObjects,
                                 int slices, const OcclusionFitSettings& settings = {});
// The same for another light than the scene's (RenderSettings::light).
OcclusionFrame fitOcclusionFrame(const Scene& scene, const RectLight& light,
                                 std::span<const std::size_t> casterObjects, int slices,
                                 const OcclusionFitSettings& settings = {});

// Slice k's share in V(P).
struct SliceLookup {
    float weight = 0.0f;     // w_k; 0: not looked up
    glm::vec2 center{0.0f};  // the kernel's centre in texture coordinates
    float width = 0.0f;      // the kernel's side in texture units (eq. 4 through the frustum)
};
SliceLookup sliceLookup(const OcclusionFrame& frame, const glm::vec3& p, int k);

// V(P) = Π_k (1 - w_k I_k), I_k = boxMean(k, center, width): the mean occupancy of slice k over
// the square kernel (its part outside the texture counts as empty).
template <class BoxMean>
double occlusionVisibility(const OcclusionFrame& frame, const glm::vec3& p, BoxMean&& boxMean) {
    if (frame.empty) return 1.0;
    double v = 1.0;
    for (int k = 0; k < frame.slices; ++k) {
        const SliceLookup s = sliceLookup(frame, p, k);
        if (s.weight <= 0.0f) break; // weights only fall with k
        v *= 1.0 - double(s.weight) * std::clamp(double(boxMean(k, s.center, s.width)), 0.0, 1.0);
    }
    return v;
}

// The fraction of the light in front of the plane through p with normal n (the side n points
// to): an opaque surface hides the rest of the light from its own points. Not in the paper
// (which leaves surfaces turned from the light to the diffuse term, §3.4 Fig. 8); the
// occlusion method multiplies V by it (parameter horizon=on).
float horizonFraction(const RectLight& light, const glm::vec3& p, const glm::vec3& n);

} // namespace geometry
