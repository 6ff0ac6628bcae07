// Per-frame silhouettes from the light centre, grouped for per-silhouette visibility buffers
// (Forest, Barthe & Paulin 2006), with their hard volumes and penumbra wedges.
//
// - Classification: every triangle faces the light centre or not. Closed 2-manifolds use the
//   classic one-sided rule (back-facing triangles take no part: a closed mesh already blocks
//   with its front) while that is correct, i.e. while the light centre is outside the mesh;
//   open and non-manifold meshes, and closed ones that contain the light centre (or are
//   oriented inside out), use the two-sided rule of DESIGN.md §4 (back-facing triangles are
//   flipped and take part), as in geometry/shadow/ShadowVolume.h. SilhouetteFrame reports the rule.
// - Groups: connected components of participating triangles joined across edges where their
//   orientations cancel (multiplicity 0). The edges with non-zero multiplicity *within the group*
//   are its silhouette edges; chained, they form closed, oriented loops. Each group carries its
//   own closed z-fail volume (front cap, back cap, sides), its wedges (one per silhouette edge
//   copy) and its bounds.
// - Output is flat arrays with per-group ranges, ready to upload.
// - Lean mode (SilhouetteSettings::lean()): only what a GPU that builds volumes and wedges itself
//   needs (by vertex pulling from the static welded positions): the grouped triangle ids, the
//   grouped directed edges (unchained) and per group its ranges and bounds, the influence bounds
//   from the occluder box and the light's box alone. About 4x cheaper on game levels; the full
//   mode stays the reference for it (same groups, triangles and edge copies).
// - Topology is built once per mesh (geometry/shadow/Topology.h); SilhouetteExtractor redoes only the
//   classification, loops, volumes and wedges when the light moves, and returns the previous
//   result untouched when it has not.
#pragma once

#include <geometry/shadow/Topology.h>
#include <geometry/shadow/Wedge.h>

#include <cstdint>
#include <memory>
#include <vector>

namespace geometry {

// One directed silhouette edge of a loop. Seen from the light centre, the group's
// light-oriented triangles lie to the left of v0 -> v1 (the edge as its triangle uses it).
struct SilhouetteEdge {
    std::uint32_t v0, v1; // welded vertex ids (Topology::positions)
    std::uint32_t edge;   // Topology edge id
};

// A range of consecutive edges in SilhouetteFrame::edges with edges[i].v1 == edges[i+1].v0 and
// the last edge's v1 == the first edge's v0 (loops are always closed).
// (Empty, with every group's loopCount 0, when SilhouetteSettings::chainLoops is off.)
struct SilhouetteLoop {
    std::uint32_t firstEdge = 0;
    std::uint32_t edgeCount = 0;
};

struct SilhouetteGroup {
    std::uint32_t firstTriangle = 0, triangleCount = 0;   // SilhouetteFrame::triangles
    std::uint32_t firstLoop = 0, loopCount = 0;           // SilhouetteFrame::loops
    std::uint32_t firstEdge = 0, edgeCount = 0;           // SilhouetteFrame::edges
    std::uint32_t firstWedge = 0;                         // wedges.wedges, edgeCount of them,
                                                          // in edge order
    std::uint32_t firstVolumeVertex = 0, volumeVertexCount = 0; // SilhouetteFrame::volumeVertices
    std::uint32_t frontCapVertexCount = 0; // the first ones of the range: the front caps
                                           // (0 unless SilhouetteSettings::capVertices)
    Aabb occluderBounds;  // the group's triangles
    Aabb influenceBounds; // conservative bounds of (volume ∪ wedges) ∩ scene bounds: where the
                          // group can change visibility (for scissor rectangles); see
                          // InfluenceBoundsMode. Empty when nothing of it is in the scene.
};

// How SilhouetteGroup::influenceBounds is found.
enum class InfluenceBoundsMode : std::uint8_t {
    // Per silhouette edge: the rays of its wedge as built (or, without wedges, of its side quad:
    // then the bounds cover the volume alone), clipped to the scene bounds, plus the box edges
    // and corners the pieces straddle. Tight; O(silhouette edges).
    EdgeRays,
    // Per group, from its occluder box B and the light's box alone: the bounds of
    // { a + t (a - y) : a in B, y in the light, t >= 0 } ∩ scene bounds, which holds the
    // volume and the exact wedges of every edge in B whether or not they are built. Looser
    // (whole groups, not their silhouettes); O(1) per group.
    OccluderCone,
};


struct SilhouetteSettings {
    bool oneSidedClosed = true; // classic rule for closed meshes while the light is outside
    // A triangle whose plane holds the light centre exactly: facing it (the classic >= rule,
    // a flat but closed volume, and its edges silhouettes for the centre's wedges), or, when
    // false, in no group (its volume is empty; drawn, it z-fights with every receiver in its
    // plane): wedges-bitmask's potential silhouettes, whose wedges come from every edge anyway.
    bool flatTrianglesFace = true;
    bool buildVolumes = true;
    // Caps as vertices in volumeVertices (front caps, back caps, then sides), or, when false,
    // by reference only: the group's `triangles` entries (with kTriangleFlipped) are its caps,
    // which the GPU draws from the mesh's own static vertex data (front cap: the triangle,
    // wound as light-oriented; back cap: the same reversed, extruded to infinity in the vertex
    // shader), and volumeVertices holds the sides alone. Re-emitting every cap triangle costs
    // ~96 bytes per triangle per frame; the reference costs 4.
    bool capVertices = false;
    bool buildWedges = true;
    // Order each group's edges into closed loops (SilhouetteFrame::loops). Off: the edges keep
    // their per-group copies in an arbitrary (but deterministic) order, which is all that side
    // quads and wedges built edge by edge need, and `loops` stays empty.
    bool chainLoops = true;
    InfluenceBoundsMode influenceBounds = InfluenceBoundsMode::EdgeRays;

