// The `auto` method's per-object rule (DESIGN.md §3: scene JSON "method"; issue: occlusion
// textures and per-object auto): which shadow path serves each casting object. Decided once per
// object from what does not change from frame to frame (material, topology) plus the silhouette
// density from the light centre the first time it is seen, so that the choice never flickers
// while a light moves.
//
// Rule, in order (the first that applies):
//  1. the scene JSON names the path ("wedges" or "occlusion"): as named;
//  2. alpha-masked materials (glTF MASK or BLEND; geometry/scene/AlphaMask.h): occlusion textures —
//     shadow volumes and wedges occlude with whole triangles;
//  3. non-manifold beyond repair: more than kMaxNonManifoldEdgeShare of the edges have three or
//     more triangles (triangle soups, crossed cards): occlusion. Boundary edges and the few
//     non-manifold edges of game levels (kaos2: 0.6 %) are served by the volumes' multiplicity
//     rule and stay with wedges;
//  4. silhouette-dense: more than kMaxSilhouetteEdgesPerTriangle directed silhouette edges per
//     triangle from the light centre, and at least kMinDenseSilhouetteEdges of them (one wedge
//     per edge: fur, grass, shredded geometry cost more in wedges than a slicing pass); a closed
//     box (6 edges, 12 triangles) is not dense — too few edges to matter;
//  5. otherwise wedges.
#pragma once

#include <geometry/shadow/Topology.h>
#include <geometry/core/Types.h>

#include <cstddef>
#include <string>

namespace geometry {

inline constexpr double kMaxNonManifoldEdgeShare = 0.02;
inline constexpr double kMaxSilhouetteEdgesPerTriangle = 0.5;
inline constexpr std::size_t kMinDenseSilhouetteEdges = 256;

enum class ShadowPath { Wedges, Occlusion };

struct ShadowPathChoice {
    ShadowPath path = ShadowPath::Wedges;
    std::string reason; // one line for report.json and the viewer
};

struct CasterFacts {
    ShadowMethod requested = ShadowMethod::Auto; // the scene JSON's "method" (not None)
    bool alphaMasked = false;
    TopologyStats topology;
    std::size_t silhouetteEdges = 0; // directed, from the light centre
};

ShadowPathChoice chooseShadowPath(const CasterFacts& facts);

const char* toString(ShadowPath path); // "wedges", "occlusion"

} // namespace geometry
