// The edges whose wedges wedges-bitmask draws with silhouettes=potential: every edge that can be
// a silhouette seen from some point of the light, with the triangles that use it.
//
// For a receiver p and a light point y, D(p, y) is the number of triangles the segment p -> y
// crosses (two-sided). Moving y from the centre to a sample, D changes only where y crosses the
// projection from p of an edge e, by m_p(e) = the number of e's triangles whose third vertex w
// lies on the sample's side of the plane through p and e, minus those on the centre's side
// (DESIGN.md §4; Laine et al. 2005). m_p(e) != 0 over the light only if e is a silhouette seen
// from some light point z (z on the plane through p and e), so these edges are all that can
// matter:
// - boundary edges (one triangle) and edges with more than two triangles, always;
// - an edge of two triangles unless both triangles' planes keep the light wholly on one side
//   each and those sides make the edge a non-silhouette from every light point (the two faces
//   facing every light point alike, for a consistently oriented pair), or the two triangles lie
//   exactly in one plane on either side of the edge (a flat face's diagonal: a silhouette from
//   no point at all).
// Each entry carries at most two triangles (their third vertices); an edge of k > 2 triangles
// becomes ceil(k / 2) entries over the same edge, whose counts add.
#pragma once

#include <geometry/core/Types.h>
#include <geometry/shadow/Topology.h>

#include <cstdint>
#include <vector>

namespace geometry {

inline constexpr std::uint32_t kNoApex = 0xFFFFFFFFu;

struct PotentialEdge {
    std::uint32_t v0, v1;  // welded vertex ids (Topology::positions), v0 < v1
    std::uint32_t apex[2]; // third vertex of each triangle of the entry (kNoApex: none)
};

struct PotentialEdgeStats {
    std::size_t interior = 0;    // two-triangle edges kept (straddling or silhouette somewhere)
    std::size_t boundary = 0;    // one-triangle edges
    std::size_t nonManifold = 0; // edges of more than two triangles (entries: ceil(k / 2) each)
    std::size_t skipped = 0;     // two-triangle edges that are a silhouette from no light point
                                 // (flat faces' diagonals included)
};

// The potential silhouette edges of one mesh, per frame. What does not depend on the light is
// found once: each triangle's normal length and edge lengths (the tolerance of the side test),
// each edge use's third vertex, and (on first need) whether a two-triangle edge is a flat
// face's diagonal (exact arithmetic). Per frame: the side of each triangle's plane the light
// lies on (double precision; a plane within a relative 1e-9 of a light corner counts as
// straddling it, conservative: an extra edge changes nothing, its m_p is 0 wherever it is no
// silhouette), then one pass over the edges. `topology` must outlive it.
class PotentialSilhouettes {
public:
    explicit PotentialSilhouettes(const Topology& topology);
    // The potential silhouette edges for `light`, appended to `out` (cleared first).
    PotentialEdgeStats update(const RectLight& light, std::vector<PotentialEdge>& out);

private:
    const Topology& mTopology;
    std::vector<double> mNormalLength; // per triangle: |(b - a) x (c - a)|
    std::vector<double> mSideLength;   // per triangle: |b - a| + |c - a| (a bound's term)
    std::vector<std::uint32_t> mApex;  // per edge use: its triangle's third vertex
    std::vector<std::uint8_t> mFlat;   // per edge: 0 no, 1 a flat face's diagonal, 2 not known yet
    std::vector<std::int8_t> mSide;    // per triangle, this frame: +1, -1 or 0 (straddling)
};

// The same for one light, without keeping anything (PotentialSilhouettes::update).
PotentialEdgeStats potentialSilhouetteEdges(const Topology& topology, const RectLight& light,
                                            std::vector<PotentialEdge>& out);

// Conservative bounds of where an occluder within `occluder` can change visibility from `light`,
// within `scene` (the influence bounds of SilhouetteSettings::lean()).
Aabb occluderInfluenceBounds(const Aabb& occluder, const RectLight& light, const Aabb& scene);

} // namespace geometry
