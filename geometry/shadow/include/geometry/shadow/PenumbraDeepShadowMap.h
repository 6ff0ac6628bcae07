// The `pdsm` method's map (penumbra deep shadow maps, St-Amour, Paquette & Poulin 2005), built
// on the CPU from the `sample-maps` method's shadow maps (SampleMapFrame.h: one per light
// sample, all looking along the light's normal n with its lateral axes).
//
// A texel of the deep map is a ray from the light's centre c through m = (x, y) / z in (eu, ev,
// n), over the region where some sample's map may hide a receiver. Along it, the points
// q(s) = c + (zNear / s) (m, 1) for s = zNear / z in [sFar, 1] (reversed depth, as the maps store
// it). From sample y_i = c + d_i (d_i lateral: depth along n is the same from every sample),
// q(s) lies in map i at m - d_i s / zNear: a straight line through the map, affine in s. It is
// hidden from y_i where that map's texel holds a caster nearer to y_i (stored value
// > s (1 + depthBias), the comparison of the sample-maps lookup, one texel, no filtering). The
// build walks that line through map i's texels (a 2D DDA) and turns each texel's stored value
// into the exact interval of s it hides: per sample a set of hidden intervals, per texel the sum
// over the samples, V(t) = 1 - hidden / N, a staircase in the depth code t (shared/Pdsm.h).
// The staircase is then compressed to a piecewise-linear function with a guaranteed bound:
// |V_stored(t) - V_staircase(t)| <= bound(V_staircase(t)) at every t (PdsmBound: the tolerance,
// or a share of the k samples' standard error where V is between 0 and 1), quantisation of the
// values to 8 bits included (the staircase's steps themselves lie on the 16-bit depth codes).
// The compression is Lokovic & Veach's (2000) greedy one: from each segment's start, the window
// of slopes that keep every later step within the bound is narrowed step by step, and the
// segment ends where it would empty; a step larger than the bounds of its two sides together is
// stored as a step (two points at one depth).
//
// Storage (the slides' index + data textures): per texel (first group, point count) and the
// points, 24 bits each, four in three 32-bit words (shared/Pdsm.h), each texel's from a group's
// start. A texel whose function is 1
// everywhere stores no point. The lookup (shaders/pdsm-lookup.frag) reads it with the same
// statements as evaluatePdsm below.
#pragma once

#include <geometry/core/Types.h>
#include <geometry/shadow/PcssFrame.h>
#include <geometry/shadow/SampleMapFrame.h>

#include <glm/glm.hpp>

#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <vector>

namespace geometry {

// The deep map's frame: the light's centre and axes (those of the sample maps), the extent in
// m and the depth range.
struct PdsmGrid {
    glm::vec3 centre{0.0f};
    glm::vec3 eu{1, 0, 0}, ev{0, 0, 1}, n{0, -1, 0};
    glm::vec2 lo{0.0f}, hi{0.0f}; // extent in m from the centre
    int resolution = 0;           // texels per row (along eu)
    int rows = 0;                 // rows (along ev): resolution, or fewer for a cube's side
                                  // face, whose band is a third as tall as it is wide
    float zNear = 0.0f;           // the casters' least depth along n (t = 0)
    float sFar = 0.0f;            // zNear / the deepest receiver's depth (t = 1), in (0, 1)
    // The extent was capped at kSampleMapMaxTan, or the sample frame is clipped: receivers the
    // map does not hold may be hidden (the lookup counts them).
    bool clipped = false;
    // A caster may lie nearer to the centre than zNear (a cube face's zNear held beyond its
    // samples' own depth; for the one map, its frame clipped at all): a receiver nearer than
    // zNear, drawn lit, may then be hidden (the lookup counts it).
    bool nearClipped = false;
    bool empty = true; // no casters: every receiver lit

