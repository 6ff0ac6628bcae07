// Penumbra wedges for a rectangular light (Assarsson & Akenine-Möller 2003), built exactly.
//
// The visibility of a point P can change because of silhouette edge E = [e0, e1] exactly when,
// seen from P, E projects onto the light: when some segment P -> y (y on the light) crosses E.
// That region is
//     W(E) = { a + t (a - y) : a in E, y in L, t >= 0 } = E + cone{ e_i - c_j }
// (c_j the light's four corners): a convex, unbounded polyhedron. Its facets are the front and
// back planes through the edge tangent to the light, and at each end point the faces of the
// vertex's own pyramid v + cone{v - c_j} that face away from the edge: the side planes. Two
// wedges meeting at a loop vertex take their side planes from the same pyramid, so they share
// them (no crack between adjacent wedges; they overlap exactly in the pyramid, where both edges
// project onto the light).
//
// A wedge is GPU-ready: planes for the inside test, and its boundary as triangles with w = 0
// vertices at infinity (like shadow volumes) for rasterisation.
#pragma once

#include <geometry/core/LightFrame.h>
#include <geometry/core/Types.h>

#include <array>
#include <cstdint>
#include <vector>

namespace geometry {

inline constexpr int kMaxWedgePlanes = 12; // facets of E + cone: at most 6 + 6

enum WedgeFlags : std::uint32_t {
    kWedgeUnbounded = 1u << 0, // E touches the light: every point may be affected (no planes)
    kWedgeDegenerate = 1u << 1, // zero-length edge: influences nothing, not drawn
};

// std430-compatible layout (vec4s first, then scalars; 16-byte multiple).
struct Wedge {
    glm::vec4 planes[kMaxWedgePlanes]; // xyz unit outward normal, w = -dot(n, point on plane):
                                       // P is inside when dot(n, P) + w <= 0 for every plane
    glm::vec4 e0;                      // xyz edge start (w = 1)
    glm::vec4 e1;                      // xyz edge end (w = 1)
    std::uint32_t planeCount = 0;
    std::uint32_t flags = 0;
    std::uint32_t firstVertex = 0; // boundary triangles in WedgeArrays::vertices
    std::uint32_t vertexCount = 0;
};
static_assert(sizeof(Wedge) % 16 == 0, "Wedge must stay std430-friendly");

// Flat arrays, uploaded once per frame without conversion.
struct WedgeArrays {
    std::vector<Wedge> wedges;
    std::vector<glm::vec4> vertices; // boundary triangle lists, outward CCW; w = 0: a direction

    void clear() {
        wedges.clear();
        vertices.clear();
    }
};

// The extreme rays of a wedge's recession cone C = { x : dot(n_i, x) <= 0 } for its planes *as
// stored* (float normals, tilted outward for float safety: Wedge.cpp), as unit vectors: the
// directions in which wedgeContains lets the wedge reach infinity. C can be wider than the exact
// cone{e_i - c_j}; only the stored planes tell by how much. (Used for influence bounds.)
inline constexpr int kMaxWedgeRays = kMaxWedgePlanes * (kMaxWedgePlanes - 1) / 2;
struct WedgeRays {
    std::array<glm::vec3, kMaxWedgeRays> dirs;
    int count = 0; // -1: C is not pointed (holds a line) or is unresolved, or the wedge is
                   // unbounded: it may reach any point; 0 for a degenerate wedge
};

// Derives them from the stored planes of any wedge (O(p^2), O(p^3) when the planes are not in
// cyclic order or some are redundant). Returns rays.count.
int wedgeRecessionRays(const Wedge& wedge, WedgeRays& rays);

// Appends the wedge of edge [e0, e1] for `light` to `out` and returns its index.
// (A thin wrapper: WedgeBuilder(light).append(e0, e1, out). Per-edge callers with one light for
// many edges should hold a WedgeBuilder instead, which sets up the light's frame once.)
std::uint32_t appendWedge(const glm::vec3& e0, const glm::vec3& e1, const RectLight& light,
                          WedgeArrays& out);

// Builds the wedges of many edges for one light. The light's frame is set up once here, and
// edges in the common case (both end points on one side of the light's plane, every light corner
// seeing them at an elevation of at least ~1e-3 rad, the cone's extreme rays well apart) take a
// specialised path whose extreme rays are known combinatorially; every other edge, and every edge
// with Path::Exact, takes the general exact construction. Both paths give the same planes up to
// the float tolerance and the same float-safety guarantee (Wedge.cpp).
class WedgeBuilder {
public:
    enum class Path : std::uint32_t {
        Auto,  // fast path where it applies, the exact one elsewhere
        Exact, // always the general construction (reference and before/after comparisons)
    };

    explicit WedgeBuilder(const RectLight& light, Path path = Path::Auto);

    // Same contract as appendWedge.
    std::uint32_t append(const glm::vec3& e0, const glm::vec3& e1, WedgeArrays& out) const;
    // The same, also reporting the wedge's recession rays exactly as wedgeRecessionRays would
    // give them, but cheaper where the builder knows the planes' cyclic order (fast path).
    std::uint32_t append(const glm::vec3& e0, const glm::vec3& e1, WedgeArrays& out,
                         WedgeRays& rays) const;

    // Whether append(e0, e1, ...) takes the fast path (for tests and statistics; not cheap).
    bool takesFastPath(const glm::vec3& e0, const glm::vec3& e1) const;

    // The light's frame in double precision, with its corners.
    struct Frame : LightFrame {
        std::array<glm::dvec3, 4> corners; // cyclic: neighbours share a light edge
    };

private:
    Frame frame_;
    Path path_;
};

// Inside test with a tolerance (positive eps grows the wedge). Unbounded wedges contain every
// point, degenerate ones none.
bool wedgeContains(const Wedge& wedge, const glm::vec3& p, float eps = 0.0f);

// CPU model of the per-fragment wedge computation (DESIGN.md §4): project the directed edge
// e0 -> e1 from P onto the light's plane, and return the signed fraction of the light's area
// lying between the projected edge and the light centre's side (the region R of light points y
// whose segment from the centre crosses the projected edge). Summed over a silhouette loop,
//     V(P) = V_hard(P) - sum over edges of edgeCoverage(P, edge)
// where V_hard is the visibility of the light centre. Zero for P outside the wedge.
// The sign convention follows the loop orientation of geometry/shadow/Silhouette.h.
float edgeCoverage(const glm::vec3& p, const glm::vec3& e0, const glm::vec3& e1,
                   const RectLight& light);

} // namespace geometry
