// The silhouette extractor's clusters and per-mesh arrays, built once (Silhouette.cpp explains
// why the work is organised around clusters).
#include "SilhouetteDetail.h"

namespace geometry {

// Builds the clusters and every array that depends on the mesh only.
void SilhouetteExtractor::Scratch::build(const Topology& topology) {
    Scratch& s = *this;
    const auto positions = topology.positions();
    const auto triangles = topology.triangles();
    const auto edges = topology.edges();
    const auto offsets = topology.edgeUseOffsets();
    const auto uses = topology.edgeUses();
    const auto triangleEdges = topology.triangleEdges();
    const auto triangleCount = static_cast<std::uint32_t>(triangles.size());
    if (triangles.size() >= kIdMask) throw std::length_error("SilhouetteExtractor: mesh too big");
    s.triangleCount = triangleCount;

    const auto consistentPair = [&](std::uint32_t e) {
        return offsets[e + 1] - offsets[e] == 2 &&
               uses[offsets[e]].sign != uses[offsets[e] + 1].sign;
    };

    // Breadth-first clusters across consistent two-use edges, seeded in triangle order.
    std::vector<std::uint32_t> localOf(triangleCount, kNone);
    s.topologyId.clear();
    s.topologyId.reserve(triangleCount);
    s.clusterOffsets.assign(1, 0);
    for (std::uint32_t seed = 0; seed < triangleCount; ++seed) {
        if (localOf[seed] != kNone) continue;
        const auto first = static_cast<std::uint32_t>(s.topologyId.size());
        localOf[seed] = first;
        s.topologyId.push_back(seed);
        for (std::uint32_t head = first;
             head < s.topologyId.size() && s.topologyId.size() - first < kClusterSize; ++head) {
            const std::uint32_t t = s.topologyId[head];
            for (int k = 0; k < 3 && s.topologyId.size() - first < kClusterSize; ++k) {
                const std::uint32_t e = triangleEdges[t][k];
                if (!consistentPair(e)) continue;
                const std::uint32_t u0 = uses[offsets[e]].triangle;
                const std::uint32_t other = u0 == t ? uses[offsets[e] + 1].triangle : u0;
                if (localOf[other] != kNone) continue;
                localOf[other] = static_cast<std::uint32_t>(s.topologyId.size());
                s.topologyId.push_back(other);
            }
        }
        s.clusterOffsets.push_back(static_cast<std::uint32_t>(s.topologyId.size()));
    }
    const std::size_t clusterCount = s.clusterOffsets.size() - 1;

    // Planes, corners and cluster bounds in local order.
    s.nx.resize(triangleCount);
    s.ny.resize(triangleCount);
    s.nz.resize(triangleCount);
    s.nd.resize(triangleCount);
    s.localTriangles.resize(triangleCount);
    s.clusterOf.resize(triangleCount + 1);
    s.clusterBounds.assign(clusterCount, Aabb{});
    s.triangleBounds.resize(triangleCount);
    s.positionRadius = 0.0;
    for (const glm::vec3& p : positions)
        s.positionRadius = std::max(s.positionRadius, glm::length(glm::dvec3(p)));
    for (std::size_t c = 0; c < clusterCount; ++c) {
        for (std::uint32_t l = s.clusterOffsets[c]; l < s.clusterOffsets[c + 1]; ++l) {
            const glm::uvec3 tri = triangles[s.topologyId[l]];
            s.localTriangles[l] = tri;
            s.clusterOf[l] = static_cast<std::uint32_t>(c);
            const glm::dvec3 a(positions[tri.x]), b(positions[tri.y]), cc(positions[tri.z]);
            glm::dvec3 n = glm::cross(b - a, cc - a);
            const double len = glm::length(n);
            n = len > 0.0 ? n / len : glm::dvec3(0.0);
            s.nx[l] = static_cast<float>(n.x);
            s.ny[l] = static_cast<float>(n.y);
            s.nz[l] = static_cast<float>(n.z);
            s.nd[l] = static_cast<float>(-glm::dot(n, a));
            Aabb box;
            box.extend(positions[tri.x]);
            box.extend(positions[tri.y]);
            box.extend(positions[tri.z]);
            s.triangleBounds[l] = box;
            s.clusterBounds[c].extend(box);
        }
    }
    s.clusterOf[triangleCount] = 0; // the dummy triangle; never looked up (orientation 0)

    // Edges: internal to a cluster (skipped while the cluster is uniform), or evaluated.
    std::vector<std::uint32_t> internalCount(clusterCount + 1, 0);
    s.records.clear();
    s.recordEdge.clear();
    s.generalOffsets.assign(1, 0);
    s.generalUses.clear();
    const auto encode = [&](const EdgeUse& use) {
        return localOf[use.triangle] | (use.sign < 0 ? kSignBit : 0u);
    };
    std::vector<std::pair<std::uint64_t, InternalEdge>> crossing;
    for (std::uint32_t e = 0; e < edges.size(); ++e) {
        const std::uint32_t first = offsets[e], count = offsets[e + 1] - first;
        if (consistentPair(e)) {
            const std::uint32_t l0 = localOf[uses[first].triangle];
            const std::uint32_t l1 = localOf[uses[first + 1].triangle];
            const std::uint32_t c0 = s.clusterOf[l0], c1 = s.clusterOf[l1];
            if (c0 == c1) {
                ++internalCount[c0 + 1];
                continue;
            }
            const bool firstForward = uses[first].sign > 0;
            const std::uint64_t key = (std::uint64_t{std::min(c0, c1)} << 32) | std::max(c0, c1);
            const InternalEdge link{firstForward ? l0 : l1, firstForward ? l1 : l0, e};
            crossing.push_back({key, link});
            continue;
        }
        s.recordEdge.push_back(e);
        if (count == 1) {
            s.records.push_back({encode(uses[first]), triangleCount});
        } else if (count == 2) {
            s.records.push_back({encode(uses[first]), encode(uses[first + 1])});
        } else {
            s.records.push_back(
                {static_cast<std::uint32_t>(s.generalOffsets.size() - 1), kGeneralEdge});
            for (std::uint32_t u = first; u < first + count; ++u)
                s.generalUses.push_back(encode(uses[u]));
            s.generalOffsets.push_back(static_cast<std::uint32_t>(s.generalUses.size()));
        }
    }
    std::sort(crossing.begin(), crossing.end(), [](const auto& x, const auto& y) {
        return x.first != y.first ? x.first < y.first : x.second.edge < y.second.edge;
    });
    s.links.clear();
    s.linkEdges.clear();
    s.linkEdges.reserve(crossing.size());
    for (std::size_t i = 0; i < crossing.size(); ++i) {
        if (i == 0 || crossing[i].first != crossing[i - 1].first) {
            s.links.push_back({static_cast<std::uint32_t>(crossing[i].first >> 32),
                               static_cast<std::uint32_t>(crossing[i].first),
                               static_cast<std::uint32_t>(i), 0});
        }
        ++s.links.back().edgeCount;
        s.linkEdges.push_back(crossing[i].second);
    }
    for (std::size_t c = 0; c < clusterCount; ++c)
        internalCount[c + 1] += internalCount[c];
    s.internalOffsets = internalCount;
    s.internalEdges.resize(internalCount[clusterCount]);
    std::vector<std::uint32_t> fill(internalCount.begin(), internalCount.end() - 1);
    for (std::uint32_t e = 0; e < edges.size(); ++e) {
        const std::uint32_t first = offsets[e];
        if (!consistentPair(e)) continue;
        const std::uint32_t l0 = localOf[uses[first].triangle];
        const std::uint32_t l1 = localOf[uses[first + 1].triangle];
        if (s.clusterOf[l0] != s.clusterOf[l1]) continue;
        const bool firstForward = uses[first].sign > 0;
        s.internalEdges[fill[s.clusterOf[l0]]++] =
            InternalEdge{firstForward ? l0 : l1, firstForward ? l1 : l0, e};
    }
    s.adjacency.assign(triangleCount, 0);
    for (const InternalEdge& ie : s.internalEdges) {
        const std::uint32_t first = s.clusterOffsets[s.clusterOf[ie.a]];
        s.adjacency[ie.a] |= std::uint64_t{1} << (ie.b - first);
        s.adjacency[ie.b] |= std::uint64_t{1} << (ie.a - first);
    }

    // Per-frame arrays, sized once.
    s.orient.assign(triangleCount + 1, 0);
    const std::size_t words = (triangleCount + 63) / 64 + 1;
    s.posBits.assign(words, 0);
    s.negBits.assign(words, 0);
    s.unsureBits.assign(words, 0);
    s.uniform.assign(clusterCount, 0);
    s.componentOffsets.assign(clusterCount + 1, 0);
    s.candidates.resize(s.internalEdges.size() + s.linkEdges.size() + s.records.size());
    s.nodeOf.assign(triangleCount + 1, 0);
    s.parent.assign(triangleCount + 1, 0);
    s.rootGroup.assign(triangleCount + 1, kNone);
    s.clusterGroup.assign(clusterCount, kNone);
    s.triangleGroup.assign(triangleCount + 1, kNone);
    s.outHead.assign(positions.size(), kNone);
    s.inHead.assign(positions.size(), kNone);
    s.outDegree.assign(positions.size(), 0);

    s.meshBounds = Aabb{};
    for (const glm::vec3& p : positions)
        s.meshBounds.extend(p);
    s.meshScale = s.meshBounds.empty() ? 0.0 : glm::length(glm::dvec3(s.meshBounds.extent()));
    s.buildOrientation(topology);
    s.haveContainment = false;
}

// closedOutward: the mesh is closed and each connected component encloses a non-negative
// volume (signed volume of its triangles about the mesh centre), so the winding number is
// nowhere negative (components are assumed not to intersect themselves). An inside-out
// component (a room modelled as a closed box facing inwards) has winding -1 inside, and the
// one-sided rule would miss its shadows on everything outside it; such meshes go two-sided.
void SilhouetteExtractor::Scratch::buildOrientation(const Topology& topology) {
    closedOutward = false;
    if (topology.manifoldness() != Manifoldness::Closed) return;
    const auto positions = topology.positions();
    const auto triangles = topology.triangles();
    const auto offsets = topology.edgeUseOffsets();
    const auto uses = topology.edgeUses();
    const auto triangleEdges = topology.triangleEdges();
    const glm::dvec3 origin(meshBounds.center());
    std::vector<std::uint8_t> seen(triangles.size(), 0);
    std::vector<std::uint32_t> stack;
    for (std::uint32_t seed = 0; seed < triangles.size(); ++seed) {
        if (seen[seed]) continue;
        seen[seed] = 1;
        stack.assign(1, seed);
        double volume = 0.0;
        Aabb bounds;
        while (!stack.empty()) {
            const std::uint32_t t = stack.back();
            stack.pop_back();
            const glm::uvec3 tri = triangles[t];
            const glm::dvec3 a = glm::dvec3(positions[tri.x]) - origin;
            const glm::dvec3 b = glm::dvec3(positions[tri.y]) - origin;
            const glm::dvec3 c = glm::dvec3(positions[tri.z]) - origin;
            volume += glm::dot(a, glm::cross(b, c)) / 6.0;
            for (int k = 0; k < 3; ++k) {
                bounds.extend(positions[tri[k]]);
                const std::uint32_t e = triangleEdges[t][k];
                for (std::uint32_t u = offsets[e]; u < offsets[e + 1]; ++u) {
                    const std::uint32_t other = uses[u].triangle;
                    if (seen[other]) continue;
                    seen[other] = 1;
                    stack.push_back(other);
                }
            }
        }
        // Rounding (and flat, doubled sheets, which enclose nothing) stay within a tiny
        // fraction of the component's size cubed; an inside-out solid does not.
        const double size = glm::length(glm::dvec3(bounds.extent()));
        if (volume < -1e-6 * size * size * size) return;
    }
    closedOutward = true;
}

} // namespace geometry
