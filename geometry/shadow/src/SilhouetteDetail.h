// Private to geometry/shadow: what the parts of the silhouette extractor share (Silhouette.cpp
// the per-frame update and loops; SilhouetteClusters.cpp the clusters built once per mesh;
// SilhouetteContainment.cpp whether the light is inside a closed mesh; SilhouetteGroups.cpp the
// per-frame orientation and groups; SilhouetteInfluence.cpp the groups' influence bounds):
// constants, small helpers and the extractor's scratch state.
#pragma once

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
#include <vector>

namespace geometry {

namespace silhouette_detail {

inline constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();
inline constexpr std::uint32_t kSignBit = 0x80000000u; // set: the use runs v1 -> v0 (sign -1)
inline constexpr std::uint32_t kIdMask = 0x7fffffffu;
// EdgeRecord::b marker: 3+ uses, a = the general index.
inline constexpr std::uint32_t kGeneralEdge = kNone;

// Cluster size: large enough that few edges cross clusters, small enough that the clusters the
// silhouette passes through (handled triangle by triangle) stay a small part of the mesh.
inline constexpr std::uint32_t kClusterSize = 64;
static_assert(kClusterSize <= 64, "cluster masks are 64-bit");

// Exact "is the corner in the volume" tests are only run for groups up to this size; larger
// groups take the conservative answer of the bounding-box test (keeps the per-frame cost
// independent of the mesh size).
inline constexpr std::uint32_t kExactCornerTestLimit = 4096;

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
inline bool clipRay(const glm::dvec3& p, const glm::dvec3& d, const Aabb& box, double tMax, double& t0,
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

inline bool contains(const Aabb& b, const glm::vec3& p) {
    return p.x >= b.min.x && p.y >= b.min.y && p.z >= b.min.z && p.x <= b.max.x &&
           p.y <= b.max.y && p.z <= b.max.z;
}

inline bool coversBox(const Aabb& b, const Aabb& box) {
    return b.min.x <= box.min.x && b.min.y <= box.min.y && b.min.z <= box.min.z &&
           b.max.x >= box.max.x && b.max.y >= box.max.y && b.max.z >= box.max.z;
}

inline glm::vec3 boxCorner(const Aabb& box, int i) {
    return {i & 1 ? box.max.x : box.min.x, i & 2 ? box.max.y : box.min.y,
            i & 4 ? box.max.z : box.min.z};
}

// Segment a -> b against a triangle (Möller-Trumbore in double), endpoints excluded.
inline bool segmentHitsTriangle(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& p0,
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

} // namespace silhouette_detail

using namespace silhouette_detail;

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
    std::uint32_t flatTriangles = 0;             // classify: the light centre in their plane
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
    void classify(const Topology& topology, const glm::vec3& light, bool oneSided,
                  bool flatTrianglesFace);
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

namespace silhouette_detail {

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
    void add(const Wedge& wedge, const WedgeRays& rays, const Aabb& box, std::uint8_t& straddle);
};

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

// Conservative bounds of (the group's volume ∪ its wedges) ∩ box (SilhouetteInfluence.cpp).
Aabb influenceBounds(const SilhouetteFrame& frame, const SilhouetteGroup& group,
                     const Topology& topo, const glm::vec3& lc, const Aabb& box, bool wedges,
                     const Aabb& rayBounds, std::vector<std::uint8_t>& straddles);

// The box of the points an occluder in `occluder` can shade from `light`, within `scene`.
Aabb occluderConeBounds(const Aabb& occluder, const LightBox& light, const Aabb& scene);

} // namespace silhouette_detail

} // namespace geometry
