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
#include <geometry/shadow/Silhouette.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstring>
#include <limits>
#include <optional>
#include <span>
#include <stdexcept>
#include <utility>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace geometry {

namespace {

constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();
constexpr std::uint32_t kSignBit = 0x80000000u; // set: the use runs v1 -> v0 (sign -1)
constexpr std::uint32_t kIdMask = 0x7fffffffu;
constexpr std::uint32_t kGeneralEdge = kNone; // EdgeRecord::b marker: 3+ uses, a = general index

// Cluster size: large enough that few edges cross clusters, small enough that the clusters the
// silhouette passes through (handled triangle by triangle) stay a small part of the mesh.
constexpr std::uint32_t kClusterSize = 64;
static_assert(kClusterSize <= 64, "cluster masks are 64-bit");

// Exact "is the corner in the volume" tests are only run for groups up to this size; larger
// groups take the conservative answer of the bounding-box test (keeps the per-frame cost
// independent of the mesh size).
constexpr std::uint32_t kExactCornerTestLimit = 4096;

// One edge evaluated every frame: up to two uses as local triangle id | kSignBit for sign -1.
// A boundary edge's second use is the dummy triangle (orientation always 0).
struct EdgeRecord {
    std::uint32_t a, b;
};

// A consistently oriented two-use edge inside one cluster: a uses it v0 -> v1, b v1 -> v0.
struct InternalEdge {
    std::uint32_t a, b, edge;
};

// The consistent two-use edges between two clusters: while both clusters are uniform, they all
// have the same multiplicity and need one union (or none) for all of them.
struct ClusterLink {
    std::uint32_t clusterA, clusterB, firstEdge, edgeCount;
};

// A connected set of same-orientation triangles of one non-uniform cluster (bit i: the
// cluster's i-th triangle), one union-find node: `node` is its first triangle's local id.
struct Component {
    std::uint64_t mask;
    std::uint32_t node;
    std::uint32_t group;
};

// Bit i set for i < n.
inline std::uint64_t lowBits(std::uint32_t n) {
    return n >= 64 ? ~std::uint64_t{0} : (std::uint64_t{1} << n) - 1;
}

// Bits [first, first + n) of a bit set (n <= 64; the set has a padding word).
inline std::uint64_t extractBits(const std::uint64_t* words, std::uint32_t first,
                                 std::uint32_t n) {
    const std::uint32_t word = first >> 6, shift = first & 63;
    std::uint64_t bits = words[word] >> shift;
    if (shift != 0) bits |= words[word + 1] << (64 - shift);
    return bits & lowBits(n);
}

// An edge with non-zero multiplicity this frame, before it is split among groups.
struct Candidate {
    std::uint32_t edge, a, b; // as EdgeRecord (b = kGeneralEdge: a indexes the general edges)
};

// One group's share of an edge: m_g copies (sign = direction).
struct GroupEdge {
    std::uint32_t group, edge;
    std::int32_t m;
};

inline std::int32_t useSign(std::uint32_t use) { return (use & kSignBit) ? -1 : 1; }

// Ray p + t d (t >= 0) clipped to the box: the parameter range, empty when t0 > t1.
bool clipRay(const glm::dvec3& p, const glm::dvec3& d, const Aabb& box, double tMax, double& t0,
             double& t1) {
    t0 = 0.0;
    t1 = tMax;
    for (int k = 0; k < 3; ++k) {
        if (d[k] == 0.0) {
            if (p[k] < box.min[k] || p[k] > box.max[k]) return false;
            continue;
        }
        double a = (box.min[k] - p[k]) / d[k], b = (box.max[k] - p[k]) / d[k];
        if (a > b) std::swap(a, b);
        t0 = std::max(t0, a);
        t1 = std::min(t1, b);
        if (t0 > t1) return false;
    }
    return true;
}

bool contains(const Aabb& b, const glm::vec3& p) {
    return p.x >= b.min.x && p.y >= b.min.y && p.z >= b.min.z && p.x <= b.max.x &&
           p.y <= b.max.y && p.z <= b.max.z;
}

bool coversBox(const Aabb& b, const Aabb& box) {
    return b.min.x <= box.min.x && b.min.y <= box.min.y && b.min.z <= box.min.z &&
           b.max.x >= box.max.x && b.max.y >= box.max.y && b.max.z >= box.max.z;
}

glm::vec3 boxCorner(const Aabb& box, int i) {
    return {i & 1 ? box.max.x : box.min.x, i & 2 ? box.max.y : box.min.y,
            i & 4 ? box.max.z : box.min.z};
}

// Segment a -> b against a triangle (Möller-Trumbore in double), endpoints excluded.
bool segmentHitsTriangle(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& p0,
                         const glm::dvec3& p1, const glm::dvec3& p2) {
    const glm::dvec3 d = b - a, e1 = p1 - p0, e2 = p2 - p0;
    const glm::dvec3 h = glm::cross(d, e2);
    const double det = glm::dot(e1, h);
    if (std::abs(det) < 1e-300) return false;
    const double inv = 1.0 / det;
    const glm::dvec3 s = a - p0;
    const double u = glm::dot(s, h) * inv;
    // A small tolerance on the conservative side: a corner on the volume's boundary counts.
    constexpr double kTol = 1e-9;
    if (u < -kTol || u > 1.0 + kTol) return false;
    const glm::dvec3 q = glm::cross(s, e1);
    const double v = glm::dot(d, q) * inv;
    if (v < -kTol || u + v > 1.0 + kTol) return false;
    const double t = glm::dot(e2, q) * inv;
    return t > -kTol && t < 1.0 + kTol;
}

} // namespace

