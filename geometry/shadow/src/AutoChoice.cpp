#include <geometry/shadow/AutoChoice.h>

#include <cstdio>

namespace geometry {

ShadowPathChoice chooseShadowPath(const CasterFacts& facts) {
    if (facts.requested == ShadowMethod::Wedges)
        return {ShadowPath::Wedges, "scene JSON \"method\": \"wedges\""};
    if (facts.requested == ShadowMethod::Occlusion)
        return {ShadowPath::Occlusion, "scene JSON \"method\": \"occlusion\""};
    if (facts.alphaMasked) {
        const std::string materials =
            "alpha-tested materials" +
            (facts.alphaMaterials.empty() ? std::string() : ": " + facts.alphaMaterials) +
            " (volumes occlude whole triangles)";
        if (facts.alphaPath == ShadowPath::SampleMaps && !facts.sampleMapsHold)
            return {ShadowPath::Pcss,
                    materials + "; not wholly in front of every light point within the sample "
                                "maps' 71.6-degree cap (around the light), so pcss"};
        return {facts.alphaPath, materials};
    }
    const TopologyStats& t = facts.topology;
    const double nonManifold =
        t.edges > 0 ? static_cast<double>(t.nonManifoldEdges) / static_cast<double>(t.edges) : 0.0;
    const double density = t.triangles > 0 ? static_cast<double>(facts.silhouetteEdges) /
                                                 static_cast<double>(t.triangles)
                                           : 0.0;
    char text[200];
    std::snprintf(text, sizeof(text),
                  "opaque: %.1f %% non-manifold edges, %zu silhouette edges (%.2f per triangle)",
                  100.0 * nonManifold, facts.silhouetteEdges, density);
    return {ShadowPath::Wedges, text};
}

const char* toString(ShadowPath path) {
    switch (path) {
    case ShadowPath::Occlusion:
        return "occlusion";
    case ShadowPath::Pcss:
        return "pcss";
    case ShadowPath::SampleMaps:
        return "sample-maps";
    case ShadowPath::Wedges:
        break;
    }
    return "wedges";
}

} // namespace geometry