    int rowCount() const { return rows > 0 ? rows : resolution; }
    // The texel centre's m of texel (i, j) (column i, row j from lo).
    glm::vec2 texelCentre(int i, int j) const;
};

// The region the deep map must hold: every receiver that some sample's map may hide
// (geometry::inReach's bound over the depths up to the deepest receiver of `scene`), capped at
// kSampleMapMaxTan. `scene`: the bounds of everything that may receive (all objects).
PdsmGrid fitPdsmGrid(const SampleMapFrame& frame, const glm::vec3& lightCentre, const Aabb& scene,
                     int resolution);

// A deep map per face of a cube around the light's centre, for receivers one frustum along
// the light's normal cannot hold (fitPdsmGrid's map clipped: a lamp in a room, whose walls,
// floor and ceiling lie all around it, the light emitting to both sides). The faces are pcss's
// (PcssFrame.h: 0 and 1 along ±n up to 71.6° off it, 2..5 along ±eu and ±ev, the bands beyond),
// each with its own k sample maps looking along its axis from the same light samples, and its
// own deep map over the face's directions from the centre. On the front faces the samples lie
// in the maps' plane, as in the one-map case; on a side face a sample lies `depth` ahead of the
// centre along the face's axis (SampleMapView::depth), its own near plane that much nearer,
// and a texel ray's line through its map affine in 1 / (z - depth) (the walk handles both).
// - A face is built where receivers lie in it (pcss's `present`) and casters lie within its
//   sample maps' reach (their views, capped at |m| <= kPdsmViewCap); a face without casters
//   is lit.
// - zNear of a face: the casters' least depth along its axis in that reach, held beyond the
//   samples' own depth along it (every view's near plane in front of its sample); a caster
//   nearer than that is missed, and the face says so (clipped), as is one whose views reach
//   past the cap.
// - A view's extent: the face's region seen from its sample over the face's depths (the
//   region's corners at zNear and the deepest receiver, bilinear in m and 1 / (z - depth)),
//   narrowed to the casters' box where the box lies wholly in front of it.
inline constexpr float kPdsmViewCap = kSampleMapMaxTan;

struct PdsmFace {
    int face = 0; // the cube face (PcssFrame's numbering)
    SampleMapFrame frame;
    PdsmGrid grid;
};

// The faces to build for `light`'s samples (st in [-1, 1]^2): `cube` fitted to the scene's
// receivers and `casterObjects`, whose bounds are `casters`; `scene`: the receivers' bounds.
std::vector<PdsmFace> fitPdsmCube(const PcssFrame& cube, const RectLight& light,
                                  std::span<const glm::vec2> samples, const Scene& sceneObjects,
                                  std::span<const std::size_t> casterObjects, const Aabb& casters,
                                  const Aabb& scene, int resolution);

// One step of a texel's staircase: at depth code `code` V goes from `before` to `after`.
struct PdsmStep {
    std::uint32_t code = 0;
    float before = 1.0f, after = 1.0f;
    bool exact = false; // stored as a step (two points) whatever the bound
};

// A stored point before packing: depth code and value in [0, 1].
struct PdsmPoint {
    std::uint32_t code = 0;
    float value = 1.0f;
};

// The compression's tolerance is a bound on |dV|. A run of one-sample steps (1 / k each) can be
// cut through by a line only where the bound is above 1 / (2 k) plus the 8-bit values' half
// step (0.5 / 255); below that every step is kept as a step (two points). The method's default,
// 0.004, just cuts through single steps at k = 256 and keeps every step at k <= 128. At 256²
// against `reference` N = 1024 (docs/bench-pdsm.md), data/plates-three.json errs by 0.0020 at
// 0.003 and 0.004, 0.0021 at 0.008, 0.0026 at 0.016 and 0.0041 at 0.032, with 155, 72, 18, 7
// and 5 points per stored texel; the sphere 0.0007, 0.0007, 0.0008, 0.0011, 0.0019;
// spheres-nine 0.0027 at 0.004 and 0.0029 at 0.008, the demo 0.0011 and 0.0021 (those with the
// tolerance alone, noise = 0). With the noise bound, the method's default 0.5 (same view, 256²):
// spheres-nine 0.0028, plates-three 0.0021 (1 standard error: 0.0023); oa_dm5's spawn
// view with the lamp 0.0044 and 88 MiB (noise 0: 0.0044 and 316 MiB; 2: 0.0046, 27 MiB).

// The compression's bound where the staircase has the value V: `tolerance` everywhere, and
// where `noise` > 0, up to `noise` standard errors of a k-sample estimate of V,
// sqrt(V (1 - V) / k), where that is more. The staircase is the k samples' estimate of the true
// V: where V lies between 0 and 1 it is itself off by about that much (0.031 at V = 1/2, k = 256),
// and a bound far below it stores the samples' noise point by point; where V is 0 or 1 (lit, in
// umbra: most of a level's receivers) the estimate is exact and the bound is `tolerance`.
struct PdsmBound {
    float tolerance = 0.004f;
    float noise = 0.0f;
    int samples = 0; // k (noise > 0 only)
    float at(float v) const;
};

// The piecewise-linear function within the bound of the staircase that starts at `start`
// (V at t = 0) and steps at `steps` (codes strictly increasing, in (0, 65535]), values
// quantised to 8 bits (the bound includes them): |stored - staircase| <= bound.at(staircase) at
// every depth. tolerance > 0.5 / 255.
std::vector<PdsmPoint> compressPdsmStaircase(float start, std::span<const PdsmStep> steps,
                                             const PdsmBound& bound);
inline std::vector<PdsmPoint> compressPdsmStaircase(float start, std::span<const PdsmStep> steps,
                                                    float tolerance) {
    return compressPdsmStaircase(start, steps, PdsmBound{.tolerance = tolerance});
}

// The largest |stored - staircase| over every depth (exact: both are linear or constant between
// the steps and the points, which lie on the steps' codes), the stored function read as the
// lookup reads it (shared/Pdsm.h pdsmSegment, values decoded from their 8 bits).
float pdsmDeviation(float start, std::span<const PdsmStep> steps,
                    std::span<const PdsmPoint> points);

// The largest |stored - staircase| - bound.at(staircase) over every depth (exact, as
// pdsmDeviation): at most 0 where the stored function keeps the bound.
float pdsmExcess(float start, std::span<const PdsmStep> steps, std::span<const PdsmPoint> points,
                 const PdsmBound& bound);

// Shifts each sample map's texel grid by its own fraction of a texel (the window widened by one
// texel, its start moved by a share of it from the R2 sequence over the sample's index). Fitted
// to the same box, the maps put a caster's edge at about the same fraction of a texel in every
// map, so that rounding every sample's edge to texel centres moved all of them the same way: on
// data/box.json (axis-aligned, as its maps are) V came out lighter by 0.8 of a sample on average
// over the penumbra (k = 64); with the grids shifted the k roundings average out
// (PenumbraDeepShadowMapTest.ShiftedGridsDoNotBiasThePenumbra).
void jitterSampleMapGrids(SampleMapFrame& frame, int resolution);

// The sample maps as read back: views.size() layers of resolution^2 values zNear / z (0: no
// caster), rows bottom-up (GL order).
struct PdsmMaps {
    int resolution = 0;
    std::span<const float> texels;
};

// A range of depth codes [lo, hi] (0 .. 65535).
struct PdsmCodeRange {
    std::uint32_t lo = 0, hi = 0;
};

// Where the lookup may read a deep map's functions: per texel, the depth codes at which it
// reads that texel for a point of one of the receivers' triangles (shared/Pdsm.h
// pdsmReadDepth: a receiver within a texel of the texel's ray, per axis, reads it where the
// ray meets the receiver's plane, held within `spanTexels` texels of the receiver's depth and
// no deeper than it). A level's texel ray crosses a wall, then rock, then the next room: most
// of its depth holds no surface, and V there is never read. Per triangle (clipped to the
// map's near plane) and texel within a texel of its projection's bounding box: the depths of
// its plane over the texel's 2 x 2-texel square (the plane's depth is monotone in 1 / z, affine
// in m, so its extremes lie at the square's corners), within the triangle's own depths (less
// the span); where the plane is seen edge-on in the square, the triangle's depths. A texel on
// the grid's edge also takes, where the triangle reaches past that edge, the triangle's depths
// (the cube's lookup clamps a receiver past its face's edge to it). Conservative: a range may
// hold depths no receiver reads, never the reverse (PenumbraDeepShadowMapTest holds random
// receivers' reads to it). With the lookup's normal offset (shared/Pdsm.h pdsmOffsetReceiver:
// at most offsetTexels texels at the receiver's depth, either way along the normal) the
// triangle's box and the squares are widened by what the offset may move a point's
// projection, its depths by the offset, and its plane taken at both extremes of the shift; with
// `lightCorners` (the light's four corners, for a lookup that reads only receivers facing some
// of the light: plane=on), towards the light alone where the light lies wholly on one side of
// the triangle's plane.
class PdsmReadDepths {
public:
    PdsmReadDepths(const PdsmGrid& grid, std::span<const glm::vec3> triangles, float spanTexels,
                   float offsetTexels = 0.0f, std::span<const glm::vec3> lightCorners = {});