void SilhouetteFrame::clear() {
    oneSided = lightInside = false;
    triangles.clear();
    edges.clear();
    loops.clear();
    groups.clear();
    volumeVertices.clear();
    wedges.clear();
}

struct SilhouetteExtractor::Scratch {
    // --- Built once per mesh (all per-triangle arrays in local = cluster order) ---
    std::uint32_t triangleCount = 0;
    std::vector<float> nx, ny, nz, nd;          // unit normal and offset: facing = n.l + d >= 0
    std::vector<glm::uvec3> localTriangles;     // welded vertex ids
    std::vector<std::uint32_t> topologyId;      // local -> Topology triangle id
    std::vector<std::uint32_t> clusterOf;       // local -> cluster
    std::vector<std::uint32_t> clusterOffsets;  // clusters: [offsets[c], offsets[c+1])
    std::vector<Aabb> clusterBounds;
    std::vector<Aabb> triangleBounds;           // for the occluder bounds of split clusters
    std::vector<std::uint32_t> internalOffsets; // internal edges of cluster c
    std::vector<InternalEdge> internalEdges;
    std::vector<std::uint64_t> adjacency;       // cluster-internal neighbours across them
    std::vector<ClusterLink> links;             // consistent two-use edges between clusters,
    std::vector<InternalEdge> linkEdges;        // grouped by cluster pair
    std::vector<EdgeRecord> records;            // other edges, evaluated every frame
    std::vector<std::uint32_t> recordEdge;      // their Topology edge ids
    std::vector<std::uint32_t> generalOffsets;  // uses of 3+-use edges
    std::vector<std::uint32_t> generalUses;     // local triangle | kSignBit
    double positionRadius = 0.0;                // max |p|, for the float facing error bound
    Aabb meshBounds;
    double meshScale = 0.0;     // diagonal of meshBounds
    bool closedOutward = false; // closed, and no component encloses negative volume

    // Whether the light centre is inside the closed mesh, for the last centre asked about.
    enum class Containment : std::uint8_t { Outside, Inside, Unsure };
    bool haveContainment = false;
    glm::vec3 containmentLight{0.0f};
    Containment containment = Containment::Unsure;

    // --- Per frame, sized once ---
    std::vector<std::int8_t> orient;         // +1, -1 (two-sided) or 0 (not participating);
                                             // one extra dummy entry, always 0
    std::vector<std::uint64_t> posBits, negBits; // orient > 0, orient < 0 (bit t % 64 of
                                                 // word t / 64; one padding word)
    std::vector<std::uint64_t> unsureBits;       // classify: left to the exact test
    std::vector<std::uint8_t> uniform;       // per cluster
    std::vector<Component> components;       // of the non-uniform clusters, in cluster order
    std::vector<std::uint32_t> componentOffsets; // per cluster, into components
    std::vector<std::uint32_t> nodeOf;       // triangles of non-uniform clusters: their node
    std::vector<std::uint32_t> parent;       // union-find over nodes (local triangle ids)
    std::vector<std::uint32_t> rootGroup;    // group of a union-find root
    std::vector<std::uint32_t> clusterGroup; // uniform clusters
    std::vector<std::uint32_t> triangleGroup; // triangles of non-uniform clusters
    std::vector<Candidate> candidates; // sized once for every evaluated edge; candidateCount used
    std::uint32_t candidateCount = 0;
    std::vector<GroupEdge> groupEdges;
    std::vector<std::uint32_t> groupTriangleCount, groupCopyCount, groupCursor;
    std::vector<Aabb> groupBounds;
    // Loop chaining, per vertex (reset after each group) and per edge copy.
    std::vector<std::uint32_t> outHead, inHead, outDegree;
    std::vector<std::uint32_t> outNext, inNext, successor;
    std::vector<std::uint8_t> visited;
    std::vector<SilhouetteEdge> copies;
    std::vector<std::uint32_t> multiVertices, ins, outs;
    std::vector<std::uint8_t> straddles; // influence bounds: per edge of the group
    WedgeRays rays;                      // the wedge just built

