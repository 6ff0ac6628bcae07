#include <geometry/shadow/AutoChoice.h>

#include <cstdio>

namespace geometry {

namespace {

std::string formatted(const char* format, double a, double b) {
    char text[160];
    std::snprintf(text, sizeof(text), format, a, b);
    return text;
}

} // namespace

ShadowPathChoice chooseShadowPath(const CasterFacts& facts) {
    if (facts.requested == ShadowMethod::Wedges)
        return {ShadowPath::Wedges, "scene JSON \"method\": \"wedges\""};
    if (facts.requested == ShadowMethod::Occlusion)
        return {ShadowPath::Occlusion, "scene JSON \"method\": \"occlusion\""};
    if (facts.alphaMasked)
        return {ShadowPath::Occlusion, "alpha-masked materials (volumes occlude whole triangles)"};
    const TopologyStats& t = facts.topology;
    const double nonManifold =
        t.edges > 0 ? static_cast<double>(t.nonManifoldEdges) / static_cast<double>(t.edges) : 0.0;
    if (nonManifold > kMaxNonManifoldEdgeShare)
        return {ShadowPath::Occlusion,
                formatted("non-manifold: %.1f %% of the edges have 3+ triangles (limit %.0f %%)",
                          100.0 * nonManifold, 100.0 * kMaxNonManifoldEdgeShare)};
    const double density = t.triangles > 0 ? static_cast<double>(facts.silhouetteEdges) /
                                                 static_cast<double>(t.triangles)
                                           : 0.0;
    if (facts.silhouetteEdges >= kMinDenseSilhouetteEdges &&
        density > kMaxSilhouetteEdgesPerTriangle)
        return {ShadowPath::Occlusion,
                formatted("silhouette-dense: %.2f silhouette edges per triangle (limit %.2f)",
                          density, kMaxSilhouetteEdgesPerTriangle)};
    char text[160];
    std::snprintf(text, sizeof(text),
                  "%.1f %% non-manifold edges, %zu silhouette edges (%.2f per triangle)",
                  100.0 * nonManifold, facts.silhouetteEdges, density);
    return {ShadowPath::Wedges, text};
}

const char* toString(ShadowPath path) {
    return path == ShadowPath::Occlusion ? "occlusion" : "wedges";
}

} // namespace geometry
