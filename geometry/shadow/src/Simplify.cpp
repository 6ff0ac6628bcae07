// Simplified stand-ins (geometry/shadow/Simplify.h): weld with Topology, collapse half-edges on
// a copy of its OpenMesh mesh in quadric-error order, write back a MeshData.
//
// The collapse loop is our own rather than OpenMesh's decimater: the decimater asks every module
// for a verdict on each candidate whenever a neighbour changes (about 40 candidates a collapse),
// and the Hausdorff verdict costs as much as the removed points near the candidate, which grow as
// the mesh gets coarser (72 s for a 1M-triangle sphere). Here candidates wait in a heap with their
// quadric error only, and the expensive vetoes run once, when a candidate comes out on top.
//
// The Hausdorff bookkeeping: every removed vertex (its position and original normal) is kept with
// one triangle of the current mesh that is within the tolerance of it and within the normal
// deviation of its normal. A collapse v0 -> v1 moves the triangles around v0; it is legal only
// if every point kept by those triangles (and v0 itself) is covered so by one of the moved
// triangles and the moved triangles stay within the deviation of their kept corners' original
// normals; afterwards each point goes to the nearest moved triangle that covers it.
#include <geometry/shadow/Simplify.h>

#include <geometry/core/Error.h>
#include <geometry/scene/Scene.h>
#include <geometry/shadow/Topology.h>

#include "HalfEdgeMesh.h"

#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <queue>
#include <string>
#include <type_traits>
#include <vector>

namespace geometry {

// Named, not anonymous: the sanitizer build is a unity build, where every file's anonymous
// namespace is one (Silhouette.cpp has a kNone of its own).
namespace simplify_detail {

using Mesh = OpenMesh::TriMesh_ArrayKernelT<>;
constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();

// Below this a mesh has nothing worth removing (a box is 12).
constexpr std::size_t kMinTriangles = 8;

// Copies of a welded vertex whose unit normals differ by more than about 1.8 degrees make a
// crease: the kept vertex then has no normal of its own.
constexpr float kSameNormalDot = 0.9995f;

void checkOptions(const SimplifyOptions& o) {
    if (!std::isfinite(o.tolerance) || o.tolerance <= 0.0f)
        throw InputError("simplify: the tolerance must be a finite number > 0 (got " +
                         std::to_string(o.tolerance) + ")");
    if (!std::isfinite(o.maxNormalDeviationDeg) || o.maxNormalDeviationDeg <= 0.0f ||
        o.maxNormalDeviationDeg > 180.0f)
        throw InputError("simplify: the largest normal deviation must be in (0, 180] degrees (got " +
                         std::to_string(o.maxNormalDeviationDeg) + ")");
    if (!std::isfinite(o.maxNormalTurnDeg) || o.maxNormalTurnDeg <= 0.0f ||
        o.maxNormalTurnDeg >= 180.0f)
        throw InputError("simplify: the largest normal turn must be in (0, 180) degrees (got " +
                         std::to_string(o.maxNormalTurnDeg) + ")");
}

// One normal per welded vertex: the copies' common unit normal, or zero where they disagree or
// the mesh has none.
std::vector<glm::vec3> weldedNormals(const MeshData& mesh, const Topology& topo) {
    std::vector<glm::vec3> normal(topo.positions().size(), glm::vec3(0.0f));
    if (mesh.normals.empty()) return normal;
    std::vector<std::uint8_t> state(normal.size(), 0); // 0 unseen, 1 one normal, 2 crease
    for (std::size_t t = 0; t < topo.triangles().size(); ++t) {
        const glm::uvec3 w = topo.triangles()[t];
        const glm::uvec3 s = mesh.triangles[topo.sourceTriangle()[t]];
        for (int k = 0; k < 3; ++k) {
            const std::uint32_t v = w[k];
            if (state[v] == 2) continue;
            const glm::vec3 n = mesh.normals[s[k]];
            const float len = glm::length(n);
            if (!(len > 0.0f)) {
                state[v] = 2;
                normal[v] = glm::vec3(0.0f);
                continue;
            }
            const glm::vec3 u = n / len;
            if (state[v] == 0) {
                normal[v] = u;
                state[v] = 1;
            } else if (glm::dot(normal[v], u) < kSameNormalDot) {
                state[v] = 2;
                normal[v] = glm::vec3(0.0f);
            }
        }
    }
    return normal;
}


// Garland-Heckbert quadric: the sum of area-weighted squared distances to planes, as the 10
// coefficients of a symmetric 4x4 matrix.
struct Quadric {
    std::array<double, 10> q{};
    static Quadric plane(const glm::dvec3& n, double d, double weight) {
        Quadric r;
        r.q = {n.x * n.x, n.x * n.y, n.x * n.z, n.x * d, n.y * n.y,
               n.y * n.z, n.y * d,   n.z * n.z, n.z * d,   d * d};
        for (double& c : r.q) c *= weight;
        return r;
    }
    Quadric& operator+=(const Quadric& o) {
        for (int i = 0; i < 10; ++i) q[i] += o.q[i];
        return *this;
    }
    double operator()(const glm::dvec3& p) const {
        const double x = p.x, y = p.y, z = p.z;
        return q[0] * x * x + 2 * q[1] * x * y + 2 * q[2] * x * z + 2 * q[3] * x + q[4] * y * y +
               2 * q[5] * y * z + 2 * q[6] * y + q[7] * z * z + 2 * q[8] * z + q[9];
    }
};

glm::dvec3 at(const Mesh& m, Mesh::VertexHandle v) {
    const Mesh::Point& p = m.point(v);
    return {p[0], p[1], p[2]};
}

double pointTriangleDistanceSq(const glm::dvec3& p, const glm::dvec3& a, const glm::dvec3& b,
                               const glm::dvec3& c) {
    // Closest point by the triangle's Voronoi regions (vertex, edge, face).
    const glm::dvec3 ab = b - a, ac = c - a, ap = p - a;
    const double d1 = glm::dot(ab, ap), d2 = glm::dot(ac, ap);
    auto sq = [](const glm::dvec3& v) { return glm::dot(v, v); };
    if (d1 <= 0 && d2 <= 0) return sq(p - a);
    const glm::dvec3 bp = p - b;
    const double d3 = glm::dot(ab, bp), d4 = glm::dot(ac, bp);
    if (d3 >= 0 && d4 <= d3) return sq(bp);
    const double vc = d1 * d4 - d3 * d2;
    if (vc <= 0 && d1 >= 0 && d3 <= 0) return sq(p - (a + ab * (d1 / (d1 - d3))));
    const glm::dvec3 cp = p - c;
    const double d5 = glm::dot(ab, cp), d6 = glm::dot(ac, cp);
    if (d6 >= 0 && d5 <= d6) return sq(cp);
    const double vb = d5 * d2 - d1 * d6;
    if (vb <= 0 && d2 >= 0 && d6 <= 0) return sq(p - (a + ac * (d2 / (d2 - d6))));
    const double va = d3 * d6 - d5 * d4;
    if (va <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0)
        return sq(p - (b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)))));
    const double denom = 1.0 / (va + vb + vc);
    return sq(p - (a + ab * (vb * denom) + ac * (vc * denom)));
}