    void build(const Topology& topology);
    void buildOrientation(const Topology& topology);
    Containment lightContainment(const Topology& topology, const glm::vec3& light);
    Containment rayContainment(const Topology& topology, const glm::dvec3& light) const;
    void classify(const Topology& topology, const glm::vec3& light, bool oneSided);
    void mergeGroups();

    std::uint32_t find(std::uint32_t x) {
        while (parent[x] != x) {
            parent[x] = parent[parent[x]]; // path halving
            x = parent[x];
        }
        return x;
    }
    void unite(std::uint32_t a, std::uint32_t b) {
        a = find(a);
        b = find(b);
        if (a == b) return;
        // The smaller id becomes the root: deterministic, independent of the union order.
        if (a < b) {
            parent[b] = a;
        } else {
            parent[a] = b;
        }
    }
    std::uint32_t node(std::uint32_t t) const {
        const std::uint32_t c = clusterOf[t];
        return uniform[c] ? clusterOffsets[c] : nodeOf[t];
    }
    std::uint32_t groupOf(std::uint32_t t) const {
        const std::uint32_t c = clusterOf[t];
        return uniform[c] ? clusterGroup[c] : triangleGroup[t];
    }
};

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

namespace {

// Generic directions for the containment rays (no axis-aligned or diagonal ties with
// axis-aligned meshes); the next is tried when a ray passes too close to an edge.
constexpr std::array<std::array<double, 3>, 4> kContainmentDirs = {{{0.3241, 0.8127, 0.4842},
                                                                    {-0.7053, 0.2671, 0.6567},
                                                                    {0.5512, -0.4117, -0.7257},
                                                                    {-0.2089, -0.8736, 0.4395}}};

// Whether the ray l + t d (t >= 0) meets the box grown by pad.
bool rayMeetsBox(const glm::dvec3& l, const glm::dvec3& d, const Aabb& box, double pad) {
    double t0 = 0.0, t1 = std::numeric_limits<double>::infinity();
    for (int k = 0; k < 3; ++k) {
        const double lo = double(box.min[k]) - pad, hi = double(box.max[k]) + pad;
        if (d[k] == 0.0) {
            if (l[k] < lo || l[k] > hi) return false;
            continue;
        }
        double a = (lo - l[k]) / d[k], b = (hi - l[k]) / d[k];
        if (a > b) std::swap(a, b);
        t0 = std::max(t0, a);
        t1 = std::min(t1, b);
        if (t0 > t1) return false;
    }
    return true;
}

} // namespace

// Winding number of the closed mesh at the light centre by signed ray crossings: +1 for each
// triangle the ray leaves through (along its normal), -1 for each it enters through. Unsure when
// the centre lies on a triangle (within 1e-7 of the mesh size along the ray), or when every ray
// tried passes within rounding distance of an edge or vertex.
SilhouetteExtractor::Scratch::Containment
SilhouetteExtractor::Scratch::rayContainment(const Topology& topology,
                                             const glm::dvec3& l) const {
    const auto positions = topology.positions();
    const std::size_t clusterCount = clusterOffsets.size() - 1;
    const double pad = 1e-6 * meshScale;
    const double onSurface = 1e-7 * meshScale;
    for (const auto& dirValues : kContainmentDirs) {
        const glm::dvec3 d = glm::normalize(glm::dvec3(dirValues[0], dirValues[1], dirValues[2]));
        int winding = 0;
        bool tie = false;
        for (std::size_t c = 0; c < clusterCount && !tie; ++c) {
            if (!rayMeetsBox(l, d, clusterBounds[c], pad)) continue;
            for (std::uint32_t t = clusterOffsets[c]; t < clusterOffsets[c + 1]; ++t) {
                const glm::uvec3 tri = localTriangles[t];
                const glm::dvec3 da = glm::dvec3(positions[tri.x]) - l;
                const glm::dvec3 db = glm::dvec3(positions[tri.y]) - l;
                const glm::dvec3 dc = glm::dvec3(positions[tri.z]) - l;
                // The line l + t d passes through the triangle when these three agree in sign
                // (signed volumes of d with each edge seen from l); their sum is dot(n, d).
                const double pa = glm::dot(d, glm::cross(db, dc));
                const double pb = glm::dot(d, glm::cross(dc, da));
                const double pc = glm::dot(d, glm::cross(da, db));
                const double r = std::max({glm::length(da), glm::length(db), glm::length(dc)});
                const double tol = 1e-10 * r * r;
                const double lo = std::min({pa, pb, pc}), hi = std::max({pa, pb, pc});
                if (lo < -tol && hi > tol) continue; // clearly beside the triangle
                const glm::dvec3 n = glm::cross(db - da, dc - da);
                const double nd = glm::dot(n, d);
                if (lo > tol || hi < -tol) {
                    const double along = glm::dot(n, da) / nd; // ray parameter of the plane
                    if (std::abs(along) <= onSurface) return Containment::Unsure;
                    if (along > 0.0) winding += nd > 0.0 ? 1 : -1;
                    continue;
                }
                // Near an edge or vertex, or in the triangle's plane: a tie unless the triangle
                // lies wholly behind the centre.
                const double back = -1e-9 * r;
                if (glm::dot(da, d) < back && glm::dot(db, d) < back && glm::dot(dc, d) < back)
                    continue;
                tie = true;
                break;
            }
        }
        if (!tie) return winding != 0 ? Containment::Inside : Containment::Outside;
    }
    return Containment::Unsure;
}

