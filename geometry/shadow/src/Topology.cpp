// Welded edge topology (geometry/shadow/Topology.h):
// - weld by position on a uniform grid hashed into a flat open-addressing table (O(n), input order
//   decides every tie, so the result is deterministic);
// - drop degenerate and exactly duplicated triangles, compact the welded vertices to the referenced ones;
// - unique undirected edges and their uses by a counting sort on the smaller vertex id (O(n));
// - an OpenMesh half-edge mesh with duplicated vertices where OpenMesh cannot take a corner;
// - classification from the edge uses and the vertex fans.
#include <geometry/shadow/Topology.h>

#include <geometry/core/Error.h>

#include "HalfEdgeMesh.h"
#include <geometry/core/Hash.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <string>
#include <unordered_set>
#include <utility>

namespace geometry {

const char* toString(Manifoldness m) {
    switch (m) {
    case Manifoldness::Closed:
        return "closed";
    case Manifoldness::Open:
        return "open";
    case Manifoldness::NonManifold:
        return "non-manifold";
    }
    return "unknown";
}

namespace {

constexpr std::uint32_t kNoId = std::numeric_limits<std::uint32_t>::max();

// Triangles with |cross(b-a, c-a)| <= kDegenerateArea * diagonal^2 have no area worth keeping.
// Relative to the bounds (not to the triangle) because float rounding of the positions is
// relative to the coordinates' magnitude; 1e-12 only catches (numerically) collinear corners.
constexpr double kDegenerateArea = 1e-12;

// Cell coordinates are packed 21 bits per axis into one 64-bit key.
constexpr std::int64_t kMaxCell = (std::int64_t{1} << 21) - 2;


// Cell key -> most recently inserted welded vertex of that cell (the rest chained via `next`).
class CellTable {
public:
    explicit CellTable(std::size_t expected) {
        std::size_t capacity = 16;
        while (capacity < expected + expected / 2)
            capacity *= 2;
        mSlots.assign(capacity, Slot{kEmpty, kNoId});
        mMask = capacity - 1;
    }

    std::uint32_t find(std::uint64_t key) const {
        for (std::size_t i = mix64(key) & mMask;; i = (i + 1) & mMask) {
            if (mSlots[i].key == key) return mSlots[i].head;
            if (mSlots[i].key == kEmpty) return kNoId;
        }
    }

    // Returns the previous head of the cell (kNoId if new) and makes `vertex` the head.
    std::uint32_t push(std::uint64_t key, std::uint32_t vertex) {
        for (std::size_t i = mix64(key) & mMask;; i = (i + 1) & mMask) {
            if (mSlots[i].key == key) return std::exchange(mSlots[i].head, vertex);
            if (mSlots[i].key == kEmpty) {
                mSlots[i] = Slot{key, vertex};
                return kNoId;
            }
        }
    }

private:
    static constexpr std::uint64_t kEmpty = std::numeric_limits<std::uint64_t>::max();
    struct Slot {
        std::uint64_t key;
        std::uint32_t head;
    };
    std::vector<Slot> mSlots;
    std::size_t mMask = 0;
};

std::uint64_t packCell(std::int64_t x, std::int64_t y, std::int64_t z) {
    return static_cast<std::uint64_t>(x) | (static_cast<std::uint64_t>(y) << 21) |
           (static_cast<std::uint64_t>(z) << 42);
}

void validate(const MeshData& mesh) {
    for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
        const glm::vec3& p = mesh.positions[i];
        if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) {
            throw InputError("mesh '" + mesh.name + "': position " + std::to_string(i) +
                             " is not finite");
        }
    }
    const std::size_t n = mesh.positions.size();
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
        const glm::uvec3& tri = mesh.triangles[t];
        for (int k = 0; k < 3; ++k) {
            if (tri[k] >= n) {
                throw InputError("mesh '" + mesh.name + "': triangle " + std::to_string(t) +
                                 " has vertex index " + std::to_string(tri[k]) + " but only " +
                                 std::to_string(n) + " positions");
            }
        }
    }
}