// The three corners of face f, with vertex `moved` (if a corner) placed at `to`.
std::array<glm::dvec3, 3> corners(const Mesh& m, Mesh::FaceHandle f, Mesh::VertexHandle moved,
                                  const glm::dvec3& to) {
    std::array<glm::dvec3, 3> c;
    int k = 0;
    for (const auto v : m.fv_range(f)) c[k++] = v == moved ? to : at(m, v);
    return c;
}

// A removed vertex: where it was and the original surface's normal there (area-weighted).
struct Removed {
    glm::dvec3 p;
    glm::dvec3 n;
};

// Collapses half-edges of `m` (statuses requested) cheapest first while every removed vertex
// stays within the tolerance of a triangle whose normal is within the deviation of its original
// normal, every kept vertex's triangles stay within the deviation of its original normal, and no
// triangle turns by more than the per-collapse angle.
void collapseWithin(Mesh& m, const SimplifyOptions& options) {
    const double tolSq = double(options.tolerance) * double(options.tolerance);
    constexpr double kPi = 3.14159265358979323846;
    const double cosTurn = std::cos(double(options.maxNormalTurnDeg) * kPi / 180.0);
    const double cosDeviation = std::cos(double(options.maxNormalDeviationDeg) * kPi / 180.0);

    std::vector<Quadric> quadric(m.n_vertices());
    std::vector<glm::dvec3> original(m.n_vertices(), glm::dvec3(0.0)); // area-weighted normals
    for (const auto f : m.faces()) {
        const auto c = corners(m, f, Mesh::VertexHandle(), {});
        const glm::dvec3 n2 = glm::cross(c[1] - c[0], c[2] - c[0]);
        const double len = glm::length(n2);
        if (!(len > 0.0)) continue;
        const glm::dvec3 n = n2 / len;
        const Quadric q = Quadric::plane(n, -glm::dot(n, c[0]), 0.5 * len);
        for (const auto v : m.fv_range(f)) {
            quadric[std::size_t(v.idx())] += q;
            original[std::size_t(v.idx())] += n2;
        }
    }
    for (glm::dvec3& n : original) {
        const double len = glm::length(n);
        n = len > 0.0 ? n / len : glm::dvec3(0.0);
    }
    // A normal within the deviation of `n` (a zero n, a vertex whose triangles cancel, accepts
    // nothing but is only reached on degenerate input: such collapses are then refused).
    auto closeNormal = [&](const glm::dvec3& face, const glm::dvec3& n) {
        return glm::dot(face, n) >= cosDeviation;
    };
    std::vector<std::vector<Removed>> kept(m.n_faces()); // removed vertices, per face
    std::vector<std::uint32_t> stamp(m.n_vertices(), 0); // bumped when a vertex's entry changes

    // One heap entry per vertex: the cost of its cheapest outgoing collapse. A vertex's entry is
    // replaced (its stamp bumped) whenever its fan changes.
    struct Entry {
        double cost;
        int vertex;
        std::uint32_t stamp;
        bool operator<(const Entry& o) const { return cost > o.cost; } // min-heap
    };
    std::priority_queue<Entry> heap;
    auto cost = [&](Mesh::HalfedgeHandle h) {
        const auto to = m.to_vertex_handle(h);
        Quadric q = quadric[std::size_t(m.from_vertex_handle(h).idx())];
        q += quadric[std::size_t(to.idx())];
        return q(at(m, to));
    };
    auto push = [&](Mesh::VertexHandle v) {
        double best = std::numeric_limits<double>::infinity();
        for (const auto h : m.voh_range(v)) best = std::min(best, cost(h));
        if (best < std::numeric_limits<double>::infinity())
            heap.push({best, v.idx(), ++stamp[std::size_t(v.idx())]});
    };
    for (const auto v : m.vertices()) push(v);

    std::vector<Removed> points;
    struct Moved {
        Mesh::FaceHandle face;
        std::array<glm::dvec3, 3> corners; // after the collapse
        glm::dvec3 normal;
    };
    std::vector<Moved> moved;
    std::vector<std::pair<double, Mesh::HalfedgeHandle>> choices;
    // Whether the point is within the tolerance of a moved triangle close to its normal.
    auto covered = [&](const Removed& r) {
        for (const Moved& f : moved)
            if (closeNormal(f.normal, r.n) &&
                pointTriangleDistanceSq(r.p, f.corners[0], f.corners[1], f.corners[2]) <= tolSq)
                return true;
        return false;
    };
    // Whether collapsing h (v0 -> v1) keeps every veto; on success `points` holds what the faces
    // around v0 kept, and v0.
    auto legal = [&](Mesh::HalfedgeHandle h) {
        if (!m.is_collapse_ok(h)) return false;
        const auto v0 = m.from_vertex_handle(h);
        const glm::dvec3 p0 = at(m, v0), p1 = at(m, m.to_vertex_handle(h));
        const auto fl = m.face_handle(h), fr = m.face_handle(m.opposite_halfedge_handle(h));
        // The triangles around v0 that survive, moved: none may flip, turn too far in one step,
        // vanish, or leave the original normals of its corners.
        moved.clear();
        for (const auto f : m.vf_range(v0)) {
            if (f == fl || f == fr) continue;
            const auto before = corners(m, f, v0, p0), after = corners(m, f, v0, p1);
            const glm::dvec3 nb = glm::cross(before[1] - before[0], before[2] - before[0]);
            const glm::dvec3 na = glm::cross(after[1] - after[0], after[2] - after[0]);
            const double lb = glm::length(nb), la = glm::length(na);
            if (!(la > 1e-12 * (1.0 + glm::dot(before[0], before[0]))) ||
                glm::dot(nb, na) < cosTurn * lb * la)
                return false;
            const glm::dvec3 n = na / la;
            for (const auto v : m.fv_range(f))
                if (v != v0 && !closeNormal(n, original[std::size_t(v.idx())])) return false;
            moved.push_back({f, after, n});
        }
        if (moved.empty()) return false;
        // Every point the faces around v0 keep, and v0: v0 first, then each face's farthest
        // point (kept at the front of its list), so that most vetoes stop after a few points.
        points.clear();
        points.push_back({p0, original[std::size_t(v0.idx())]});
        for (const auto f : m.vf_range(v0)) {
            const auto& k = kept[std::size_t(f.idx())];
            if (!k.empty()) points.push_back(k.front());
        }
        for (const auto f : m.vf_range(v0)) {
            const auto& k = kept[std::size_t(f.idx())];
            if (k.size() > 1) points.insert(points.end(), k.begin() + 1, k.end());
        }
        for (const Removed& r : points)
            if (!covered(r)) return false;
        return true;
    };

    while (!heap.empty()) {
        const Entry e = heap.top();
        heap.pop();
        const Mesh::VertexHandle v0(e.vertex);
        if (m.status(v0).deleted() || e.stamp != stamp[std::size_t(v0.idx())]) continue; // stale
        // Its collapses cheapest first; the first that keeps every veto is made.
        choices.clear();
        for (const auto h : m.voh_range(v0)) choices.emplace_back(cost(h), h);
        std::sort(choices.begin(), choices.end(),
                  [](const auto& a, const auto& b) { return a.first < b.first; });
        Mesh::HalfedgeHandle h;
        for (const auto& [c, candidate] : choices)
            if (legal(candidate)) {
                h = candidate;
                break;
            }
        if (!h.is_valid()) continue; // until a neighbour's collapse changes its fan
        const auto v1 = m.to_vertex_handle(h);
        for (const auto f : m.vf_range(v0)) kept[std::size_t(f.idx())].clear();
        m.collapse(h);
        quadric[std::size_t(v1.idx())] += quadric[std::size_t(v0.idx())];
        // Each point goes to the nearest moved triangle that covers it (one does: legal() said
        // so; the moved triangles are all around v1 now, with the corners `moved` holds).
        for (const Removed& r : points) {
            double best = std::numeric_limits<double>::infinity();
            const Moved* bestFace = nullptr;
            for (const Moved& f : moved) {
                if (!closeNormal(f.normal, r.n)) continue;
                const double d = pointTriangleDistanceSq(r.p, f.corners[0], f.corners[1], f.corners[2]);
                if (d < best) {
                    best = d;
                    bestFace = &f;
                }
            }
            if (bestFace == nullptr) continue; // cannot happen (legal() checked)
            auto& k = kept[std::size_t(bestFace->face.idx())];
            k.push_back(r);
            // The farthest point at the front.
            if (k.size() > 1) {
                const auto& t = bestFace->corners;
                if (best > pointTriangleDistanceSq(k.front().p, t[0], t[1], t[2]))
                    std::swap(k.front(), k.back());
            }
        }
        // Fresh entries for v1 (its quadric changed) and its neighbours (their fans changed: a
        // veto may now pass, and their costs moved).
        push(v1);
        for (const auto w : m.vv_range(v1)) push(w);
    }
}

} // namespace simplify_detail