SilhouetteExtractor::Scratch::Containment
SilhouetteExtractor::Scratch::lightContainment(const Topology& topology, const glm::vec3& light) {
    if (haveContainment && containmentLight == light) return containment;
    const glm::dvec3 l(light);
    const double pad = 1e-6 * meshScale;
    bool inBox = !meshBounds.empty();
    for (int k = 0; k < 3 && inBox; ++k)
        inBox = l[k] >= double(meshBounds.min[k]) - pad && l[k] <= double(meshBounds.max[k]) + pad;
    containment = inBox ? rayContainment(topology, l) : Containment::Outside;
    containmentLight = light;
    haveContainment = true;
    return containment;
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
           a.chainLoops == b.chainLoops && a.influenceBounds == b.influenceBounds;
}

} // namespace

// Step 1: orientation of every triangle (local order), as bytes (for lookups by triangle) and
// as bit sets (for the clusters' masks), 64 triangles per word.
void SilhouetteExtractor::Scratch::classify(const Topology& topology, const glm::vec3& light,
                                            bool oneSided) {
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
                const bool facing = glm::dot(nn, l - a) >= 0.0;
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

namespace {

// The 12 box edges as pairs of corner indices (boxCorner: bit 0 = x, bit 1 = y, bit 2 = z).
constexpr std::array<std::array<int, 2>, 12> kBoxEdges = {{{0, 1}, {2, 3}, {4, 5}, {6, 7},
                                                           {0, 2}, {1, 3}, {4, 6}, {5, 7},
                                                           {0, 4}, {1, 5}, {2, 6}, {3, 7}}};

constexpr int kMixedFaces = -1;

// Extends `bounds` by the part of the ray p + t d (t >= 0) inside `box`. Returns the box face
// the ray leaves through (2 axis + (d[axis] > 0)) when it starts inside the box, else
// kMixedFaces.
int extendRayInBox(Aabb& bounds, const glm::vec3& p, const glm::vec3& d, const Aabb& box) {
    float t0 = 0.0f, t1 = std::numeric_limits<float>::infinity();
    int face = kMixedFaces;
    for (int k = 0; k < 3; ++k) {
        if (d[k] == 0.0f) {
            if (p[k] < box.min[k] || p[k] > box.max[k]) return kMixedFaces;
            continue;
        }
        const float inv = 1.0f / d[k];
        const float a = (box.min[k] - p[k]) * inv, b = (box.max[k] - p[k]) * inv;
        t0 = std::max(t0, std::min(a, b));
        const float exit = std::max(a, b);
        if (exit < t1) {
            t1 = exit;
            face = 2 * k + (d[k] > 0.0f ? 1 : 0);
        }
    }
    if (t0 > t1) return kMixedFaces;
    bounds.extend(p + t0 * d);
    bounds.extend(p + t1 * d);
    return t0 > 0.0f ? kMixedFaces : face;
}

// Common exit face of several rays: kMixedFaces as soon as two differ.
int mergeFaces(int a, int b) { return a == b ? a : kMixedFaces; }

// A wedge's rays from both its end points, as extendRayInBox for each (the same bounds and the
// same common exit face), but with each ray's reciprocal computed once for both ends, and for an
// end inside the box (always, for a scene box around the mesh) without the entry parameter: from
// inside the box every ray enters at t = 0, at the end point itself, which the caller's bounds
// already hold (occluderBounds), and leaves where the first of its three exit slabs ends.
int extendWedgeRaysInBox(Aabb& bounds, const glm::vec3& e0, const glm::vec3& e1,
                         const WedgeRays& rays, const Aabb& box) {
    if (!contains(box, e0) || !contains(box, e1)) {
        int face = extendRayInBox(bounds, e0, rays.dirs[0], box);
        for (int r = 0; r < rays.count; ++r) {
            if (r > 0) face = mergeFaces(face, extendRayInBox(bounds, e0, rays.dirs[r], box));
            face = mergeFaces(face, extendRayInBox(bounds, e1, rays.dirs[r], box));
        }
        return face;
    }
    bounds.extend(e0);
    bounds.extend(e1);
    const glm::vec3 lo0 = box.min - e0, hi0 = box.max - e0; // lo <= 0 <= hi
    const glm::vec3 lo1 = box.min - e1, hi1 = box.max - e1;
    glm::vec3 bmin = bounds.min, bmax = bounds.max;
    int face = kMixedFaces - 1; // not set yet
    for (int r = 0; r < rays.count; ++r) {
        const glm::vec3 d = rays.dirs[r];
        float t0 = std::numeric_limits<float>::infinity(), t1 = t0;
        int f0 = kMixedFaces, f1 = kMixedFaces;
        for (int k = 0; k < 3; ++k) {
            if (d[k] == 0.0f) continue; // parallel to this slab, and inside it
            const float inv = 1.0f / d[k];
            const bool up = d[k] > 0.0f;
            const float a = (up ? hi0[k] : lo0[k]) * inv, b = (up ? hi1[k] : lo1[k]) * inv;
            // Strictly smaller, in axis order: the face extendRayInBox reports.
            if (a < t0) {
                t0 = a;
                f0 = 2 * k + up;
            }
            if (b < t1) {
                t1 = b;
                f1 = 2 * k + up;
            }
        }
        const glm::vec3 x0 = e0 + t0 * d, x1 = e1 + t1 * d;
        bmin = glm::min(bmin, glm::min(x0, x1));
        bmax = glm::max(bmax, glm::max(x0, x1));
        face = mergeFaces(face == kMixedFaces - 1 ? f0 : face, f0);
        face = mergeFaces(face, f1);
    }
    bounds.min = bmin;
    bounds.max = bmax;
    return face == kMixedFaces - 1 ? kMixedFaces : face;
}

// Where the group can change visibility, clamped to the scene: the AABB of
// (volume ∪ wedges) ∩ box, for the wedges as built (their float planes, which are looser than
// the exact E + cone{e_i - c_j}: see wedgeRecessionRays in geometry/shadow/Wedge.h).
//
// The extreme points of a convex piece P ∩ box are vertices: vertices of P inside the box,
// crossings of P's edges with box faces, crossings of P's facets with box edges, and box
// corners inside P. For a wedge P = conv(V) + C, V its finite vertices (at E, within the
// planes' outward push) and C the recession cone above, so its edges are segments near E
// (occluderBounds) and rays v + t r (r an extreme ray of C), approximated by e0 + t r and
// e1 + t r: points of P (e0, e1 are in P, r in C) within the push of the true edges, which the
// final padding covers. Facet crossings and corners use the stored planes, evaluated in float
// exactly as wedgeContains does. The volume's boundary is its caps (in occluderBounds or at
// infinity) and side quads, which lie inside the wedges (the light centre is a light point),
// so with wedges only box corners inside the volume need a test of their own; without wedges
// the side quads' rays and box-edge crossings are used instead.
//
// Work is ordered by cost: rays first, then box edges and corners, and those only where they can
// matter. When every edge ray of a piece P starts inside the box and leaves it through the same
// face F, P ∩ box = P ∩ (F's half-space), a bounded polytope whose vertices are P's finite
// vertices and the ray exits on F (every recession direction of P leaves through F): no box
// edge or corner can add anything. That holds for almost every wedge in practice (a penumbra
// falls on one wall), so the per-edge box tests run only for the few pieces that straddle a box
// edge, and only for box edges and corners still outside the bounds.
//
// With wedges, pass 1 (the rays) runs in update() as each wedge is built, while its rays are at
// hand from the builder (WedgeRayPass below); `rayBounds` and `straddles` are its result.
// Pass 1 of influenceBounds for wedges, fed wedge by wedge: the rays from both end points, and
// which pieces straddle a box edge. `whole` once the bounds can only be the whole box.
struct WedgeRayPass {
    Aabb bounds;
    bool whole = false;

    void begin(const SilhouetteGroup& group, const Aabb& box, std::uint32_t edgeCount,
               std::vector<std::uint8_t>& straddles) {
        bounds = group.occluderBounds;
        whole = box.empty(); // (influenceBounds returns empty bounds then)
        straddles.assign(edgeCount, 0);
    }
    void add(const Wedge& wedge, const WedgeRays& rays, const Aabb& box, std::uint8_t& straddle) {
        if (whole || (wedge.flags & kWedgeDegenerate)) return;
        if (rays.count < 0) {
            whole = true; // may reach any point of the scene
            return;
        }
        const int face = extendWedgeRaysInBox(bounds, glm::vec3(wedge.e0), glm::vec3(wedge.e1),
                                              rays, box);
        straddle = face == kMixedFaces;
        // Typical in interiors (the light inside, walls all around): the group's penumbrae
        // already reach every wall, nothing further can grow the bounds.
        whole = coversBox(bounds, box);
    }
};

Aabb influenceBounds(const SilhouetteFrame& frame, const SilhouetteGroup& group,
                     const Topology& topo, const glm::vec3& lc, const Aabb& box, bool wedges,
                     const Aabb& rayBounds, std::vector<std::uint8_t>& straddles) {
    if (box.empty()) return Aabb{};
    const auto positions = topo.positions();
    Aabb b = wedges ? rayBounds : group.occluderBounds;
    std::array<glm::vec3, 8> corners;
    for (int i = 0; i < 8; ++i) corners[i] = boxCorner(box, i);
    const std::uint32_t edgeEnd = group.firstEdge + group.edgeCount;
    const Wedge* groupWedges = wedges ? frame.wedges.wedges.data() + group.firstWedge : nullptr;

    // Pass 1 without wedges: the side quads' rays, and which quads straddle a box edge.
    if (!wedges) {
        straddles.assign(group.edgeCount, 0);
        for (std::uint32_t k = group.firstEdge; k < edgeEnd; ++k) {
            const glm::vec3 e0 = positions[frame.edges[k].v0];
            const glm::vec3 e1 = positions[frame.edges[k].v1];
            // The side quad's two edge rays (a vertex at the light casts none).
            int face = e0 != lc ? extendRayInBox(b, e0, e0 - lc, box) : kMixedFaces;
            face = mergeFaces(face, e1 != lc ? extendRayInBox(b, e1, e1 - lc, box) : kMixedFaces);
            straddles[k - group.firstEdge] = face == kMixedFaces;
            if (coversBox(b, box)) return box;
        }
    }

    // Pass 2: box edges and corners not yet inside the bounds.
    std::uint32_t cornersOut = 0, edgesOut = 0;
    const auto updateOutside = [&] {
        cornersOut = 0;
        for (int i = 0; i < 8; ++i) cornersOut |= contains(b, corners[i]) ? 0u : 1u << i;
        edgesOut = 0;
        for (int e = 0; e < 12; ++e) {
            // An edge is covered when both its ends are (the bounds are a box).
            edgesOut |= (cornersOut >> kBoxEdges[e][0] | cornersOut >> kBoxEdges[e][1]) & 1u
                            ? 1u << e
                            : 0u;
        }
    };
    updateOutside();
    for (std::uint32_t k = group.firstEdge; k < edgeEnd && edgesOut != 0; ++k) {
        if (!straddles[k - group.firstEdge]) continue;
        const Aabb before = b;
        if (wedges) {
            const Wedge& wedge = groupWedges[k - group.firstEdge];
            if (wedge.flags & kWedgeDegenerate) continue;
            // f[p][c]: plane p at corner c, as wedgeContains evaluates it.
            std::array<std::array<float, 8>, kMaxWedgePlanes> f;
            const auto planeCount = static_cast<int>(wedge.planeCount);
            for (int p = 0; p < planeCount; ++p) {
                const glm::vec4& pl = wedge.planes[p];
                for (int c = 0; c < 8; ++c)
                    f[p][c] = glm::dot(glm::vec3(pl), corners[c]) + pl.w;
            }
            for (int c = 0; c < 8; ++c) {
                if (!(cornersOut >> c & 1u)) continue;
                bool inside = true;
                for (int p = 0; p < planeCount && inside; ++p) inside = f[p][c] <= 0.0f;
                if (inside) b.extend(corners[c]);
            }
            for (int e = 0; e < 12; ++e) {
                if (!(edgesOut >> e & 1u)) continue;
                const int ca = kBoxEdges[e][0], cb = kBoxEdges[e][1];
                float t0 = 0.0f, t1 = 1.0f;
                for (int p = 0; p < planeCount && t0 <= t1; ++p) {
                    const float fa = f[p][ca], fb = f[p][cb];
                    if (fa <= 0.0f && fb <= 0.0f) continue;
                    if (fa > 0.0f && fb > 0.0f) {
                        t1 = -1.0f;
                        break;
                    }
                    const float t = fa / (fa - fb);
                    if (fa > 0.0f) {
                        t0 = std::max(t0, t);
                    } else {
                        t1 = std::min(t1, t);
                    }
                }
                if (t0 > t1) continue;
                const glm::vec3 d = corners[cb] - corners[ca];
                b.extend(corners[ca] + t0 * d);
                b.extend(corners[ca] + t1 * d);
            }
        } else {
            // The side quad E + cone{e0 - lc, e1 - lc} (planar) against the box edges.
            const glm::dvec3 l(lc);
            const glm::dvec3 r0 = glm::dvec3(positions[frame.edges[k].v0]) - l;
            const glm::dvec3 r1 = glm::dvec3(positions[frame.edges[k].v1]) - l;
            const glm::dvec3 n = glm::cross(r0, r1);
            const double nn = glm::dot(n, n);
            if (nn == 0.0) continue; // edge in line with the light: a flat, empty quad
            std::array<double, 8> f;
            for (int c = 0; c < 8; ++c) f[c] = glm::dot(n, glm::dvec3(corners[c]) - l);
            const double onPlane = 1e-9 * std::sqrt(nn) * (glm::length(box.extent()) + 1.0);
            for (int e = 0; e < 12; ++e) {
                if (!(edgesOut >> e & 1u)) continue;
                const int ca = kBoxEdges[e][0], cb = kBoxEdges[e][1];
                const double fa = f[ca], fb = f[cb];
                if (std::abs(fa) <= onPlane && std::abs(fb) <= onPlane) {
                    // Box edge in the quad's plane: conservatively take it whole.
                    b.extend(corners[ca]);
                    b.extend(corners[cb]);
                    continue;
                }
                if ((fa > 0.0 && fb > 0.0) || (fa < 0.0 && fb < 0.0)) continue;
                const double t = fa / (fa - fb);
                const glm::dvec3 a(corners[ca]);
                const glm::dvec3 x = a + t * (glm::dvec3(corners[cb]) - a) - l;
                // x = alpha r0 + beta r1 with alpha, beta >= 0 and alpha + beta >= 1 (beyond E).
                const double alpha = glm::dot(glm::cross(x, r1), n) / nn;
                const double beta = glm::dot(glm::cross(r0, x), n) / nn;
                constexpr double kTol = 1e-9;
                if (alpha >= -kTol && beta >= -kTol && alpha + beta >= 1.0 - kTol)
                    b.extend(glm::vec3(x + l));
            }
        }
        if (b.min != before.min || b.max != before.max) updateOutside();
    }

    // Box corners inside the volume (the segment to the light centre crosses one of the
    // group's triangles). Corners inside a wedge were taken above.
    const auto groupTriangles = std::span<const std::uint32_t>(frame.triangles)
                                    .subspan(group.firstTriangle, group.triangleCount);
    for (int i = 0; i < 8; ++i) {
        if (!(cornersOut >> i & 1u) || contains(b, corners[i])) continue;
        const glm::dvec3 p(corners[i]);
        double t0, t1;
        if (!clipRay(p, glm::dvec3(lc) - p, group.occluderBounds, 1.0, t0, t1)) continue;
        bool inside = group.triangleCount > kExactCornerTestLimit; // conservative for big groups
        for (std::size_t j = 0; j < groupTriangles.size() && !inside; ++j) {
            const glm::uvec3 tri = topo.triangles()[groupTriangles[j] & ~kTriangleFlipped];
            inside = segmentHitsTriangle(p, glm::dvec3(lc), glm::dvec3(positions[tri.x]),
                                         glm::dvec3(positions[tri.y]),
                                         glm::dvec3(positions[tri.z]));
        }
        if (inside) b.extend(corners[i]);
    }

    // Float rounding of the clipped points and the push of the wedge planes: pad by a hair,
    // then clamp to the scene.
    const glm::vec3 pad = 1e-5f * (box.extent() + glm::vec3(1e-6f));
    b.min = glm::max(b.min - pad, box.min);
    b.max = glm::min(b.max + pad, box.max);
    if (b.min.x > b.max.x || b.min.y > b.max.y || b.min.z > b.max.z) return Aabb{};
    return b;
}

// The light's axis-aligned box (of its four corners), in double.
struct LightBox {
    glm::dvec3 min, max;
    explicit LightBox(const RectLight& light) {
        const glm::dvec3 c(light.center), u(light.u), v(light.v);
        const glm::dvec3 reach = glm::abs(u) + glm::abs(v);
        min = c - reach;
        max = c + reach;
    }
};

// A float no greater than x (finite x within float range): x rounded, and when that rounded up,
// moved down by at least one ulp (|f| 2^-23 is one or two ulps; FLT_MIN covers f = 0).
inline float floatAtMost(double x) {
    const auto f = static_cast<float>(x);
    if (static_cast<double>(f) <= x) return f;
    return f - (std::abs(f) * 0x1p-23f + std::numeric_limits<float>::min());
}

// InfluenceBoundsMode::OccluderCone: the bounds of R ∩ S for
//     R = { a + t (a - y) : a in B, y in L, t >= 0 }
// (B the occluder box, L the light, S the scene box). R holds the group's volume (a on its
// triangles, y the light centre) and the exact wedge E + cone{e - y} of every edge in B.
//
// Why this is conservative (not just "the corner rays clipped to S", which need not be): for a
// fixed t, the points (1 + t) a - t y form the Minkowski sum (1 + t) B + (-t) L, which lies in the
// box Q(t) = [lo(t), hi(t)] with, per axis k (L's box [Lmin, Lmax]),
//     lo_k(t) = Bmin_k + t (Bmin_k - Lmax_k),   hi_k(t) = Bmax_k + t (Bmax_k - Lmin_k).
// A point P of R ∩ S lies in Q(t) ∩ S for its own t, so t is in T = { t >= 0 : Q(t) meets S },
// an interval (each "Q(t) meets S on axis k" is a pair of linear inequalities in t), and
// P_k is in [max(lo_k(t), Smin_k), min(hi_k(t), Smax_k)]. Over t in T those ends are extreme at
// T's ends (lo_k and hi_k are linear), which gives the bounds; at an infinite end a decreasing
// lo_k (or increasing hi_k) reaches S's face.
//
// Rounding, and the float planes of wedges built elsewhere (slightly outside the exact wedges,
// by an angle: so by more the farther from the edge): B and S are grown by a margin (growing B
// by m grows R by (1 + t) m, which follows that angle), and the result is clamped to S.
Aabb occluderConeBounds(const Aabb& occluder, const LightBox& light, const Aabb& scene) {
    if (scene.empty() || occluder.empty()) return Aabb{};
    const glm::dvec3 sceneExtent(scene.extent());
    const double margin =
        1e-5 * std::max({sceneExtent.x, sceneExtent.y, sceneExtent.z, 1e-6});
    const glm::dvec3 bMin = glm::dvec3(occluder.min) - margin;
    const glm::dvec3 bMax = glm::dvec3(occluder.max) + margin;
    const glm::dvec3 sMin = glm::dvec3(scene.min) - margin;
    const glm::dvec3 sMax = glm::dvec3(scene.max) + margin;
    const glm::dvec3 loSlope = bMin - light.max, hiSlope = bMax - light.min;
    constexpr double kInf = std::numeric_limits<double>::infinity();
    double t0 = 0.0, t1 = kInf;
    // f0 + f1 t <= g on T.
    const auto constrain = [&](double f0, double f1, double g) {
        if (f1 > 0.0) {
            t1 = std::min(t1, (g - f0) / f1);
        } else if (f1 < 0.0) {
            t0 = std::max(t0, (g - f0) / f1);
        } else if (f0 > g) {
            t1 = -1.0;
        }
    };
    for (int k = 0; k < 3; ++k) {
        constrain(bMin[k], loSlope[k], sMax[k]);    // lo_k(t) <= Smax_k
        constrain(-bMax[k], -hiSlope[k], -sMin[k]); // hi_k(t) >= Smin_k
    }
    if (!(t0 <= t1)) return Aabb{};
    Aabb b;
    for (int k = 0; k < 3; ++k) {
        const double loEnd = loSlope[k] >= 0.0 ? t0 : t1;
        const double hiEnd = hiSlope[k] <= 0.0 ? t0 : t1;
        const double lo = loEnd == kInf ? -kInf : bMin[k] + loEnd * loSlope[k];
        const double hi = hiEnd == kInf ? kInf : bMax[k] + hiEnd * hiSlope[k];
        // Rounded outward to float, then clamped to the scene.
        b.min[k] = std::max(floatAtMost(std::max(lo, sMin[k])), scene.min[k]);
        b.max[k] = std::min(-floatAtMost(-std::min(hi, sMax[k])), scene.max[k]);
    }
    if (b.min.x > b.max.x || b.min.y > b.max.y || b.min.z > b.max.z) return Aabb{};
    return b;
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

    s.classify(topo, lc, oneSided);
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