// Maps every input position to a welded vertex; fills `welded` with the representative positions
// (the first input position of each cluster). Two positions within `tolerance` of each other end
// up in one vertex when one of them is the representative (clusters are not transitive closures:
// a chain of near points spaced just under the tolerance is not collapsed into one).
std::vector<std::uint32_t> weldPositions(std::span<const glm::vec3> positions, const Aabb& bounds,
                                         double tolerance, std::vector<glm::vec3>& welded) {
    std::vector<std::uint32_t> remap(positions.size());
    welded.clear();
    if (positions.empty()) return remap;

    const glm::dvec3 lo(bounds.min);
    const glm::dvec3 extent = glm::dvec3(bounds.max) - lo;
    const double maxExtent = std::max({extent.x, extent.y, extent.z});
    // Cells at least as large as the tolerance (so a partner is in one of the 27 neighbouring
    // cells) and few enough per axis to pack; larger cells stay correct, only chains get longer.
    double cell = std::max(tolerance, maxExtent / static_cast<double>(kMaxCell));
    if (!(cell > 0.0)) cell = 1.0; // all positions equal
    const double invCell = 1.0 / cell;
    const double tol2 = tolerance * tolerance;

    CellTable table(positions.size());
    std::vector<std::uint32_t> next; // welded vertex -> next older welded vertex of its cell
    next.reserve(positions.size());
    welded.reserve(positions.size());

    auto cellOf = [&](const glm::vec3& p) {
        const glm::dvec3 c = glm::floor((glm::dvec3(p) - lo) * invCell);
        return glm::i64vec3(std::clamp<std::int64_t>(static_cast<std::int64_t>(c.x), 0, kMaxCell),
                            std::clamp<std::int64_t>(static_cast<std::int64_t>(c.y), 0, kMaxCell),
                            std::clamp<std::int64_t>(static_cast<std::int64_t>(c.z), 0, kMaxCell));
    };
    // Smallest welded id within the tolerance in one cell, or kNoId.
    auto searchCell = [&](std::uint64_t key, const glm::dvec3& p) {
        std::uint32_t best = kNoId;
        for (std::uint32_t w = table.find(key); w != kNoId; w = next[w]) {
            const glm::dvec3 d = glm::dvec3(welded[w]) - p;
            if (glm::dot(d, d) <= tol2) best = std::min(best, w);
        }
        return best;
    };

    for (std::size_t i = 0; i < positions.size(); ++i) {
        const glm::dvec3 p(positions[i]);
        const glm::i64vec3 c = cellOf(positions[i]);
        const std::uint64_t key = packCell(c.x, c.y, c.z);
        // The own cell first: split glTF vertices are exact duplicates, found here at once.
        std::uint32_t match = searchCell(key, p);
        if (match == kNoId && tolerance > 0.0) {
            for (std::int64_t dz = -1; dz <= 1; ++dz) {
                for (std::int64_t dy = -1; dy <= 1; ++dy) {
                    for (std::int64_t dx = -1; dx <= 1; ++dx) {
                        const glm::i64vec3 n = c + glm::i64vec3(dx, dy, dz);
                        if ((dx == 0 && dy == 0 && dz == 0) || n.x < 0 || n.y < 0 || n.z < 0 ||
                            n.x > kMaxCell || n.y > kMaxCell || n.z > kMaxCell) {
                            continue;
                        }
                        match = std::min(match, searchCell(packCell(n.x, n.y, n.z), p));
                    }
                }
            }
        }
        if (match == kNoId) {
            match = static_cast<std::uint32_t>(welded.size());
            welded.push_back(positions[i]);
            next.push_back(table.push(key, match));
        }
        remap[i] = match;
    }
    return remap;
}

