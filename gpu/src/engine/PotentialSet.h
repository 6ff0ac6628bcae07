// wedges-bitmask with silhouettes=potential: what its one stencil pass and one wedge pass draw,
// per frame, for a subset of the casters (geometry/shadow/PotentialSilhouettes.h):
// - the light centre's two-sided z-fail volumes (every triangle a cap, flipped to face the
//   centre; SilhouetteSettings::oneSidedClosed off), so that the stencil holds D(p, c), the
//   triangles the segment p -> c crosses, counted two-sided for every mesh, closed or not;
// - the potential silhouette edges with the third vertices of their triangles (wedge-setup
//   and wedge.vert with WEDGE_APEXES), each caster's under one group whose influence bounds
//   are the caster's (frustum culling, full-screen wedges).
// Rebuilt when the light or the subset changes; one upload, bound at the same slots as
// CasterSet's frame arrays (caps, edges, groups) plus BINDING_EDGE_APEXES.
#pragma once

#include "engine/CasterSet.h"

#include <geometry/shadow/PotentialSilhouettes.h>
#include <geometry/shadow/Silhouette.h>

#include <glm/glm.hpp>

#include <cstdint>
#include <memory>
#include <span>
#include <vector>

namespace gpu {

class PotentialSet {
public:
    // Extractors and edges for `subset` of `casters` (whose update() ran this frame).
    void update(const CasterSet& casters, std::span<const std::uint32_t> subset,
                const geometry::RectLight& light);
    // The static welded geometry (CasterSet::bind) and this set's arrays.
    void bind(const CasterSet& casters) const;

    const DrawSet& volumes() const { return mVolumes; } // caps and side copies
    const DrawSet& wedges() const { return mWedges; }   // potential edges and their twins
    std::span<const CasterRange> wedgeRuns() const { return mWedgeRuns; } // for WedgePass::setup
    std::uint32_t edgeCount() const { return mEdgeTotal; } // entries of the edges array
    std::uint32_t wedgeCount() const { return mWedgeTotal; }
    // Potential edge i's second wedge (a silhouette cone, WedgePass::setup) is at i + this; the
    // wedge buffer holds wedgeSlots().
    std::uint32_t twinOffset() const { return mWedgeTotal; }
    std::uint32_t wedgeSlots() const { return mEdgeTotal + mWedgeTotal; }
    std::uint32_t centreEdgeCount() const { return mCentreEdges; } // side copies (two-sided)
    // Caster triangles whose plane holds the light centre this frame (flat volumes: none drawn).
    std::uint32_t flatTriangles() const { return mFlatTriangles; }
    // The potential edges' end points (world), in the order of the edges array's potential part.
    std::span<const glm::vec3> edgeStarts() const { return mEdgeA; }
    std::span<const glm::vec3> edgeEnds() const { return mEdgeB; }
    // The wedge set and set-up runs of the potential edges with keep[i] != 0 (i as in
    // edgeStarts), their twin slots included: depth-aware culling of a frame.
    void keptWedges(std::span<const std::uint8_t> keep, DrawSet& wedges,
                    std::vector<CasterRange>& runs) const;
    const geometry::PotentialEdgeStats& stats() const { return mStats; }

private:
    struct Caster {
        std::uint32_t index = 0;
        std::unique_ptr<geometry::SilhouetteExtractor> extractor;
        std::unique_ptr<geometry::PotentialSilhouettes> potential; // its light-free part, kept
        std::vector<geometry::PotentialEdge> edges;
        geometry::Aabb bounds; // every triangle's corners
    };
    std::vector<Caster> mCasters;
    std::vector<std::uint32_t> mSubset;
    bool mHasLight = false;
    geometry::RectLight mLight;
    DrawSet mVolumes, mWedges;
    std::vector<CasterRange> mWedgeRuns;
    std::uint32_t mEdgeTotal = 0, mWedgeTotal = 0, mCentreEdges = 0, mFlatTriangles = 0;
    std::vector<glm::vec3> mEdgeA, mEdgeB;
    geometry::PotentialEdgeStats mStats;
    Buffer mData{BufferDesc{.label = "potential-silhouettes"}};
    std::vector<std::byte> mStaging;
    std::size_t mEdgeOffset = 0, mApexOffset = 0, mGroupOffset = 0, mBytes = 0;
};

} // namespace gpu
