// The `auto` method's per-object rule (DESIGN.md §3: scene JSON "method"; issues: occlusion
// textures and per-object auto, the alpha path right on foliage): which shadow path serves each
// casting object. Decided once per
// object from what does not change from frame to frame (material, topology) plus the silhouette
// density from the light centre the first time it is seen, so that the choice never flickers
// while a light moves.
//
// Rule, in order (the first that applies):
//  1. the scene JSON names the path ("wedges" or "occlusion"): as named;
//  2. alpha-tested materials (glTF MASK or BLEND; geometry/scene/AlphaMask.h): the alpha path
//     (CasterFacts::alphaPath: by default sample maps, one alpha-tested shadow map per light
//     sample, for an object every light point sees wholly in front of it within the maps' cap
//     (geometry::sampleMapsHold: a tree under the light), and pcss's alpha-tested shadow maps
//     for the others (a level's grates around a lamp); pcss or occlusion textures for all with
//     auto's alpha=pcss|occlusion) — shadow volumes and wedges occlude with whole triangles.
//     Scene loading splits an object that mixes opaque and alpha-tested materials into two
//     (splitByAlphaTest in geometry/scene/Scene.h), so a level's grate takes the alpha path and
//     its walls stay with wedges. Sample maps shadow leaves with leaves as raytrace does with
//     the same samples; pcss and occlusion textures approximate (docs/methods/auto.md);
//  3. otherwise wedges. Open, non-manifold and silhouette-dense meshes included: the volumes'
//     two-sided multiplicity rule counts every crossing of every triangle, so the wedge
//     methods' counts are right on level geometry whatever its topology (an earlier rule sent
//     meshes with more than 2 % non-manifold edges, or over 0.5 silhouette edges per triangle,
//     to occlusion textures: oa_dm1 and oa_dm4 from their spawn points with the viewer's lamp,
//     dark rooms drawn lit). The reason names the topology and silhouette counts, for cost.
#pragma once

#include <geometry/shadow/Topology.h>
#include <geometry/core/Types.h>

#include <cstddef>
#include <string>

namespace geometry {

enum class ShadowPath { Wedges, Occlusion, Pcss, SampleMaps };

struct ShadowPathChoice {
    ShadowPath path = ShadowPath::Wedges;
    std::string reason; // one line for report.json and the viewer
};

struct CasterFacts {
    ShadowMethod requested = ShadowMethod::Auto; // the scene JSON's "method" (not None)
    bool alphaMasked = false;
    std::string alphaMaterials; // with alphaMasked: "grate (MASK 0.50), flame (BLEND as MASK 0.50)"
    TopologyStats topology;
    std::size_t silhouetteEdges = 0; // directed, from the light centre
    // For alpha-tested objects: SampleMaps (then Pcss where !sampleMapsHold), Pcss or Occlusion.
    ShadowPath alphaPath = ShadowPath::SampleMaps;
    bool sampleMapsHold = true; // geometry::sampleMapsHold of the object's bounds, first seen
};

ShadowPathChoice chooseShadowPath(const CasterFacts& facts);

const char* toString(ShadowPath path); // "wedges", "occlusion", "pcss", "sample-maps"

} // namespace geometry
