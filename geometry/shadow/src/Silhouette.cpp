// Per-frame silhouette groups, loops, volumes and wedges (geometry/shadow/Silhouette.h).
//
// Why the work is organised around static clusters:
// - Groups are connected components of participating triangles across edges with multiplicity
//   0. Running a union-find over every edge of a 1M-triangle mesh each frame costs far more than
//   the 5 ms budget, but almost every edge is an interior edge between two triangles with the
//   same orientation. So the constructor cuts the mesh once into small connected clusters
//   (breadth-first, across consistently oriented two-use edges only) and stores every
//   per-triangle array in cluster order. Per frame, a cluster whose triangles all have the same
//   orientation is internally one component with multiplicity 0 on all its internal edges: it
//   becomes a single union-find node and its internal edges are never looked at. Only the edges
//   between clusters, the edges that are not consistent two-use edges, and the internal edges of
//   the clusters the silhouette passes through are evaluated.
// - Clusters hold at most 64 triangles, so a cluster the silhouette passes through is split into
//   its components by a flood fill over 64-bit masks (its triangles' orientations and the
//   cluster-internal adjacency, built once), and each component, not each triangle, becomes a
//   union-find node. Game levels need this: their silhouettes cross most clusters (the light
//   sits among the walls, 0.4 silhouette edges per triangle), and handling those clusters
//   triangle by triangle cost more than everything else in the lean mode.
// - Facing uses float planes (normalised, so one error bound holds for every triangle) and falls
//   back to exactly the double expression of classifyFacing (ShadowVolume.cpp) when the float
//   value is too close to zero to trust, so both always agree.
// - A group's silhouette edges are the boundary of its oriented 2-chain, so in-degree equals
//   out-degree at every vertex by construction; chaining only has to choose a pairing at
//   vertices where several loops touch.
// - The one-sided rule for closed meshes counts only the triangles a segment from the light
//   centre enters through; a segment can only leave the mesh without entering it first when it
//   starts inside. So the rule holds while the winding number of the mesh at the light centre is
//   0 and nowhere negative (every component outward). Per frame, a bounding-box test settles the
//   usual case (the light outside the box); otherwise a ray from the centre counts signed
//   crossings, skipping clusters whose bounds it misses.
#include "SilhouetteDetail.h"

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace geometry {

using namespace silhouette_detail;

void SilhouetteFrame::clear() {
    oneSided = lightInside = false;
    flatTriangles = 0;
    triangles.clear();
    edges.clear();
    loops.clear();
    groups.clear();
    volumeVertices.clear();
    wedges.clear();
}

SilhouetteExtractor::SilhouetteExtractor(const Topology& topology)
    : mTopology(&topology), mScratch(std::make_unique<Scratch>()) {
    mScratch->build(topology);
}

SilhouetteExtractor::~SilhouetteExtractor() = default;
SilhouetteExtractor::SilhouetteExtractor(SilhouetteExtractor&&) noexcept = default;
SilhouetteExtractor& SilhouetteExtractor::operator=(SilhouetteExtractor&&) noexcept = default;

namespace {

bool sameBounds(const Aabb& a, const Aabb& b) { return a.min == b.min && a.max == b.max; }

bool sameSettings(const SilhouetteSettings& a, const SilhouetteSettings& b) {
    return a.oneSidedClosed == b.oneSidedClosed && a.buildVolumes == b.buildVolumes &&
           a.capVertices == b.capVertices && a.buildWedges == b.buildWedges &&
           a.chainLoops == b.chainLoops && a.influenceBounds == b.influenceBounds &&
           a.flatTrianglesFace == b.flatTrianglesFace;
}

} // namespace

const SilhouetteFrame& SilhouetteExtractor::update(const RectLight& light,
                                                   const Aabb& sceneBounds,
                                                   const SilhouetteSettings& settings) {
    if (mHasFrame && light == mLight && sameBounds(sceneBounds, mBounds) &&
        sameSettings(settings, mSettings)) {
        mReused = true;
        return mFrame;
    }
    mReused = false;
    mHasFrame = true;
    mLight = light;
    mBounds = sceneBounds;
    mSettings = settings;

    Scratch& s = *mScratch;
    const Topology& topo = *mTopology;
    const auto positions = topo.positions();
    const auto topoEdges = topo.edges();
    const glm::vec3 lc = light.center;
    // The one-sided rule only while it is right (see the top of this file); otherwise the
    // two-sided rule, which holds for any mesh and any light position. (Reversing the one-sided
    // rule would also do for a light inside an outward mesh that nothing nests in, but not where
    // components overlap or nest, and it saves geometry only where the mesh is concave around
    // the light.)
    bool oneSided = false, lightInside = false;
    if (settings.oneSidedClosed && topo.manifoldness() == Manifoldness::Closed) {
        lightInside = s.lightContainment(topo, lc) != Scratch::Containment::Outside;
        oneSided = !lightInside && s.closedOutward;
    }
    SilhouetteFrame& frame = mFrame;
    frame.oneSided = oneSided;
    frame.lightInside = lightInside;
    frame.edges.clear();
    frame.loops.clear();
    frame.groups.clear();
    frame.wedges.clear();

    s.classify(topo, lc, oneSided, settings.flatTrianglesFace);
    frame.flatTriangles = s.flatTriangles;
    s.mergeGroups();

    // Step 3: group ids in order of first triangle (local order), sizes and occluder bounds.
    const std::size_t clusterCount = s.clusterOffsets.size() - 1;
    const std::int8_t* orient = s.orient.data();
    std::uint32_t groupCount = 0;
    s.groupTriangleCount.clear();
    s.groupBounds.clear();
    const auto groupOfRoot = [&](std::uint32_t root) {
        std::uint32_t& g = s.rootGroup[root];
        if (g == kNone) {
            g = groupCount++;
            s.groupTriangleCount.push_back(0);
            s.groupBounds.emplace_back();
        }
        return g;
    };
    for (std::size_t c = 0; c < clusterCount; ++c) {
        const std::uint32_t first = s.clusterOffsets[c], last = s.clusterOffsets[c + 1];
        if (s.uniform[c]) {
            if (orient[first] == 0) {
                s.clusterGroup[c] = kNone;
                continue;
            }
            const std::uint32_t g = groupOfRoot(s.find(first));
            s.clusterGroup[c] = g;
            s.groupTriangleCount[g] += last - first;
            s.groupBounds[g].extend(s.clusterBounds[c]);
            continue;
        }
        for (std::uint32_t k = s.componentOffsets[c]; k < s.componentOffsets[c + 1]; ++k) {
            Component& comp = s.components[k];
            const std::uint32_t g = groupOfRoot(s.find(comp.node));
            comp.group = g;
            s.groupTriangleCount[g] += static_cast<std::uint32_t>(std::popcount(comp.mask));
            glm::vec3 lo = s.groupBounds[g].min, hi = s.groupBounds[g].max;
            for (std::uint64_t bits = comp.mask; bits != 0; bits &= bits - 1) {
                const std::uint32_t t = first + static_cast<std::uint32_t>(std::countr_zero(bits));
                s.triangleGroup[t] = g;
                lo = glm::min(lo, s.triangleBounds[t].min);
                hi = glm::max(hi, s.triangleBounds[t].max);
            }
            s.groupBounds[g].min = lo;
            s.groupBounds[g].max = hi;
        }
    }

    // Step 4: split the candidate edges among groups (m_g = sum over the group's uses).
    s.groupEdges.clear();
    s.groupCopyCount.assign(groupCount, 0);
    const auto addShare = [&](std::uint32_t g, std::uint32_t edge, std::int32_t m) {
        if (m == 0) return;
        s.groupEdges.push_back({g, edge, m});
        s.groupCopyCount[g] += static_cast<std::uint32_t>(std::abs(m));
    };
    for (const Candidate& cand :
         std::span<const Candidate>(s.candidates.data(), s.candidateCount)) {
        if (cand.b == kGeneralEdge) {
            // Few uses: accumulate per group with a tiny linear search.
            std::array<std::pair<std::uint32_t, std::int32_t>, 16> shares{};
            std::size_t shareCount = 0;
            const std::uint32_t first = s.generalOffsets[cand.a];
            const std::uint32_t last = s.generalOffsets[cand.a + 1];
            for (std::uint32_t u = first; u < last; ++u) {
                const std::uint32_t t = s.generalUses[u] & kIdMask;
                if (orient[t] == 0) continue;
                const std::uint32_t g = s.groupOf(t);
                const std::int32_t contribution = useSign(s.generalUses[u]) * orient[t];
                std::size_t i = 0;
                while (i < shareCount && shares[i].first != g)
                    ++i;
                if (i == shareCount) {
                    if (shareCount == shares.size()) {
                        // More groups on one edge than the buffer holds: flush what we have.
                        for (std::size_t k = 0; k < shareCount; ++k)
                            addShare(shares[k].first, cand.edge, shares[k].second);
                        shareCount = 0;
                        i = 0;
                    }
                    shares[shareCount++] = {g, 0};
                }
                shares[i].second += contribution;
            }
            for (std::size_t k = 0; k < shareCount; ++k)
                addShare(shares[k].first, cand.edge, shares[k].second);
            continue;
        }
        const std::uint32_t ta = cand.a & kIdMask, tb = cand.b & kIdMask;
        const std::int32_t ca = useSign(cand.a) * orient[ta], cb = useSign(cand.b) * orient[tb];
        const std::uint32_t ga = ca != 0 ? s.groupOf(ta) : kNone;
        const std::uint32_t gb = cb != 0 ? s.groupOf(tb) : kNone;
        if (ga == gb) {
            addShare(ga, cand.edge, ca + cb);
        } else {
            if (ga != kNone) addShare(ga, cand.edge, ca);
            if (gb != kNone) addShare(gb, cand.edge, cb);
        }
    }
    // Step 5: ranges.
    const bool capVertices = settings.buildVolumes && settings.capVertices;
    std::uint32_t triangleTotal = 0, edgeTotal = 0;
    std::size_t volumeTotal = 0;
    frame.groups.resize(groupCount);
    for (std::uint32_t g = 0; g < groupCount; ++g) {
        SilhouetteGroup& group = frame.groups[g];
        group = SilhouetteGroup{};
        group.firstTriangle = triangleTotal;
        group.triangleCount = s.groupTriangleCount[g];
        group.firstEdge = edgeTotal;
        group.edgeCount = s.groupCopyCount[g];
        group.firstWedge = edgeTotal;
        group.occluderBounds = s.groupBounds[g];
        if (settings.buildVolumes) {
            group.firstVolumeVertex = static_cast<std::uint32_t>(volumeTotal);
            group.frontCapVertexCount = capVertices ? 3 * group.triangleCount : 0;
            group.volumeVertexCount = 2 * group.frontCapVertexCount + 6 * group.edgeCount;
            volumeTotal += group.volumeVertexCount;
        }
        triangleTotal += group.triangleCount;
        edgeTotal += group.edgeCount;
    }
    // resize, not clear + resize: a warm vector only value-initialises what it grows by.
    frame.triangles.resize(triangleTotal);
    frame.volumeVertices.resize(volumeTotal);

    // Step 6: triangles of each group (with kTriangleFlipped: the GPU draws the caps from them)
    // and, in the same pass, its front and back caps as vertices when asked for.
    s.groupCursor.resize(groupCount + 1);
    for (std::uint32_t g = 0; g < groupCount; ++g)
        s.groupCursor[g] = 0;
    std::uint32_t* triOut = frame.triangles.data();
    glm::vec4* volOut = frame.volumeVertices.data();
    const auto emitTriangle = [&](std::uint32_t t, const SilhouetteGroup& group,
                                  std::uint32_t k) {
        const bool flip = orient[t] < 0;
        triOut[group.firstTriangle + k] = s.topologyId[t] | (flip ? kTriangleFlipped : 0u);
        if (!capVertices) return;
        const glm::uvec3 tri = s.localTriangles[t];
        const glm::vec3 a = positions[tri.x];
        const glm::vec3 b = positions[flip ? tri.z : tri.y];
        const glm::vec3 c = positions[flip ? tri.y : tri.z];
        glm::vec4* front = volOut + group.firstVolumeVertex + 3 * k;
        front[0] = glm::vec4(a, 1.0f);
        front[1] = glm::vec4(b, 1.0f);
        front[2] = glm::vec4(c, 1.0f);
        // Back cap: reversed at infinity (counter-clockwise seen from beyond it).
        glm::vec4* back = volOut + group.firstVolumeVertex + group.frontCapVertexCount + 3 * k;
        back[0] = glm::vec4(a - lc, 0.0f);
        back[1] = glm::vec4(c - lc, 0.0f);
        back[2] = glm::vec4(b - lc, 0.0f);
    };
    for (std::size_t c = 0; c < clusterCount; ++c) {
        const std::uint32_t first = s.clusterOffsets[c], last = s.clusterOffsets[c + 1];
        if (s.uniform[c]) {
            const std::uint32_t g = s.clusterGroup[c];
            if (g == kNone) continue;
            const SilhouetteGroup& group = frame.groups[g];
            std::uint32_t k = s.groupCursor[g];
            for (std::uint32_t t = first; t < last; ++t)
                emitTriangle(t, group, k++);
            s.groupCursor[g] = k;
            continue;
        }
        for (std::uint32_t k = s.componentOffsets[c]; k < s.componentOffsets[c + 1]; ++k) {
            const Component& comp = s.components[k];
            const SilhouetteGroup& group = frame.groups[comp.group];
            std::uint32_t at = s.groupCursor[comp.group];
            for (std::uint64_t bits = comp.mask; bits != 0; bits &= bits - 1)
                emitTriangle(first + static_cast<std::uint32_t>(std::countr_zero(bits)), group,
                             at++);
            s.groupCursor[comp.group] = at;
        }
    }

    // Step 7: the edge copies of each group, in candidate order (a counting sort by group):
    // m > 0 runs v0 -> v1 (as the light-oriented triangles use it).
    frame.edges.resize(edgeTotal);
    for (std::uint32_t g = 0; g < groupCount; ++g)
        s.groupCursor[g] = frame.groups[g].firstEdge;
    SilhouetteEdge* edgeOut = frame.edges.data();
    for (const GroupEdge& ge : s.groupEdges) {
        const Edge e = topoEdges[ge.edge];
        const SilhouetteEdge directed = ge.m > 0 ? SilhouetteEdge{e.v0, e.v1, ge.edge}
                                                 : SilhouetteEdge{e.v1, e.v0, ge.edge};
        std::uint32_t& cursor = s.groupCursor[ge.group];
        for (std::int32_t k = std::abs(ge.m); k > 0; --k)
            edgeOut[cursor++] = directed;
    }

    // Step 8: per group, loops (then sides and wedges in loop order) and influence bounds.
    // One wedge builder per frame: the light's per-frame constants are set up once.
    std::optional<WedgeBuilder> wedgeBuilder;
    if (settings.buildWedges) wedgeBuilder.emplace(light);
    const LightBox lightBox(light);
    for (std::uint32_t g = 0; g < groupCount; ++g) {
        SilhouetteGroup& group = frame.groups[g];
        group.firstLoop = static_cast<std::uint32_t>(frame.loops.size());
        if (settings.chainLoops) chainGroupLoops(frame, group, lc);
        group.loopCount = static_cast<std::uint32_t>(frame.loops.size()) - group.firstLoop;
        if (!settings.chainLoops) group.firstLoop = 0;

        // Sides: (q, p, p∞), (q, p∞, q∞) for directed edge p -> q, as appendHardShadowVolume.
        if (settings.buildVolumes) {
            glm::vec4* side = volOut + group.firstVolumeVertex + 2 * group.frontCapVertexCount;
            for (std::uint32_t k = group.firstEdge; k < group.firstEdge + group.edgeCount; ++k) {
                const glm::vec3 p = positions[frame.edges[k].v0], q = positions[frame.edges[k].v1];
                const glm::vec4 pf(p, 1.0f), qf(q, 1.0f), pi(p - lc, 0.0f), qi(q - lc, 0.0f);
                side[0] = qf;
                side[1] = pf;
                side[2] = pi;
                side[3] = qf;
                side[4] = pi;
                side[5] = qi;
                side += 6;
            }
        }
        const bool edgeRays = settings.influenceBounds == InfluenceBoundsMode::EdgeRays;
        WedgeRayPass rayPass;
        if (settings.buildWedges) {
            group.firstWedge = static_cast<std::uint32_t>(frame.wedges.wedges.size());
            if (edgeRays) rayPass.begin(group, sceneBounds, group.edgeCount, s.straddles);
            for (std::uint32_t k = 0; k < group.edgeCount; ++k) {
                const SilhouetteEdge& se = frame.edges[group.firstEdge + k];
                const std::uint32_t w =
                    wedgeBuilder->append(positions[se.v0], positions[se.v1], frame.wedges, s.rays);
                if (edgeRays)
                    rayPass.add(frame.wedges.wedges[w], s.rays, sceneBounds, s.straddles[k]);
            }
        }
        if (!edgeRays) {
            group.influenceBounds = occluderConeBounds(group.occluderBounds, lightBox, sceneBounds);
        } else {
            group.influenceBounds =
                settings.buildWedges && rayPass.whole && !sceneBounds.empty()
                    ? sceneBounds
                    : influenceBounds(frame, group, topo, lc, sceneBounds, settings.buildWedges,
                                      rayPass.bounds, s.straddles);
        }
    }
    return frame;
}

// Orders the group's edge copies (frame.edges, in place) into closed loops and appends them to
// frame.loops.
void SilhouetteExtractor::chainGroupLoops(SilhouetteFrame& frame, const SilhouetteGroup& group,
                                          const glm::vec3& lc) {
    Scratch& s = *mScratch;
    const auto positions = mTopology->positions();
    s.copies.assign(frame.edges.begin() + group.firstEdge,
                    frame.edges.begin() + group.firstEdge + group.edgeCount);
    const auto copyCount = static_cast<std::uint32_t>(s.copies.size());

    // Chain: per vertex lists of outgoing and incoming copies.
    s.outNext.resize(copyCount);
    s.inNext.resize(copyCount);
    s.successor.assign(copyCount, kNone);
    s.visited.assign(copyCount, 0);
    s.multiVertices.clear();
    for (std::uint32_t k = copyCount; k-- > 0;) { // reverse: lists end up in copy order
        const SilhouetteEdge& ce = s.copies[k];
        s.outNext[k] = s.outHead[ce.v0];
        s.outHead[ce.v0] = k;
        s.inNext[k] = s.inHead[ce.v1];
        s.inHead[ce.v1] = k;
        if (++s.outDegree[ce.v0] == 2) s.multiVertices.push_back(ce.v0);
    }
    for (std::uint32_t k = 0; k < copyCount; ++k) {
        const std::uint32_t w = s.copies[k].v1;
        if (s.outDegree[w] == 1) s.successor[k] = s.outHead[w];
    }
    for (const std::uint32_t w : s.multiVertices) {
        // Several loops meet at w: pair each incoming copy with the outgoing copy that turns
        // most sharply left seen from the light, so that each loop keeps to its own region.
        s.ins.clear();
        s.outs.clear();
        for (std::uint32_t k = s.inHead[w]; k != kNone; k = s.inNext[k])
            s.ins.push_back(k);
        for (std::uint32_t k = s.outHead[w]; k != kNone; k = s.outNext[k])
            s.outs.push_back(k);
        if (s.ins.size() != s.outs.size()) {
            throw std::logic_error("SilhouetteExtractor: unbalanced silhouette vertex");
        }
        const glm::dvec3 pw(positions[w]);
        glm::dvec3 view = pw - glm::dvec3(lc);
        const double viewLength = glm::length(view);
        view = viewLength > 0.0 ? view / viewLength : glm::dvec3(0.0, 0.0, 1.0);
        const auto project = [&](const glm::dvec3& x) { return x - glm::dot(x, view) * view; };
        for (const std::uint32_t in : s.ins) {
            const glm::dvec3 a = project(pw - glm::dvec3(positions[s.copies[in].v0]));
            double best = -std::numeric_limits<double>::infinity();
            std::size_t bestIndex = 0;
            for (std::size_t o = 0; o < s.outs.size(); ++o) {
                if (s.outs[o] == kNone) continue;
                const glm::dvec3 b =
                    project(glm::dvec3(positions[s.copies[s.outs[o]].v1]) - pw);
                // Counter-clockwise seen from the light = around -view.
                const double turn = std::atan2(-glm::dot(glm::cross(a, b), view),
                                               glm::dot(a, b));
                if (turn > best) {
                    best = turn;
                    bestIndex = o;
                }
            }
            s.successor[in] = s.outs[bestIndex];
            s.outs[bestIndex] = kNone;
        }
    }
    // Reset the per-vertex lists for the next group (touching only what was used).
    for (const SilhouetteEdge& ce : s.copies) {
        s.outHead[ce.v0] = kNone;
        s.inHead[ce.v1] = kNone;
        s.outDegree[ce.v0] = 0;
    }
    for (std::uint32_t k = 0; k < copyCount; ++k) {
        if (s.successor[k] == kNone) {
            throw std::logic_error("SilhouetteExtractor: silhouette edge without successor");
        }
    }
    // Trace the loops, starting each at its first copy in copy order.
    std::uint32_t written = group.firstEdge;
    for (std::uint32_t start = 0; start < copyCount; ++start) {
        if (s.visited[start]) continue;
        SilhouetteLoop loop;
        loop.firstEdge = written;
        for (std::uint32_t k = start; !s.visited[k]; k = s.successor[k]) {
            s.visited[k] = 1;
            frame.edges[written++] = s.copies[k];
        }
        loop.edgeCount = written - loop.firstEdge;
        frame.loops.push_back(loop);
    }
}


} // namespace geometry