// Replicates the acceptance tests of OpenMesh's PolyConnectivity::add_face for one triangle, so
// that add_face is only called when it succeeds (it prints to omerr on failure, and that stream
// is global state we do not want to toggle). Returns a bit mask of corners that must move to
// another (duplicated) vertex; 0 = the face can be added as is.
unsigned rejectedCorners(const Topology::HalfEdgeMesh::Mesh& mesh,
                         const std::array<OpenMesh::VertexHandle, 3>& v) {
    unsigned bad = 0;
    // A vertex whose fan is already closed cannot take another face ("complex vertex").
    for (int k = 0; k < 3; ++k) {
        if (!mesh.is_boundary(v[k])) bad |= 1u << k;
    }
    // A half-edge that already has a face ("complex edge"): a third triangle on the edge or a
    // second one in the same direction. Moving either end point frees it; take the second one
    // unless the first is moving anyway.
    std::array<OpenMesh::HalfedgeHandle, 3> he;
    for (int k = 0; k < 3; ++k) {
        const int k1 = (k + 1) % 3;
        he[k] = mesh.find_halfedge(v[k], v[k1]);
        if (he[k].is_valid() && !mesh.is_boundary(he[k]) && !(bad & (1u << k))) bad |= 1u << k1;
    }
    if (bad) return bad;
    // Both edges at a corner exist but are not consecutive around it: OpenMesh relinks the patch
    // in between into another boundary gap of that vertex, and fails if there is none.
    for (int k = 0; k < 3; ++k) {
        const int k1 = (k + 1) % 3;
        const OpenMesh::HalfedgeHandle innerPrev = he[k], innerNext = he[k1];
        if (!innerPrev.is_valid() || !innerNext.is_valid()) continue;
        if (mesh.next_halfedge_handle(innerPrev) == innerNext) continue;
        OpenMesh::HalfedgeHandle gap = mesh.opposite_halfedge_handle(innerNext);
        do {
            gap = mesh.opposite_halfedge_handle(mesh.next_halfedge_handle(gap));
        } while (!mesh.is_boundary(gap));
        if (gap == innerPrev) bad |= 1u << k1;
    }
    return bad;
}

struct EdgeArrays {
    std::vector<Edge> edges;
    std::vector<std::uint32_t> useOffsets;
    std::vector<EdgeUse> uses;
    std::vector<glm::uvec3> triangleEdges;
};

EdgeArrays buildEdges(std::span<const glm::uvec3> triangles, std::size_t vertexCount) {
    // Every directed triangle edge h = 3t + k (corner k -> k+1) is bucketed by its smaller vertex
    // (counting sort), then sorted by the larger one within the bucket. Buckets are vertex fans,
    // so these sorts are tiny; the result is edges in (v0, v1) order and uses in triangle order.
    const std::size_t halfEdges = 3 * triangles.size();
    std::vector<std::uint32_t> bucketStart(vertexCount + 1, 0);
    for (const glm::uvec3& tri : triangles) {
        for (int k = 0; k < 3; ++k)
            ++bucketStart[std::min(tri[k], tri[(k + 1) % 3]) + 1];
    }
    for (std::size_t v = 0; v < vertexCount; ++v)
        bucketStart[v + 1] += bucketStart[v];

    // (larger vertex << 32 | half-edge): sorting these orders by v1, then by triangle.
    std::vector<std::uint64_t> entries(halfEdges);
    {
        std::vector<std::uint32_t> fill(bucketStart.begin(), bucketStart.end() - 1);
        for (std::size_t t = 0; t < triangles.size(); ++t) {
            const glm::uvec3& tri = triangles[t];
            for (int k = 0; k < 3; ++k) {
                const std::uint32_t a = tri[k], b = tri[(k + 1) % 3];
                entries[fill[std::min(a, b)]++] =
                    (static_cast<std::uint64_t>(std::max(a, b)) << 32) | (3 * t + k);
            }
        }
    }

    EdgeArrays out;
    out.edges.reserve(halfEdges / 2 + 1);
    out.useOffsets.reserve(halfEdges / 2 + 2);
    out.uses.resize(halfEdges);
    out.triangleEdges.assign(triangles.size(), glm::uvec3(0));
    for (std::size_t v0 = 0; v0 < vertexCount; ++v0) {
        const auto first = entries.begin() + bucketStart[v0];
        const auto last = entries.begin() + bucketStart[v0 + 1];
        if (last - first > 16) {
            std::sort(first, last);
        } else {
            // Insertion sort: buckets are usually a handful of entries.
            for (auto i = first + 1; i < last; ++i) {
                const std::uint64_t x = *i;
                auto j = i;
                for (; j > first && *(j - 1) > x; --j)
                    *j = *(j - 1);
                *j = x;
            }
        }
        for (auto i = first; i < last; ++i) {
            const auto v1 = static_cast<std::uint32_t>(*i >> 32);
            if (i == first || static_cast<std::uint32_t>(*(i - 1) >> 32) != v1) {
                out.useOffsets.push_back(static_cast<std::uint32_t>(i - entries.begin()));
                out.edges.push_back(Edge{static_cast<std::uint32_t>(v0), v1});
            }
            const auto h = static_cast<std::uint32_t>(*i);
            const std::uint32_t t = h / 3, k = h % 3;
            const auto edgeId = static_cast<std::uint32_t>(out.edges.size() - 1);
            out.triangleEdges[t][k] = edgeId;
            out.uses[i - entries.begin()] = EdgeUse{t, triangles[t][k] == v0 ? 1 : -1};
        }
    }
    out.useOffsets.push_back(static_cast<std::uint32_t>(halfEdges));
    return out;
}