    // The ranges of texel (i, j) for every column i of row j, each sorted and disjoint (ranges
    // less than kMergeGap codes apart merged); empty where no receiver reads it.
    void row(int j, std::vector<std::vector<PdsmCodeRange>>& ranges) const;

    static constexpr std::uint32_t kMergeGap = 32;

private:
    struct Triangle {
        glm::vec3 nm{0.0f}; // the plane dot(nm, (x, y, z)) = d in the map's axes from the centre
        float d = 0.0f;
        float z0 = 0.0f, z1 = 0.0f; // the clipped triangle's depths
        float reach = 0.0f;         // how far in m the offset may move a point's projection
        int towards = 0;            // the offset's side: the sign of dot(nm, X) - d, or 0: both
        int i0 = 0, i1 = -1;        // its columns
        bool pastLo[2] = {false, false}, pastHi[2] = {false, false}; // reaches past an edge
    };
    PdsmGrid mGrid;
    float mTexelU = 0.0f, mTexelV = 0.0f, mLowShare = 0.0f;
    float mOffset = 0.0f; // the offset's largest delta / zP
    std::vector<Triangle> mTriangles;
    std::vector<std::vector<std::uint32_t>> mRows; // per row, the triangles that may reach it
};

// Holds the staircase (start, steps) only within `kept` (sorted, disjoint, not empty): between
// two ranges it keeps the value it had at the end of the first, and steps to the staircase's
// value at the start of the next; before the first it holds the value there, after the last
// the value at its end. Returns the new start; `steps` replaced.
float maskPdsmStaircase(float start, std::vector<PdsmStep>& steps,
                        std::span<const PdsmCodeRange> kept);

struct PdsmBuildSettings {
    float tolerance = 0.004f;
    float noise = 0.0f; // PdsmBound::noise (k: the frame's views)
    float depthBias = 1e-3f; // hidden where the stored value > s (1 + depthBias)
    int threads = 0;         // 0: std::thread::hardware_concurrency()
    // The receivers' triangles (world space, three corners each): each texel's function is
    // kept only at the depths where the lookup may read it for a point of one of them
    // (PdsmReadDepths, masked by maskPdsmStaircase), and a texel no receiver reads is not
    // walked; null: every depth (receivers whose depths are not known when the map is built:
    // dynamic objects).
    std::shared_ptr<const std::vector<glm::vec3>> receivers;
    float readSpanTexels = 16.0f; // the lookup's RECEIVER_PLANE_SPAN
    float readOffsetTexels = 0.0f; // the lookup's largest normal offset: bias PDSM_OFFSET_MAX_TAN
    // The light's corners where the lookup reads only receivers facing some of it (plane=on;
    // empty: any receiver).
    std::vector<glm::vec3> lightCorners;
    // (rows done, rows), from the calling thread.
    std::function<void(int, int)> progress;
};

struct PdsmStats {
    std::uint64_t points = 0;        // stored points over all texels
    std::uint64_t steps = 0;         // the staircases' steps before compression
    std::uint32_t texelsStored = 0;  // texels with a function (not 1 everywhere)
    std::uint32_t texelsRead = 0;    // texels a receiver may read (all, without receivers)
    std::uint64_t codesKept = 0;     // the depth codes kept over those texels
    std::uint32_t longest = 0;       // the most points of one texel
    float maxDeviation = 0.0f;       // the largest pdsmDeviation over the texels
    float maxExcess = -1.0f;         // the largest pdsmExcess over the texels (<= 0: in bound)
    double buildMs = 0.0;            // the walk and the compression (CPU)
};

struct Pdsm {
    PdsmGrid grid;
    // Per texel (row-major from lo, rows along ev): its first group of points and its point
    // count. Each texel's points start a group (a bisection reads whole groups).
    std::vector<std::uint32_t> index;
    // The points, four per three words (shared/Pdsm.h); each texel's last group padded.
    std::vector<std::uint32_t> data;
    PdsmStats stats;

