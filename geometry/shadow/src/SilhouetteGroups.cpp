// The per-frame steps before the groups' edges: every triangle's orientation to the light
// centre, then the groups (uniform clusters and split clusters' components, union-find).
#include "SilhouetteDetail.h"

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace geometry {

// Step 1: orientation of every triangle (local order), as bytes (for lookups by triangle) and
// as bit sets (for the clusters' masks), 64 triangles per word.
void SilhouetteExtractor::Scratch::classify(const Topology& topology, const glm::vec3& light,
                                            bool oneSided, bool flatTrianglesFace) {
    Scratch& s = *this;
    const std::uint32_t n = s.triangleCount;
    const float lx = light.x, ly = light.y, lz = light.z;
    // Float error of n.l + d with unit n rounded to float: a few ulps of |l| + |p|. 4e-6 leaves
    // a wide margin; inside it the exact double test of classifyFacing decides.
    const auto tau =
        static_cast<float>(4e-6 * (glm::length(glm::dvec3(light)) + s.positionRadius));
    const std::int8_t pos = 1, neg = oneSided ? 0 : -1, unsure = 2;
    const float* nx = s.nx.data();
    const float* ny = s.ny.data();
    const float* nz = s.nz.data();
    const float* nd = s.nd.data();
    std::int8_t* orient = s.orient.data();
    std::uint64_t* posBits = s.posBits.data();
    std::uint64_t* negBits = s.negBits.data();
    std::uint64_t* unsureBits = s.unsureBits.data();
    std::uint64_t anyUnsure = 0;
    s.flatTriangles = 0;
    const std::uint32_t words = (n + 63) / 64;
    for (std::uint32_t w = 0; w < words; ++w) {
        const std::uint32_t first = 64 * w, count = std::min(64u, n - first);
        std::uint64_t ge = 0, le = 0; // d >= tau, d <= -tau
        std::uint32_t i = 0;
#if defined(__SSE2__)
        // Four triangles per step (SSE2 is part of x86-64): the scalar loop below does not
        // vectorise (float compares into bytes and bits), and at ~5 ns per triangle it was a
        // fifth of the lean step on game levels.
        const __m128 vx = _mm_set1_ps(lx), vy = _mm_set1_ps(ly), vz = _mm_set1_ps(lz);
        const __m128 vTau = _mm_set1_ps(tau), vNegTau = _mm_set1_ps(-tau);
        const __m128i vPos = _mm_set1_epi32(pos), vNeg = _mm_set1_epi32(neg);
        const __m128i vUnsure = _mm_set1_epi32(unsure);
        for (; i + 16 <= count; i += 16) {
            __m128i codes[4];
            for (int j = 0; j < 4; ++j) {
                const std::uint32_t t = first + i + 4 * static_cast<std::uint32_t>(j);
                const __m128 d = _mm_add_ps(
                    _mm_add_ps(_mm_mul_ps(_mm_loadu_ps(nx + t), vx),
                               _mm_mul_ps(_mm_loadu_ps(ny + t), vy)),
                    _mm_add_ps(_mm_mul_ps(_mm_loadu_ps(nz + t), vz), _mm_loadu_ps(nd + t)));
                const __m128 isPos = _mm_cmpge_ps(d, vTau), isNeg = _mm_cmple_ps(d, vNegTau);
                const auto shift = i + 4 * static_cast<std::uint32_t>(j);
                ge |= std::uint64_t(_mm_movemask_ps(isPos)) << shift;
                le |= std::uint64_t(_mm_movemask_ps(isNeg)) << shift;
                const __m128i p = _mm_castps_si128(isPos), q = _mm_castps_si128(isNeg);
                codes[j] = _mm_or_si128(
                    _mm_or_si128(_mm_and_si128(p, vPos), _mm_and_si128(q, vNeg)),
                    _mm_andnot_si128(_mm_or_si128(p, q), vUnsure));
            }
            const __m128i bytes = _mm_packs_epi16(_mm_packs_epi32(codes[0], codes[1]),
                                                  _mm_packs_epi32(codes[2], codes[3]));
            _mm_storeu_si128(reinterpret_cast<__m128i*>(orient + first + i), bytes);
        }
#endif
        for (; i < count; ++i) {
            const std::uint32_t t = first + i;
            const float d = nx[t] * lx + ny[t] * ly + nz[t] * lz + nd[t];
            const bool isPos = d >= tau, isNeg = d <= -tau;
            ge |= std::uint64_t{isPos} << i;
            le |= std::uint64_t{isNeg} << i;
            orient[t] = isPos ? pos : (isNeg ? neg : unsure);
        }
        const std::uint64_t undecided = lowBits(count) & ~(ge | le);
        anyUnsure |= undecided;
        unsureBits[w] = undecided;
        posBits[w] = ge;
        negBits[w] = oneSided ? 0 : le;
    }
    if (anyUnsure != 0) {
        const auto positions = topology.positions();
        const glm::dvec3 l(light);
        for (std::uint32_t w = 0; w < words; ++w) {
            const std::uint32_t first = 64 * w;
            for (std::uint64_t undecided = unsureBits[w]; undecided != 0;
                 undecided &= undecided - 1) {
                const int i = std::countr_zero(undecided);
                const std::uint32_t t = first + static_cast<std::uint32_t>(i);
                // Exactly the expression of classifyFacing, so both agree bit for bit.
                const glm::uvec3 tri = s.localTriangles[t];
                const glm::dvec3 a(positions[tri.x]);
                const glm::dvec3 nn = glm::cross(glm::dvec3(positions[tri.y]) - a,
                                                  glm::dvec3(positions[tri.z]) - a);
                const double d = glm::dot(nn, l - a);
                if (d == 0.0) {
                    ++s.flatTriangles;
                    if (!flatTrianglesFace) {
                        orient[t] = 0; // the light in its plane: a flat volume, no part
                        continue;
                    }
                }
                const bool facing = d >= 0.0;
                orient[t] = facing ? pos : neg;
                if (facing) {
                    posBits[w] |= std::uint64_t{1} << i;
                } else if (!oneSided) {
                    negBits[w] |= std::uint64_t{1} << i;
                }
            }
        }
    }
    orient[n] = 0; // the dummy triangle (its bits, in the padding word or beyond `count`, are 0)
}

// Step 2: per cluster, uniformity, or its components (flood fill over the masks); then
// union-find across multiplicity-0 edges between nodes; edges with m != 0 become candidates.
void SilhouetteExtractor::Scratch::mergeGroups() {
    Scratch& s = *this;
    const std::size_t clusterCount = s.clusterOffsets.size() - 1;
    const std::int8_t* orient = s.orient.data();
    const std::uint64_t* adjacency = s.adjacency.data();
    s.components.clear();
    Candidate* candidates = s.candidates.data();
    std::uint32_t candidateCount = 0;
    for (std::size_t c = 0; c < clusterCount; ++c) {
        const std::uint32_t first = s.clusterOffsets[c], last = s.clusterOffsets[c + 1];
        const std::uint32_t n = last - first;
        const std::uint64_t pos = extractBits(s.posBits.data(), first, n);
        const std::uint64_t neg = extractBits(s.negBits.data(), first, n);
        const std::uint64_t all = lowBits(n);
        const bool uniform = pos == all || neg == all || (pos | neg) == 0;
        s.uniform[c] = uniform;
        if (uniform) {
            s.parent[first] = first;
            s.rootGroup[first] = kNone;
            s.componentOffsets[c + 1] = static_cast<std::uint32_t>(s.components.size());
            continue;
        }
        // Components of each orientation: internal edges join triangles of the same
        // orientation (m = 0) and separate the others (m != 0: candidates, below).
        for (const std::uint64_t region : {pos, neg}) {
            std::uint64_t left = region;
            while (left != 0) {
                std::uint64_t comp = left & (~left + 1), frontier = comp;
                while (frontier != 0) {
                    const int i = std::countr_zero(frontier);
                    frontier &= frontier - 1;
                    const std::uint64_t grown = adjacency[first + i] & region & ~comp;
                    comp |= grown;
                    frontier |= grown;
                }
                left &= ~comp;
                const std::uint32_t node =
                    first + static_cast<std::uint32_t>(std::countr_zero(comp));
                s.parent[node] = node;
                s.rootGroup[node] = kNone;
                s.components.push_back({comp, node, kNone});
                for (std::uint64_t bits = comp; bits != 0; bits &= bits - 1)
                    s.nodeOf[first + static_cast<std::uint32_t>(std::countr_zero(bits))] = node;
            }
        }
        s.componentOffsets[c + 1] = static_cast<std::uint32_t>(s.components.size());
        // Branch-free: on a level about a quarter of these are silhouette edges, at random.
        for (std::uint32_t i = s.internalOffsets[c]; i < s.internalOffsets[c + 1]; ++i) {
            const InternalEdge& ie = s.internalEdges[i];
            candidates[candidateCount] = {ie.edge, ie.a, ie.b | kSignBit};
            candidateCount += orient[ie.a] != orient[ie.b];
        }
    }
    for (const ClusterLink& link : s.links) {
        const InternalEdge* linkEdges = s.linkEdges.data() + link.firstEdge;
        if (s.uniform[link.clusterA] && s.uniform[link.clusterB]) {
            const std::uint32_t nodeA = s.clusterOffsets[link.clusterA];
            const std::uint32_t nodeB = s.clusterOffsets[link.clusterB];
            if (orient[nodeA] == orient[nodeB]) {
                if (orient[nodeA] != 0) s.unite(nodeA, nodeB);
                continue;
            }
            for (std::uint32_t i = 0; i < link.edgeCount; ++i) {
                candidates[candidateCount++] = {linkEdges[i].edge, linkEdges[i].a,
                                                linkEdges[i].b | kSignBit};
            }
            continue;
        }
        for (std::uint32_t i = 0; i < link.edgeCount; ++i) {
            const InternalEdge& le = linkEdges[i];
            const std::int8_t oa = orient[le.a], ob = orient[le.b];
            if (oa == ob) {
                if (oa != 0) s.unite(s.node(le.a), s.node(le.b));
            } else {
                candidates[candidateCount++] = {le.edge, le.a, le.b | kSignBit};
            }
        }
    }
    const std::size_t recordCount = s.records.size();
    for (std::size_t r = 0; r < recordCount; ++r) {
        const EdgeRecord rec = s.records[r];
        if (rec.b == kGeneralEdge) {
            std::int32_t m = 0;
            const std::uint32_t first = s.generalOffsets[rec.a], last = s.generalOffsets[rec.a + 1];
            for (std::uint32_t u = first; u < last; ++u)
                m += useSign(s.generalUses[u]) * orient[s.generalUses[u] & kIdMask];
            if (m != 0) {
                candidates[candidateCount++] = {s.recordEdge[r], rec.a, kGeneralEdge};
                continue;
            }
            // m = 0 on a non-manifold edge: all its participating triangles join one group.
            std::uint32_t anchor = kNone;
            for (std::uint32_t u = first; u < last; ++u) {
                const std::uint32_t t = s.generalUses[u] & kIdMask;
                if (orient[t] == 0) continue;
                if (anchor == kNone) {
                    anchor = s.node(t);
                } else {
                    s.unite(anchor, s.node(t));
                }
            }
            continue;
        }
        const std::uint32_t ta = rec.a & kIdMask, tb = rec.b & kIdMask;
        const std::int32_t m = useSign(rec.a) * orient[ta] + useSign(rec.b) * orient[tb];
        if (m != 0) {
            candidates[candidateCount++] = {s.recordEdge[r], rec.a, rec.b};
        } else if (orient[ta] != 0 && orient[tb] != 0) {
            s.unite(s.node(ta), s.node(tb));
        }
    }
    s.candidateCount = candidateCount;
}

} // namespace geometry
