// The `deep-sm` method's map (deep shadow maps, Lokovic & Veach 2000), built on the CPU: per
// texel of the pcss method's maps (PcssFrame.h: the faces of a cube around the light's centre
// that hold receivers and casters), the transmittance along the texel's ray as a function of
// depth, for the lookup's blocker search and filtering over the light (shaders/pcss-lookup.frag
// with DEEP_SHADOW_MAP).
//
// - Pixel-area filtered: each texel's function is the mean over S x S rays through its area
//   (stratified, one per cell of an S x S grid, jittered within it by a fixed pattern) of each
//   ray's transmittance T(z) = the product of (1 - alpha) over the surfaces it crosses nearer
//   than z (SurfaceQuery: alpha 1 for opaque materials, the fractional alpha of MASK and BLEND
//   ones, as raytrace's transmittance rule). Thin geometry that covers part of a texel, and
//   partly transparent surfaces, give fractional values instead of the all-or-nothing of a
//   depth map's one sample at the texel's centre.
// - Depth is the code t of s = zc / z along the face's axis, zc the face's least caster depth
//   (PcssFace::casterNear) and zFar the deepest receiver's (t = 1: sFar = zc / zFar), in 16
//   bits (shared/Pdsm.h pdsmDepthCode): the same coding and storage as the `pdsm` map's, and
//   the same compression with a guaranteed bound (PenumbraDeepShadowMap.h
//   compressPdsmStaircase: |T stored - T of the S x S rays| <= tolerance at every depth, the
//   8-bit values included). L&V compress each ray's function before averaging them; here the
//   mean staircase of a texel is compressed once, so that the bound holds for what is read.
// - Storage: per face and texel (first group of points, count | nearest code << 16): the
//   nearest surface any of its rays crosses, as a depth code (the blocker search's depth), and
//   the points four to three words (shared/Pdsm.h), one buffer for every face.
#pragma once

#include <geometry/core/Types.h>
#include <geometry/shadow/PcssFrame.h>

#include <glm/glm.hpp>

#include <array>
#include <cstdint>
#include <functional>
#include <vector>

namespace geometry {

// Every surface along origin + t dir for 0 < t < tfar, in order of t, up to and including the
// first opaque one (RayTracer::surfacesAlong). Called from many threads at once.
using SurfaceQuery = std::function<void(const glm::vec3& origin, const glm::vec3& dir, float tfar,
                                        std::vector<SurfaceHit>& out)>;

struct DeepShadowSettings {
    int resolution = 512; // texels per side of each face
    int supersample = 3;  // S: S x S rays per texel
    float tolerance = 0.004f;
    int threads = 0; // 0: std::thread::hardware_concurrency()
    // (rows done, rows) over every face built, from the calling thread.
    std::function<void(int, int)> progress;
};

struct DeepShadowFace {
    bool built = false; // the face's map is drawn (PcssFace::drawn): texels hold functions
    float zc = 0.0f;    // t = 0: the face's least caster depth
    float sFar = 0.5f;  // zc / the deepest receiver's depth along the face's axis, in (0, 1)
};

struct DeepShadowStats {
    std::uint64_t rays = 0;         // traced
    std::uint64_t crossings = 0;    // surfaces the rays crossed
    std::uint64_t points = 0;       // stored over every texel
    std::uint32_t texelsStored = 0; // texels with a function (not 1 everywhere)
    std::uint32_t longest = 0;      // the most points of one texel
    float maxDeviation = 0.0f;      // the largest |stored - staircase| of a texel
    double buildMs = 0.0;
};

struct DeepShadowMap {
    int resolution = 0;
    std::array<DeepShadowFace, kPcssFaces> faces{};
    // Per face, row (from lo, along b2) and column: first group, count | nearest code << 16.
    std::vector<std::uint32_t> index;
    std::vector<std::uint32_t> data; // the points, four per three words
    DeepShadowStats stats;

    std::size_t bytes() const { return (index.size() + data.size()) * sizeof(std::uint32_t); }
    std::size_t at(int face, int i, int j) const {
        return 2 * ((static_cast<std::size_t>(face) * resolution + static_cast<std::size_t>(j)) *
                        resolution +
                    static_cast<std::size_t>(i));
    }
};

// The face's depth range for receivers up to `receivers` (the scene's bounds).
DeepShadowFace deepShadowFace(const PcssFrame& frame, int face, const Aabb& receivers);

// Builds the functions of every drawn face of `frame`. Throws std::invalid_argument for a
// resolution or supersampling out of range, std::length_error past 2^32 points.
DeepShadowMap buildDeepShadowMap(const PcssFrame& frame, const Aabb& receivers,
                                 const SurfaceQuery& query, const DeepShadowSettings& settings);

// The transmittance of texel (i, j) of `face` at depth code t, as the lookup reads it (1 for a
// texel without points).
float evaluateDeepShadowMap(const DeepShadowMap& map, int face, int i, int j, float t);

// The nearest code of a texel (its index entry's high 16 bits) and its point count.
inline std::uint32_t deepNearestCode(std::uint32_t countWord) {
    return countWord >> 16;
}
inline std::uint32_t deepPointCount(std::uint32_t countWord) {
    return countWord & 0xFFFFu;
}

} // namespace geometry