    std::size_t bytes() const {
        return (index.size() + data.size()) * sizeof(std::uint32_t);
    }
};

Pdsm buildPdsm(const SampleMapFrame& frame, const PdsmGrid& grid, const PdsmMaps& maps,
               const PdsmBuildSettings& settings);

// Lays out one row of `texels` texels: `index` holds two words per texel, the first group
// (written here) and a word whose bits `countMask` are its point count (read); the row's points
// (24 bits each, texel after texel) are packed into `data` from group `group`, each texel's from a
// group's start. Returns the group after the row's.
std::uint32_t packPdsmRow(std::span<const std::uint32_t> points, std::uint32_t* index, int texels,
                          std::uint32_t countMask, std::uint32_t group, std::uint32_t* data);

// Packs 24-bit points (depth code | value code << 16) four to three words from `words`
// (zeroed, 3 ceil(n / 4) of them).
void packPdsmPoints(std::span<const std::uint32_t> points, std::uint32_t* words);

// The function of `count` points from group `first` of `data` at depth code t, as the lookups
// read it (shaders/lib/Pdsm.glsl pdsmFunction; 1 for no points).
float evaluatePdsmFunction(std::span<const std::uint32_t> data, std::uint32_t first,
                           std::uint32_t count, float t);

// V of texel (i, j) at depth code t, as the lookup reads it.
float evaluatePdsm(const Pdsm& map, int i, int j, float t);

} // namespace geometry