// Returns the mesh and sets `nonManifoldVertices`.
std::unique_ptr<Topology::HalfEdgeMesh> buildHalfEdgeMesh(std::span<const glm::vec3> positions,
                                                          std::span<const glm::uvec3> triangles,
                                                          std::size_t& nonManifoldVertices) {
    // Every triangle is added. Corners OpenMesh rejects are retried on an existing duplicate of
    // the welded vertex (so that a second fan stays connected to itself), then on a fresh one
    // (a fresh corner only has new edges, so a face whose rejected corners are fresh always goes
    // in). The welded ids of rejected corners are the non-manifold vertices.
    constexpr std::size_t kDuplicatesTried = 4; // bounds the retries on pathological soups
    using HalfEdgeMesh = Topology::HalfEdgeMesh;
    auto result = std::make_unique<HalfEdgeMesh>();
    HalfEdgeMesh& hem = *result;
    HalfEdgeMesh::Mesh& om = hem.mesh;
    om.reserve(positions.size(), 3 * triangles.size() / 2, triangles.size());
    hem.weldedVertex.reserve(positions.size());
    for (std::size_t w = 0; w < positions.size(); ++w) {
        const glm::vec3& p = positions[w];
        om.add_vertex(HalfEdgeMesh::Mesh::Point(p.x, p.y, p.z));
        hem.weldedVertex.push_back(static_cast<std::uint32_t>(w));
    }
    hem.primaryVertices = positions.size();

    std::vector<std::uint32_t> firstDuplicate(positions.size(), kNoId); // chain heads
    std::vector<std::uint32_t> lastDuplicate(positions.size(), kNoId);  // chain tails
    std::vector<std::uint32_t> nextDuplicate;                           // per duplicate
    std::vector<bool> nonManifold(positions.size(), false);
    std::vector<std::uint32_t> corners(positions.size(), 0); // faces per OpenMesh vertex

    auto makeDuplicate = [&](std::uint32_t w) {
        const glm::vec3& p = positions[w];
        const OpenMesh::VertexHandle v = om.add_vertex(HalfEdgeMesh::Mesh::Point(p.x, p.y, p.z));
        hem.weldedVertex.push_back(w);
        corners.push_back(0);
        // Append at the end of the chain so that older duplicates are tried first.
        const auto d = static_cast<std::uint32_t>(v.idx());
        nextDuplicate.push_back(kNoId);
        if (firstDuplicate[w] == kNoId) {
            firstDuplicate[w] = d;
        } else {
            nextDuplicate[lastDuplicate[w] - hem.primaryVertices] = d;
        }
        lastDuplicate[w] = d;
        return v;
    };

    for (const glm::uvec3& tri : triangles) {
        std::array<OpenMesh::VertexHandle, 3> v;
        std::array<std::uint32_t, 3> candidate{}; // 0 = primary, i = i-th duplicate
        std::array<bool, 3> fresh{};
        for (int k = 0; k < 3; ++k)
            v[k] = OpenMesh::VertexHandle(static_cast<int>(tri[k]));
        for (unsigned bad = rejectedCorners(om, v); bad != 0; bad = rejectedCorners(om, v)) {
            for (int k = 0; k < 3; ++k) {
                if (!(bad & (1u << k))) continue;
                nonManifold[tri[k]] = true;
                // Next existing duplicate of this welded vertex, else a fresh one.
                std::uint32_t d = kNoId;
                if (candidate[k] < kDuplicatesTried) {
                    d = candidate[k] == 0 ? firstDuplicate[tri[k]]
                                          : nextDuplicate[static_cast<std::size_t>(v[k].idx()) -
                                                          hem.primaryVertices];
                }
                ++candidate[k];
                if (d == kNoId || fresh[k]) {
                    v[k] = makeDuplicate(tri[k]);
                    fresh[k] = true;
                } else {
                    v[k] = OpenMesh::VertexHandle(static_cast<int>(d));
                }
            }
        }
        OpenMesh::FaceHandle f = om.add_face(v[0], v[1], v[2]);
        if (!f.is_valid()) {
            // rejectedCorners() mirrors every check add_face makes, so this is not expected;
            // should an OpenMesh version check more, three fresh corners always go in (at the
            // cost of a message on omerr), which keeps face idx == triangle index.
            for (int k = 0; k < 3; ++k) {
                nonManifold[tri[k]] = true;
                v[k] = makeDuplicate(tri[k]);
            }
            f = om.add_face(v[0], v[1], v[2]);
        }
        for (int k = 0; k < 3; ++k)
            ++corners[static_cast<std::size_t>(v[k].idx())];
    }

    // A vertex OpenMesh did take may still join several fans: open fans meeting at a point are
    // kept as one vertex with several boundary gaps, and a fan closed while another was still
    // open drops out of the vertex's rotation. Both show when walking the rotation.
    for (const OpenMesh::VertexHandle v : om.vertices()) {
        const std::uint32_t expected = corners[static_cast<std::size_t>(v.idx())];
        if (expected == 0) continue;
        std::uint32_t faces = 0, gaps = 0;
        for (const OpenMesh::HalfedgeHandle h : om.voh_range(v)) {
            if (om.is_boundary(h)) {
                ++gaps;
            } else {
                ++faces;
            }
        }
        if (gaps > 1 || faces != expected) nonManifold[hem.welded(v)] = true;
    }
    nonManifoldVertices =
        static_cast<std::size_t>(std::count(nonManifold.begin(), nonManifold.end(), true));
    return result;
}

