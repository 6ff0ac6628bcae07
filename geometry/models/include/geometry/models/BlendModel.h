// CPU model (double precision) of per-silhouette visibility buffers blended with overlap
// correction, `wedges-blend` (Forest, Barthe & Paulin 2006, slides "Penumbra blending [1/6]-[6/6]"
// and "GPU implementation [2/4]"; DESIGN.md §4 "Per-silhouette blending"), and of the two
// combinations it is compared with, `wedges-additive` and `wedges-multiply`. It is the oracle the
// GPU passes are tested against, so the per-fragment steps are small functions named as the
// shaders name them (projectEdge, partCoverage, partRectangle, blendPart, packRect8, ...).
//
// Frames. Light coordinates (s, t) in [-1, 1]^2 with the light centre at the origin
// (geometry/shadow/Wedge.h). The light is split into R radial parts around its centre (R = 1, 4, 8),
// each measured in its own frame (radialPart):
// - R = 4 (the paper): quadrant (σx, σy) has x = σx s, y = σy t, the part is [0, 1]^2 and the
//   light centre is its origin corner (DESIGN.md's "useful frame"): the hard (stencil) state of
//   the centre is the state of one known corner of every part;
// - R = 8: each quadrant halved along its diagonal, mirrored so that the part is the triangle
//   0 <= y <= x <= 1 (the centre again at the origin corner);
// - R = 1: the whole light, x = (s + 1) / 2, y = (t + 1) / 2 (the centre at (1/2, 1/2)).
// Parts have equal areas, so V = 1 - mean over parts of the occluded fractions.
//
// Per group (geometry/shadow/Silhouette.h: connected light-facing triangles with their own closed
// volume and directed silhouette edges) and part, the state is PartState: the occluded fraction
// of the part (vCoef), the bounding rectangle of the occluded region (part coordinates) and the
// region's centroid. Two ways to get it:
// - groupState, THE WAY THE GPU WILL: the hard state of the centre (the group's z-fail count
//   at P is non-zero), plus per directed silhouette edge (one wedge fragment each) the signed
//   coverage of the part (partCoverage: edgeCoverage's region R ∩ the part instead of ∩ the
//   light), its first moments, the bounds of the edge's clipped projection inside the part and
//   which part corners lie in R. All are order-independent sums or min/max (PartAccum), resolved
//   once per group (resolvePart, partRectangle).
// - exactGroupState: from the exact projected occluder polygons (the group's triangles projected
//   from P onto the light's plane, their union ∩ the part): exact area, bounding box, centroid.
// The two agree whenever the light centre's silhouette is the silhouette from every light point
// and the projected silhouette does not fold (any planar polygon whose plane misses the light,
// e.g. plates at any such angle); on curved occluders they differ (the wedge method's own
// approximation: the union of the projected light-facing triangles folds beyond the projected
// rim, and the fragment state is the smaller one).
//
// What the rectangle is made of, and why (slides "Penumbra blending [6/6]"). The occluded region
// O ∩ part is a polygon; its vertices are end points of the projected silhouette edges clipped to
// the part (including their crossings with the part's sides; crossings of two edges lie on the
// edges) and the part's own corners that are occluded. So
//     bbox(O ∩ part) = bbox(clipped projected edges) ∪ {occluded part corners}
// exactly. A fragment knows the first term edge by edge (min/max: the slides' "edge max X/Y",
// with their min twins). The second is what "closes" the rectangle where O is bounded by the
// part's own sides (e.g. a strip x >= a crossing the whole part touches the part's side x = 1 with
// no edge there): corner k is occluded when C + Σ over edges of sign_e [corner_k ∈ R_e] >= 1,
// C the centre's hard state, because the same identity that makes Σ coverage exact holds
// point-wise. The centre's own corner needs no sum (no R_e contains the centre), so R = 4 and 8
// need 3 and 2 bits per part (the parity of the sum: exact while windings are 0 or 1), R = 1
// four. See PartAccum and partRectangle.
//
// Packed layout (packPart8: two 32-bit scalars per part; packPart16: four):
//   rect  = min x | min y << 8 | max x << 16 | max y << 24, rounded outwards (min down, max up:
//           a rectangle rounded inwards can lose the region it bounds, so that the overlap b
//           misses real overlap, a thin region gets B = 0 < A, and a region reaching a part's
//           side no longer does; rounded outwards it still contains the region, so A <= B
//           up to vCoef's own rounding, and a full part stays exactly [0, 1]^2);
//   coef  = vCoef | centroid x << 8 | centroid y << 16 | corner bits << 24, round to nearest.
//   This differs from the slides' (vCoef, edge max X, edge max Y): here the rectangle scalar
//   accumulates the edge extents itself (min and max, both order-independent) while the wedge
//   pass runs and is closed with the corner bits afterwards, so the edge extents need no slot of
//   their own; the two bytes carry the centroid (the slides' proposed improvement) instead, and
//   the fourth byte the corner parity bits (0 in resolved states).
//   Note for the GPU: the wedge pass's running sums (coverage, moments) are signed and gather one
//   rounding per edge; only resolved values should be stored at 8 bits.
#pragma once