    // What the GPU-side builder needs per frame and nothing more: triangles, edges, groups with
    // occluder and (conservative, cheap) influence bounds; no volumes, wedges or loops.
    static constexpr SilhouetteSettings lean();
};

constexpr SilhouetteSettings SilhouetteSettings::lean() {
    SilhouetteSettings s;
    s.buildVolumes = false;
    s.buildWedges = false;
    s.chainLoops = false;
    s.influenceBounds = InfluenceBoundsMode::OccluderCone;
    return s;
}

// Set on a SilhouetteFrame::triangles entry whose triangle is flipped to face the light
// (two-sided rule): its light-oriented winding is (a, c, b).
inline constexpr std::uint32_t kTriangleFlipped = 1u << 31;

struct SilhouetteFrame {
    // The rule this frame was classified with: true for the one-sided rule (closed mesh, light
    // centre outside it, SilhouetteSettings::oneSidedClosed), false for the two-sided rule.
    bool oneSided = false;
    // Closed mesh (with oneSidedClosed asked for) whose inside holds the light centre, or whose
    // surface passes too close to the centre to tell: classified two-sided for that reason.
    bool lightInside = false;
    // Triangles whose plane holds the light centre exactly (in no group unless
    // SilhouetteSettings::flatTrianglesFace).
    std::uint32_t flatTriangles = 0;
    std::vector<std::uint32_t> triangles; // topology triangle ids | kTriangleFlipped, grouped
    std::vector<SilhouetteEdge> edges;    // grouped; within a group in loop order (chainLoops)
    std::vector<SilhouetteLoop> loops;
    std::vector<SilhouetteGroup> groups;
    std::vector<glm::vec4> volumeVertices; // per group: front caps, back caps, sides (w = 0 far)
    WedgeArrays wedges;                    // one per edge, same order as `edges`

    void clear();
};

class SilhouetteExtractor {
public:
    explicit SilhouetteExtractor(const Topology& topology);
    ~SilhouetteExtractor();
    SilhouetteExtractor(SilhouetteExtractor&&) noexcept;
    SilhouetteExtractor& operator=(SilhouetteExtractor&&) noexcept;

    // Classification uses light.center; wedges use the whole rectangle; sceneBounds bounds the
    // influence regions. Returns the previous frame's result (and sets reused()) when light,
    // bounds and settings are unchanged.
    const SilhouetteFrame& update(const RectLight& light, const Aabb& sceneBounds,
                                  const SilhouetteSettings& settings = {});
    bool reused() const { return mReused; }
    const SilhouetteFrame& frame() const { return mFrame; }
    const Topology& topology() const { return *mTopology; }

private:
    void chainGroupLoops(SilhouetteFrame& frame, const SilhouetteGroup& group,
                         const glm::vec3& lc);

    const Topology* mTopology;
    SilhouetteFrame mFrame;
    bool mReused = false;
    bool mHasFrame = false;
    RectLight mLight;
    Aabb mBounds;
    SilhouetteSettings mSettings;
    struct Scratch;
    std::unique_ptr<Scratch> mScratch;
};

} // namespace geometry