SimplifiedMesh simplifyMesh(const MeshData& mesh, const SimplifyOptions& options) {
    simplify_detail::checkOptions(options);
    SimplifiedMesh out;
    if (!mesh.texcoords.empty() || !mesh.textures.empty()) {
        out.mesh = mesh;
        out.skipped = "textured (its texture coordinates would move)";
        return out;
    }
    if (mesh.materials.size() > 1) {
        out.mesh = mesh;
        out.skipped = "more than one material";
        return out;
    }
    if (mesh.triangles.size() < simplify_detail::kMinTriangles) {
        out.mesh = mesh;
        return out;
    }
    // Topology builds OpenMesh's mesh of the welded triangles (HalfEdgeMesh.h); for a manifold
    // mesh no vertex is duplicated (vertex idx == welded id, face idx == triangle), and a copy
    // of it is what the collapses work on.
    const Topology topo(mesh);
    const Topology::HalfEdgeMesh& hem = topo.halfEdgeMesh();
    if (topo.manifoldness() == Manifoldness::NonManifold ||
        hem.mesh.n_vertices() != hem.primaryVertices ||
        hem.mesh.n_faces() != topo.triangles().size()) {
        out.mesh = mesh;
        out.skipped = "non-manifold (OpenMesh cannot collapse it)";
        return out;
    }
    const std::vector<glm::vec3> normals = simplify_detail::weldedNormals(mesh, topo);
    using Mesh = simplify_detail::Mesh;
    static_assert(std::is_same_v<Mesh, Topology::HalfEdgeMesh::Mesh>);
    Mesh om = hem.mesh;
    OpenMesh::VPropHandleT<std::uint32_t> weldedId;
    om.add_property(weldedId);
    for (const auto v : om.vertices()) om.property(weldedId, v) = static_cast<std::uint32_t>(v.idx());
    om.request_vertex_status();
    om.request_edge_status();
    om.request_halfedge_status();
    om.request_face_status();
    simplify_detail::collapseWithin(om, options);
    om.garbage_collection();

    out.mesh.name = mesh.name;
    out.mesh.materials = mesh.materials;
    out.mesh.positions.reserve(om.n_vertices());
    for (const auto v : om.vertices()) {
        const Mesh::Point& p = om.point(v);
        out.mesh.positions.emplace_back(p[0], p[1], p[2]);
    }
    // Kept vertices keep their welded id in a property (garbage collection reorders them).
    if (!mesh.normals.empty()) {
        out.mesh.normals.reserve(out.mesh.positions.size());
        for (const auto v : om.vertices()) out.mesh.normals.push_back(normals[om.property(weldedId, v)]);
    }
    out.mesh.triangles.reserve(om.n_faces());
    for (const auto f : om.faces()) {
        glm::uvec3 t(simplify_detail::kNone);
        int k = 0;
        for (const auto v : om.fv_range(f)) {
            if (k < 3) t[k] = static_cast<std::uint32_t>(v.idx());
            ++k;
        }
        if (k != 3) throw std::logic_error("simplify: a face that is not a triangle");
        out.mesh.triangles.push_back(t);
    }
    if (!mesh.triangleMaterial.empty())
        out.mesh.triangleMaterial.assign(out.mesh.triangles.size(), mesh.triangleMaterial.front());
    return out;
}