#include <geometry/core/LightFrame.h>
#include <geometry/core/Types.h>

#include <array>
#include <cstdint>
#include <span>
#include <vector>

namespace geometry {
struct SilhouetteFrame;
class Topology;
} // namespace geometry

namespace geometry::blend {

using glm::dvec2;
using glm::dvec3;

inline constexpr int kMaxParts = 8;
bool validPartCount(int parts); // 1, 4 or 8

// --- Light frame and radial parts ----------------------------------------------------------------

// The light's frame (geometry/core/LightFrame.h).
using geometry::LightFrame;
using geometry::lightFrame;

enum class PartShape : std::uint8_t {
    Square,   // [0, 1]^2
    Triangle, // 0 <= y <= x <= 1
};

struct Part {
    glm::dmat3 toPart;   // light homogeneous (s, t, w) -> part homogeneous (x, y, w)
    glm::dmat3 fromPart; // its inverse
    PartShape shape = PartShape::Square;
    int cornerCount = 4;
    std::array<dvec2, 4> corners{}; // part coordinates, counter-clockwise
    dvec2 centre{0.0};              // the light centre in part coordinates
    double area = 1.0;              // in part coordinates: 1 (square) or 1/2 (triangle)
    dvec2 centroid{0.5};            // of the part itself, part coordinates
};
// Part `index` of `parts` (R = 4: quadrants (+,+), (-,+), (-,-), (+,-); R = 8: quadrant q's
// halves 2q (|s| >= |t|) and 2q + 1).
Part radialPart(int parts, int index);

// --- Rectangles ------------------------------------------------------------------------------

struct Rect {
    double minX = 1.0, minY = 1.0, maxX = 0.0, maxY = 0.0; // default: empty
    bool empty() const { return minX > maxX || minY > maxY; }
    double width() const { return empty() ? 0.0 : maxX - minX; }
    double height() const { return empty() ? 0.0 : maxY - minY; }
};
Rect unite(const Rect& a, const Rect& b);     // bounding box of both
Rect intersect(const Rect& a, const Rect& b); // empty when they do not meet
Rect extend(const Rect& r, const dvec2& p);
// ∫∫ over (r ∩ part) of fx(x) fy(y) dx dy, part coordinates; exact for fx, fy polynomials of
// degree <= 3 (the blend's linear weights and their first moments).
double integrateRect(const Rect& r, const Part& part, const std::array<double, 4>& fx,
                     const std::array<double, 4>& fy);
inline double rectArea(const Rect& r, const Part& part) { // |r ∩ part|, part coordinates
    return integrateRect(r, part, {1, 0, 0, 0}, {1, 0, 0, 0});
}

// --- Per fragment and edge (the wedge pass) ----------------------------------------------------

// One directed silhouette edge seen from P: the first half of geometry::edgeCoverage. The edge is
// clipped to the part between P's level and the light's plane and projected from P onto the
// light's plane, homogeneous (w = 0: a point at infinity). R_e, the light points whose segment
// from the centre crosses the projected edge, is three half-planes.
struct ProjectedEdge {
    bool segment = false;   // some of the edge lies between P and the light's plane
    bool region = false;    // R_e has area (false also when the projection passes the centre)
    dvec3 q0{0.0}, q1{0.0}; // homogeneous light coordinates (s, t, w), w >= 0
    double sign = 0.0;      // +1: R_e is occluded beyond the edge (coverage adds), -1: removes
    std::array<dvec3, 3> halves{}; // R_e = { y : dot(h, (y, 1)) >= 0 for each h }, light coords
};
ProjectedEdge projectEdge(const LightFrame& light, const dvec3& p, const dvec3& e0,
                          const dvec3& e1);

// Signed |R_e ∩ part| / |part| (sign: edge.sign). Σ over the parts / R = edgeCoverage.
double partCoverage(const ProjectedEdge& edge, const Part& part);
// Signed ∫ (x, y) dA over R_e ∩ part, over |part| (part coordinates): for the centroid.
dvec2 partMoment(const ProjectedEdge& edge, const Part& part);
// Bounds of the projected edge clipped to the part (part coordinates); empty when it misses.
Rect partEdgeBounds(const ProjectedEdge& edge, const Part& part);
// edge.sign when part corner k lies in R_e, else 0. A corner exactly on a boundary of R_e is
// decided for a point moved infinitesimally into the part (consistent between the two edges
// that share a projected vertex, so ties never count twice or not at all).
int cornerWinding(const ProjectedEdge& edge, const Part& part, int corner);

// The wedge pass's per-part accumulator: sums and min/max only, so the order in which wedge
// fragments arrive does not matter.
struct PartAccum {
    double coverage = 0.0;              // Σ partCoverage
    dvec2 moment{0.0};                  // Σ partMoment
    Rect edges;                         // ∪ partEdgeBounds (the edge extents)
    std::array<int, 4> cornerWinding{}; // Σ cornerWinding per corner (GPU: parity bits)
};
void addEdge(PartAccum& acc, const ProjectedEdge& edge, const Part& part);
// What the GPU keeps of cornerWinding: bit k = its parity (XOR of one bit per edge in R_e). While
// every winding C + Σ is 0 or 1 (planar groups: tested), corner k is occluded iff C xor bit k.
std::uint32_t cornerBits(const PartAccum& acc, const Part& part);

// Resolved per part: what the silhouette and final vBuffers hold.
struct PartState {
    double vCoef = 0.0;  // occluded fraction of the part, [0, 1]
    Rect rect;           // bounding rectangle of the occluded region, part coordinates
    dvec2 centroid{0.5}; // centroid of the occluded region, part coordinates
};
// The rectangle closed with the occluded corners: bbox(edges ∪ {corner k : occluded[k]}).
Rect partRectangle(const Rect& edgeBounds, const std::array<bool, 4>& cornerOccluded,
                   const Part& part);
// vCoef = clamp(C + coverage), corners occluded when C + winding >= 1, rect = partRectangle,
// centroid = (C · part centroid + moment) / (C + coverage) (the part's centroid when that is 0).
PartState resolvePart(const PartAccum& acc, bool centreOccluded, const Part& part);

// --- Per group -------------------------------------------------------------------------------

using Triangle = std::array<dvec3, 3>;

struct Group {
    std::vector<Triangle> triangles;         // light-facing (light-oriented) triangles
    std::vector<std::array<dvec3, 2>> edges; // directed silhouette edges (Silhouette.h rule)
};
// Every group of a silhouette frame (full or lean), positions from its topology.
std::vector<Group> silhouetteGroups(const SilhouetteFrame& frame, const Topology& topology);

struct GroupState {
    int parts = 4;
    bool centreOccluded = false;
    std::array<PartState, kMaxParts> part{};
    double visibility() const; // 1 - mean over parts of vCoef
};

// The group's z-fail count at P: its triangles crossed by the segment P -> light centre
// (closed, so a segment through a shared edge counts both triangles: the state is count != 0).
int centreCount(const LightFrame& light, const dvec3& p, const Group& group);
// The GPU's way (see the top of this file).
GroupState groupState(const RectLight& light, const dvec3& p, const Group& group, int parts);
// Exact, from the union of the triangles' projections ∩ each part.
GroupState exactGroupState(const RectLight& light, const dvec3& p,
                           std::span<const Triangle> triangles, int parts);
// Exact V for any triangle soup (every triangle a two-sided occluder): 1 - |union of the
// projections ∩ light| / |light|.
double exactVisibility(const RectLight& light, const dvec3& p, std::span<const Triangle> triangles);

// --- Blending across groups (slides "Penumbra blending [4/6]-[6/6]") ----------------------------

enum class Overlap : std::uint8_t {
    // The paper: E = (A_f / B_f) (A_s / B_s) b, occlusion spread uniformly over each rectangle.
    Paper,
    // The slides' proposed improvement: each state's occlusion is spread over its rectangle
    // with a separable linear density whose centroid is the stored one (see overlapEstimate).
    Centroid,
};

// The estimated overlap E of the occluded regions of f and s within the part, as a fraction of
// the part (A, B, b below as fractions of the part too: B = |rect ∩ part|, b = |rect_f ∩ rect_s ∩
// part|).
// Paper:    E = d_f d_s b with d = min(1, A / B) (0 when B = 0).
// Centroid: ρ(x, y) = λ wx(x) wy(y) on rect ∩ part, wx(x) = 1 + kx (x - mx), m the centroid
//           of rect ∩ part (uniform), kx = 12 (gx - mx) / W² (W the rectangle's width: the shift
//           of a linear density's mean on an interval is k W² / 12) clamped so that wx >= 0 on
//           the rectangle, likewise y; λ so that ∫ρ = A. E = ∫ over rect_f ∩ rect_s ∩ part of
//           ρ_f ρ_s (the two occluders independent within the overlap). With g = m (and A <= B)
//           it is Paper.
// Both clamp E to [0, min(A_f, A_s)] (a no-op for Paper), which is what keeps a full part full.
double overlapEstimate(const PartState& f, const PartState& s, const Part& part, Overlap overlap);
// A_f <- clamp(max(A_f, A_s) + (min(A_f, A_s) - E), 0, 1) (= A_f + A_s - E, summed so that it
// never rounds below either input); rect <- bounding box of both; centroid <- the centroid of
// A_f g_f + A_s g_s - E g_E (g_E: the centroid of the overlap density), kept in the rectangle.
PartState blendPart(const PartState& f, const PartState& s, const Part& part, Overlap overlap);
struct BlendSettings {
    Overlap overlap = Overlap::Paper;
    // 0: doubles throughout. 8 or 16: every stored state is packed and unpacked, as the GPU
    // stores it: each silhouette state before it is blended, the final state after every blend.
    int bits = 0;
};
// Groups blended in the given order into an initially empty final vBuffer; V = 1 - mean of the
// parts' A_f. All states must have the same part count.
double blendVisibility(std::span<const GroupState> groups, const BlendSettings& settings = {});
// wedges-multiply: V = Π V_s.
double multiplyVisibility(std::span<const GroupState> groups);
// wedges-additive: clamp(V_hard - Σ over every group's edges of the coverage), V_hard = 0 when
// any group occludes the centre.
double additiveVisibility(const RectLight& light, const dvec3& p, std::span<const Group> groups);

// --- Packing (GLSL twins: float and uint32 arithmetic only, no bytes, no memcpy) ---------------
//
// NaN packs as 0 (the GLSL must clamp as `v > 0.0 ? min(v, 1.0) : 0.0` too).
std::uint32_t packUnorm8(float v);      // floor(v * 255 + 0.5): round to nearest
std::uint32_t packUnorm8Down(float v);  // floor(v * 255)
std::uint32_t packUnorm8Up(float v);    // ceil(v * 255)
float unpackUnorm8(std::uint32_t bits); // (bits & 255) / 255
std::uint32_t packUnorm16(float v);     // the same with 65535
std::uint32_t packUnorm16Down(float v);
std::uint32_t packUnorm16Up(float v);
float unpackUnorm16(std::uint32_t bits);

// rect = (min x, min y, max x, max y); an empty rectangle (1, 1, 0, 0) survives packing.
std::uint32_t packRect8(const glm::vec4& rect);
glm::vec4 unpackRect8(std::uint32_t bits);
std::uint32_t packCoef8(float vCoef, const glm::vec2& centroid, std::uint32_t cornerBits);
float unpackVCoef8(std::uint32_t bits);
glm::vec2 unpackCentroid8(std::uint32_t bits);
std::uint32_t unpackCornerBits8(std::uint32_t bits);
// 16 bits: two values per scalar, (min x | min y << 16, max x | max y << 16) and
// (vCoef | centroid x << 16, centroid y | corner bits << 16).
glm::uvec2 packRect16(const glm::vec4& rect);
glm::vec4 unpackRect16(const glm::uvec2& bits);
glm::uvec2 packCoef16(float vCoef, const glm::vec2& centroid, std::uint32_t cornerBits);
float unpackVCoef16(const glm::uvec2& bits);
glm::vec2 unpackCentroid16(const glm::uvec2& bits);

glm::vec4 toVec4(const Rect& r);
Rect toRect(const glm::vec4& v);
// One part as the GPU stores it: (rect, coef) at 8 bits; (rect.xy, coef.xy) at 16.
glm::uvec2 packPart8(const PartState& s);
PartState unpackPart8(const glm::uvec2& bits);
glm::uvec4 packPart16(const PartState& s);
PartState unpackPart16(const glm::uvec4& bits);
// pack then unpack (bits = 8 or 16; anything else returns the state unchanged).
PartState quantise(const PartState& s, int bits);
GroupState quantise(const GroupState& g, int bits);

} // namespace geometry::blend