Manifoldness classify(const EdgeArrays& arrays, TopologyStats& stats) {
    for (std::size_t e = 0; e < arrays.edges.size(); ++e) {
        const std::uint32_t begin = arrays.useOffsets[e], end = arrays.useOffsets[e + 1];
        const std::uint32_t uses = end - begin;
        if (uses == 1) {
            ++stats.boundaryEdges;
        } else if (uses == 2) {
            if (arrays.uses[begin].sign == arrays.uses[begin + 1].sign) ++stats.inconsistentEdges;
        } else {
            ++stats.nonManifoldEdges;
        }
    }
    if (stats.nonManifoldEdges > 0 || stats.inconsistentEdges > 0 ||
        stats.nonManifoldVertices > 0) {
        return Manifoldness::NonManifold;
    } else if (stats.boundaryEdges > 0) {
        return Manifoldness::Open;
    } else {
        return Manifoldness::Closed; // also for no triangles at all: nothing is open
    }
}

} // namespace

Topology::Topology(const MeshData& mesh, float weldTolerance) {
    validate(mesh);
    mStats.inputVertices = mesh.positions.size();
    mStats.inputTriangles = mesh.triangles.size();

    // --- Weld. ---
    const Aabb bounds = mesh.bounds();
    const double diagonal =
        bounds.empty() ? 0.0 : glm::length(glm::dvec3(bounds.max) - glm::dvec3(bounds.min));
    std::vector<glm::vec3> weldedPositions;
    const std::vector<std::uint32_t> remap = weldPositions(
        mesh.positions, bounds, std::max(0.0, static_cast<double>(weldTolerance)) * diagonal,
        weldedPositions);

    // --- Drop degenerate triangles; keep only referenced welded vertices (in welded order). ---
    const double minCross = kDegenerateArea * diagonal * diagonal;
    mTriangles.reserve(mesh.triangles.size());
    mSourceTriangle.reserve(mesh.triangles.size());
    std::vector<std::uint32_t> used(weldedPositions.size(), kNoId);
    struct KeyHash {
        std::size_t operator()(const std::array<std::uint32_t, 3>& k) const {
            std::uint64_t h = k[0];
            h = h * 0x9E3779B97F4A7C15ull ^ k[1];
            h = h * 0x9E3779B97F4A7C15ull ^ k[2];
            return static_cast<std::size_t>(h ^ (h >> 29));
        }
    };
    std::unordered_set<std::array<std::uint32_t, 3>, KeyHash> seen;
    seen.reserve(mesh.triangles.size());
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
        const glm::uvec3 src = mesh.triangles[t];
        const glm::uvec3 tri(remap[src.x], remap[src.y], remap[src.z]);
        bool degenerate = tri.x == tri.y || tri.y == tri.z || tri.z == tri.x;
        if (!degenerate) {
            const glm::dvec3 a(weldedPositions[tri.x]);
            const glm::dvec3 n = glm::cross(glm::dvec3(weldedPositions[tri.y]) - a,
                                            glm::dvec3(weldedPositions[tri.z]) - a);
            degenerate = !(glm::length(n) > minCross);
        }
        if (degenerate) {
            ++mStats.degenerateTriangles;
            continue;
        }
        // An exact duplicate (the same welded corners in the same cyclic order) adds nothing to
        // the surface but would make its edges non-manifold and its silhouette edges count
        // twice (double wedges, double volume sides). The reversed twin (a two-sided sheet) is
        // kept.
        const int first = tri.x < tri.y ? (tri.x < tri.z ? 0 : 2) : (tri.y < tri.z ? 1 : 2);
        const std::array<std::uint32_t, 3> key{tri[first], tri[(first + 1) % 3],
                                               tri[(first + 2) % 3]};
        if (!seen.insert(key).second) {
            ++mStats.duplicateTriangles;
            continue;
        }
        for (int k = 0; k < 3; ++k)
            used[tri[k]] = 0;
        mTriangles.push_back(tri);
        mSourceTriangle.push_back(static_cast<std::uint32_t>(t));
    }
    mPositions.reserve(weldedPositions.size());
    for (std::size_t w = 0; w < weldedPositions.size(); ++w) {
        if (used[w] == kNoId) continue;
        used[w] = static_cast<std::uint32_t>(mPositions.size());
        mPositions.push_back(weldedPositions[w]);
    }
    for (glm::uvec3& tri : mTriangles)
        tri = glm::uvec3(used[tri.x], used[tri.y], used[tri.z]);
    mStats.vertices = mPositions.size();
    mStats.triangles = mTriangles.size();

    EdgeArrays arrays = buildEdges(mTriangles, mPositions.size());
    mStats.edges = arrays.edges.size();
    mHalfEdge = buildHalfEdgeMesh(mPositions, mTriangles, mStats.nonManifoldVertices);
    mManifoldness = classify(arrays, mStats);
    mEdges = std::move(arrays.edges);
    mEdgeUseOffsets = std::move(arrays.useOffsets);
    mEdgeUses = std::move(arrays.uses);
    mTriangleEdges = std::move(arrays.triangleEdges);
}

Topology::~Topology() = default;
Topology::Topology(Topology&&) noexcept = default;
Topology& Topology::operator=(Topology&&) noexcept = default;

} // namespace geometry