SimplifyOptions simplifyOptionsFor(const Aabb& bounds, const RectLight& light, float visibilityError) {
    if (!std::isfinite(visibilityError) || visibilityError <= 0.0f || visibilityError >= 1.0f)
        throw InputError("simplify: the visibility error must be in (0, 1) (got " +
                         std::to_string(visibilityError) + ")");
    const float side = 2.0f * std::min(glm::length(light.u), glm::length(light.v));
    if (!(side > 0.0f) || !std::isfinite(side))
        throw InputError("simplify: the light has no area");
    SimplifyOptions o;
    o.tolerance = 0.5f * visibilityError * side;
    if (bounds.min.x > bounds.max.x) return o; // no vertices: nothing to bound
    // The mesh's farthest corner from the light's centre: the smallest angle the light subtends.
    float farthest = 0.0f;
    for (int i = 0; i < 8; ++i) {
        const glm::vec3 corner((i & 1) ? bounds.max.x : bounds.min.x,
                               (i & 2) ? bounds.max.y : bounds.min.y,
                               (i & 4) ? bounds.max.z : bounds.min.z);
        farthest = std::max(farthest, glm::length(corner - light.center));
    }
    const double alpha = 2.0 * std::atan(0.5 * double(side) / std::max(double(farthest), 1e-30));
    o.maxNormalDeviationDeg = static_cast<float>(std::clamp(
        double(visibilityError) * alpha * 180.0 / 3.14159265358979323846, 1e-6, 180.0));
    return o;
}

SimplifyStats simplifyScene(Scene& scene, float visibilityError) {
    SimplifyStats stats;
    for (SceneObject& object : scene.objects) {
        const SimplifyOptions options =
            simplifyOptionsFor(object.mesh.bounds(), scene.light, visibilityError);
        SimplifiedMesh s = simplifyMesh(object.mesh, options);
        if (!s.skipped.empty()) {
            ++stats.skipped;
            if (stats.firstSkipReason.empty()) stats.firstSkipReason = object.name + ": " + s.skipped;
            continue;
        }
        ++stats.meshes;
        stats.trianglesBefore += object.mesh.triangles.size();
        stats.trianglesAfter += s.mesh.triangles.size();
        object.mesh = std::move(s.mesh);
    }
    return stats;
}

} // namespace geometry
