// Silhouette groups, loops, volumes, wedges and bounds (geometry/shadow/Silhouette.h), checked against
// brute force on every kind of mesh: closed (sphere, cube, torus), open (box, quad), non-manifold
// (edge fan) and a real OpenArena level.
#include "geometry/TestMeshes.h"
#include "TestRandom.h"

#include <geometry/scene/GltfLoader.h>
#include <geometry/scene/Primitives.h>
#include <geometry/shadow/PotentialSilhouettes.h>
#include <geometry/shadow/ShadowVolume.h>
#include <geometry/shadow/Silhouette.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <map>
#include <numeric>
#include <optional>
#include <random>
#include <string>

namespace geometry {
namespace {

// --- Meshes --------------------------------------------------------------------------------------

using testmeshes::cube;
using testmeshes::edgeFan;

// Torus around the y axis: major radius R, minor radius r, outward counter-clockwise. Same
// layout as makeTorus, which computes in double: its coordinates differ in the last bits.
MeshData torusMesh(float major, float minor, int around, int tube) {
    MeshData mesh;
    constexpr float kTau = 6.2831853f;
    for (int i = 0; i < around; ++i) {
        const float a = kTau * static_cast<float>(i) / static_cast<float>(around);
        for (int j = 0; j < tube; ++j) {
            const float b = kTau * static_cast<float>(j) / static_cast<float>(tube);
            const float radial = major + minor * std::cos(b);
            mesh.positions.push_back(
                {radial * std::cos(a), minor * std::sin(b), radial * std::sin(a)});
        }
    }
    const auto id = [&](int i, int j) {
        return static_cast<std::uint32_t>((i % around) * tube + (j % tube));
    };
    for (int i = 0; i < around; ++i) {
        for (int j = 0; j < tube; ++j) {
            // Winding chosen so that normals point away from the tube's centre line.
            mesh.triangles.emplace_back(id(i, j), id(i, j + 1), id(i + 1, j + 1));
            mesh.triangles.emplace_back(id(i, j), id(i + 1, j + 1), id(i + 1, j));
        }
    }
    return mesh;
}

RectLight lightAt(const glm::vec3& center, float halfSize = 0.3f) {
    return testmeshes::squareLight(center, halfSize);
}

Aabb boxAround(const Topology& topo, float margin) {
    Aabb b;
    for (const glm::vec3& p : topo.positions())
        b.extend(p);
    b.min -= glm::vec3(margin);
    b.max += glm::vec3(margin);
    return b;
}

// Whether the wedge implementation has landed (Wedge.cpp was being written alongside): a real
// wedge of an edge well away from the light has facets.
bool wedgesAvailable() {
    WedgeArrays arrays;
    appendWedge({-1, 0, 0}, {1, 0, 0}, lightAt({0, 3, 0}), arrays);
    return arrays.wedges.size() == 1 && arrays.wedges[0].planeCount > 0;
}

// --- Brute force ---------------------------------------------------------------------------------

struct Reference {
    std::vector<std::int8_t> facing;      // classifyFacing
    std::vector<std::int8_t> orientation; // participation: +1, -1 or 0
    std::vector<std::int32_t> multiplicity;
};

Reference reference(const Topology& topo, const glm::vec3& light, bool oneSided) {
    Reference r;
    r.facing.resize(topo.triangles().size());
    classifyFacing(topo, light, r.facing);
    r.orientation = r.facing;
    if (oneSided) {
        for (std::int8_t& o : r.orientation)
            o = o > 0 ? 1 : 0;
    }
    r.multiplicity.assign(topo.edges().size(), 0);
    for (std::size_t e = 0; e < topo.edges().size(); ++e) {
        for (std::uint32_t u = topo.edgeUseOffsets()[e]; u < topo.edgeUseOffsets()[e + 1]; ++u) {
            const EdgeUse use = topo.edgeUses()[u];
            r.multiplicity[e] += use.sign * r.orientation[use.triangle];
        }
    }
    return r;
}

std::uint32_t findRoot(std::vector<std::uint32_t>& parent, std::uint32_t x) {
    while (parent[x] != x)
        x = parent[x] = parent[parent[x]];
    return x;
}

// The light-oriented corners of a SilhouetteFrame::triangles entry: (a, b, c), or (a, c, b)
// when it carries kTriangleFlipped.
std::array<glm::vec3, 3> referencedCap(const Topology& topo, std::uint32_t entry) {
    const glm::uvec3 tri = topo.triangles()[entry & ~kTriangleFlipped];
    const bool flip = (entry & kTriangleFlipped) != 0;
    const auto positions = topo.positions();
    return {positions[tri.x], positions[flip ? tri.z : tri.y], positions[flip ? tri.y : tri.z]};
}

// Checks every structural invariant of one frame against brute force; returns the number of
// silhouette edge copies (for the callers' expectations).
void checkFrame(const Topology& topo, const SilhouetteFrame& frame, const glm::vec3& light,
                bool oneSided, const SilhouetteSettings& settings, const std::string& what) {
    SCOPED_TRACE(what);
    const bool wedges = settings.buildWedges;
    const bool capVertices = settings.buildVolumes && settings.capVertices;
    const Reference ref = reference(topo, light, oneSided);
    const std::size_t triangleCount = topo.triangles().size();

    // Triangles: exactly the participating ones, each in one group.
    std::vector<int> groupOf(triangleCount, -1);
    std::size_t participating = 0;
    for (const std::int8_t o : ref.orientation)
        participating += o != 0;
    ASSERT_EQ(frame.triangles.size(), participating);
    std::uint32_t nextTriangle = 0, nextEdge = 0, nextLoop = 0, nextVolume = 0;
    for (std::size_t g = 0; g < frame.groups.size(); ++g) {
        const SilhouetteGroup& group = frame.groups[g];
        ASSERT_EQ(group.firstTriangle, nextTriangle);
        ASSERT_EQ(group.firstEdge, nextEdge);
        ASSERT_EQ(group.firstLoop, nextLoop);
        ASSERT_GT(group.triangleCount, 0u);
        nextTriangle += group.triangleCount;
        nextEdge += group.edgeCount;
        nextLoop += group.loopCount;
        for (std::uint32_t i = group.firstTriangle; i < nextTriangle; ++i) {
            const std::uint32_t t = frame.triangles[i] & ~kTriangleFlipped;
            ASSERT_LT(t, triangleCount);
            ASSERT_EQ(groupOf[t], -1) << "triangle " << t << " in two groups";
            ASSERT_NE(ref.orientation[t], 0) << "non-participating triangle " << t;
            // Flipped exactly when it takes part facing away (two-sided rule), in both modes.
            EXPECT_EQ((frame.triangles[i] & kTriangleFlipped) != 0, ref.orientation[t] < 0)
                << "triangle " << t;
            groupOf[t] = static_cast<int>(g);
        }
        if (settings.buildVolumes) {
            EXPECT_EQ(group.firstVolumeVertex, nextVolume);
            // Caps by reference (the default): the range holds the sides alone.
            const std::uint32_t capCount = capVertices ? 3 * group.triangleCount : 0;
            EXPECT_EQ(group.frontCapVertexCount, capCount);
            EXPECT_EQ(group.volumeVertexCount, 2 * capCount + 6 * group.edgeCount);
            nextVolume += group.volumeVertexCount;
        } else {
            EXPECT_EQ(group.volumeVertexCount, 0u);
        }
        if (wedges) {
            EXPECT_EQ(group.firstWedge, group.firstEdge);
        }
    }
    EXPECT_EQ(nextEdge, frame.edges.size());
    EXPECT_EQ(nextLoop, frame.loops.size());
    EXPECT_EQ(nextVolume, frame.volumeVertices.size());
    if (wedges) {
        EXPECT_EQ(frame.wedges.wedges.size(), frame.edges.size());
    }

    // Groups are exactly the components of participating triangles across m = 0 edges.
    std::vector<std::uint32_t> parent(triangleCount);
    std::iota(parent.begin(), parent.end(), 0u);
    for (std::size_t e = 0; e < topo.edges().size(); ++e) {
        if (ref.multiplicity[e] != 0) continue;
        std::uint32_t anchor = UINT32_MAX;
        for (std::uint32_t u = topo.edgeUseOffsets()[e]; u < topo.edgeUseOffsets()[e + 1]; ++u) {
            const std::uint32_t t = topo.edgeUses()[u].triangle;
            if (ref.orientation[t] == 0) continue;
            if (anchor == UINT32_MAX) {
                anchor = t;
            } else {
                parent[findRoot(parent, t)] = findRoot(parent, anchor);
            }
        }
    }
    std::map<std::uint32_t, int> rootToGroup;
    for (std::uint32_t t = 0; t < triangleCount; ++t) {
        if (ref.orientation[t] == 0) continue;
        const auto [it, inserted] = rootToGroup.emplace(findRoot(parent, t), groupOf[t]);
        ASSERT_EQ(it->second, groupOf[t]) << "triangle " << t << " split from its component";
    }
    ASSERT_EQ(rootToGroup.size(), frame.groups.size()) << "components merged into one group";

    // Per group: the silhouette edges are exactly the non-zero m_g, as many copies as |m_g|,
    // directed as the group's light-oriented triangles use them (m_g > 0: v0 -> v1).
    for (std::size_t g = 0; g < frame.groups.size(); ++g) {
        const SilhouetteGroup& group = frame.groups[g];
        std::map<std::uint32_t, std::int32_t> expected, actual;
        for (std::uint32_t i = group.firstTriangle; i < group.firstTriangle + group.triangleCount;
             ++i) {
            const std::uint32_t t = frame.triangles[i] & ~kTriangleFlipped;
            for (int k = 0; k < 3; ++k) {
                const std::uint32_t e = topo.triangleEdges()[t][k];
                const Edge edge = topo.edges()[e];
                const std::int32_t sign = topo.triangles()[t][k] == edge.v0 ? 1 : -1;
                expected[e] += sign * ref.orientation[t];
            }
        }
        std::map<std::uint32_t, int> out, in;
        for (std::uint32_t i = group.firstEdge; i < group.firstEdge + group.edgeCount; ++i) {
            const SilhouetteEdge se = frame.edges[i];
            const Edge edge = topo.edges()[se.edge];
            const bool forward = se.v0 == edge.v0 && se.v1 == edge.v1;
            ASSERT_TRUE(forward || (se.v0 == edge.v1 && se.v1 == edge.v0)) << "edge " << se.edge;
            actual[se.edge] += forward ? 1 : -1;
            ++out[se.v0];
            ++in[se.v1];
        }
        for (const auto& [e, m] : expected) {
            const auto it = actual.find(e);
            EXPECT_EQ(it == actual.end() ? 0 : it->second, m) << "group " << g << " edge " << e;
        }
        for (const auto& [e, m] : actual) {
            EXPECT_TRUE(expected.count(e)) << "edge " << e << " not on group " << g;
            // Manifold edges (at most two uses): a silhouette edge has exactly one light-oriented
            // neighbour in the group running along it, unless both of its triangles are in the
            // group and oriented the same way along it (|m_g| = 2, two copies). Non-manifold
            // edges are covered by the m_g equality above (the signed sum over all their uses).
            const std::uint32_t uses = topo.edgeUseOffsets()[e + 1] - topo.edgeUseOffsets()[e];
            if (uses > 2) continue;
            int along = 0, against = 0;
            for (std::uint32_t u = topo.edgeUseOffsets()[e]; u < topo.edgeUseOffsets()[e + 1];
                 ++u) {
                const EdgeUse use = topo.edgeUses()[u];
                if (groupOf[use.triangle] != static_cast<int>(g)) continue;
                const int dir = use.sign * ref.orientation[use.triangle];
                (dir * m > 0 ? along : against) += dir != 0;
            }
            EXPECT_EQ(against, 0) << "edge " << e;
            EXPECT_EQ(along, std::abs(m)) << "edge " << e;
        }
        EXPECT_EQ(in, out) << "unbalanced vertex in group " << g;

        // Loops of the group tile its edge range and close (none without chaining).
        if (settings.chainLoops) {
            std::uint32_t covered = 0;
            for (std::uint32_t l = group.firstLoop; l < group.firstLoop + group.loopCount; ++l) {
                const SilhouetteLoop loop = frame.loops[l];
                ASSERT_EQ(loop.firstEdge, group.firstEdge + covered);
                ASSERT_GT(loop.edgeCount, 0u);
                covered += loop.edgeCount;
                for (std::uint32_t i = 0; i < loop.edgeCount; ++i) {
                    const SilhouetteEdge& a = frame.edges[loop.firstEdge + i];
                    const SilhouetteEdge& b =
                        frame.edges[loop.firstEdge + (i + 1) % loop.edgeCount];
                    ASSERT_EQ(a.v1, b.v0) << "loop " << l << " breaks after edge " << i;
                }
            }
            EXPECT_EQ(covered, group.edgeCount);
        } else {
            EXPECT_EQ(group.loopCount, 0u);
            EXPECT_TRUE(frame.loops.empty());
        }

        // Front caps are light-oriented (as vertices, and as referenced triangles wound by their
        // flag), and the occluder bounds hold the group's triangles.
        for (std::uint32_t i = group.firstTriangle; i < group.firstTriangle + group.triangleCount;
             ++i) {
            const std::array<glm::vec3, 3> cap = referencedCap(topo, frame.triangles[i]);
            const glm::dvec3 a(cap[0]), b(cap[1]), c(cap[2]);
            EXPECT_GE(glm::dot(glm::cross(b - a, c - a), glm::dvec3(light) - a), 0.0);
        }
        if (capVertices) {
            for (std::uint32_t i = 0; i < group.frontCapVertexCount; i += 3) {
                const glm::dvec3 a(frame.volumeVertices[group.firstVolumeVertex + i]),
                    b(frame.volumeVertices[group.firstVolumeVertex + i + 1]),
                    c(frame.volumeVertices[group.firstVolumeVertex + i + 2]);
                EXPECT_GE(glm::dot(glm::cross(b - a, c - a), glm::dvec3(light) - a), 0.0);
            }
        }
        for (std::uint32_t i = group.firstTriangle; i < group.firstTriangle + group.triangleCount;
             ++i) {
            for (int k = 0; k < 3; ++k) {
                const glm::vec3 p =
                    topo.positions()[topo.triangles()[frame.triangles[i] & ~kTriangleFlipped][k]];
                EXPECT_TRUE(glm::all(glm::greaterThanEqual(p, group.occluderBounds.min)) &&
                            glm::all(glm::lessThanEqual(p, group.occluderBounds.max)));
            }
        }
    }
}

// --- Volumes -------------------------------------------------------------------------------------

// Every group's closed volume as vertices: the frame's own range when it holds the caps
// (capVertices), else the caps built from the referenced triangles as the GPU draws them (front:
// the triangle wound light-oriented; back: the same reversed at infinity), then the sides.
std::vector<glm::vec4> groupVolumeVertices(const Topology& topo, const SilhouetteFrame& frame,
                                           const glm::vec3& light) {
    std::vector<glm::vec4> out;
    for (const SilhouetteGroup& group : frame.groups) {
        const auto first = frame.volumeVertices.begin() + group.firstVolumeVertex;
        if (group.frontCapVertexCount == 0) {
            for (std::uint32_t i = group.firstTriangle;
                 i < group.firstTriangle + group.triangleCount; ++i) {
                const std::array<glm::vec3, 3> cap = referencedCap(topo, frame.triangles[i]);
                out.insert(out.end(), {glm::vec4(cap[0], 1.0f), glm::vec4(cap[1], 1.0f),
                                       glm::vec4(cap[2], 1.0f), glm::vec4(cap[0] - light, 0.0f),
                                       glm::vec4(cap[2] - light, 0.0f),
                                       glm::vec4(cap[1] - light, 0.0f)});
            }
        }
        out.insert(out.end(), first, first + group.volumeVertexCount);
    }
    return out;
}

// A homogeneous volume truncated at light + far * (x - light) for its w = 0 vertices: sides and
// back caps share those vertices, so the result is a closed finite polyhedron with the same
// winding number as the infinite one at every point closer than the truncation.
std::vector<glm::dvec3> truncate(const std::vector<glm::vec4>& vertices, const glm::vec3& light,
                                 double far) {
    std::vector<glm::dvec3> out;
    out.reserve(vertices.size());
    for (const glm::vec4& v : vertices) {
        out.push_back(v.w != 0.0f ? glm::dvec3(v) : glm::dvec3(light) + far * glm::dvec3(v));
    }
    return out;
}

// Winding number of the closed triangle soup at p by signed ray crossings (+1 leaving through an
// outward face); nullopt-like `ok = false` when the ray passes too close to an edge.
int winding(const std::vector<glm::dvec3>& tris, const glm::dvec3& p, const glm::dvec3& dir,
            bool& ok) {
    int count = 0;
    for (std::size_t i = 0; i < tris.size(); i += 3) {
        const glm::dvec3 e1 = tris[i + 1] - tris[i], e2 = tris[i + 2] - tris[i];
        const glm::dvec3 h = glm::cross(dir, e2);
        const double det = glm::dot(e1, h);
        const double scale = glm::length(e1) * glm::length(e2);
        if (std::abs(det) <= 1e-12 * scale) continue; // ray parallel to the face
        const glm::dvec3 s = p - tris[i];
        const double u = glm::dot(s, h) / det;
        const glm::dvec3 q = glm::cross(s, e1);
        const double v = glm::dot(dir, q) / det;
        const double t = glm::dot(e2, q) / det;
        constexpr double kTie = 1e-7;
        if (u < -kTie || v < -kTie || u + v > 1.0 + kTie || t < -kTie) continue;
        if (u < kTie || v < kTie || u + v > 1.0 - kTie || t < kTie) {
            ok = false;
            return 0;
        }
        count += glm::dot(glm::cross(e1, e2), dir) > 0.0 ? 1 : -1;
    }
    return count;
}

bool segmentHitsAnyTriangle(const Topology& topo, const glm::dvec3& p, const glm::dvec3& l,
                            bool& ok) {
    const glm::dvec3 dir = l - p;
    bool hit = false;
    for (const glm::uvec3& tri : topo.triangles()) {
        const glm::dvec3 a(topo.positions()[tri.x]), b(topo.positions()[tri.y]),
            c(topo.positions()[tri.z]);
        const glm::dvec3 e1 = b - a, e2 = c - a, h = glm::cross(dir, e2);
        const double det = glm::dot(e1, h);
        if (std::abs(det) <= 1e-12 * glm::length(e1) * glm::length(e2) * glm::length(dir))
            continue;
        const glm::dvec3 s = p - a, q = glm::cross(s, e1);
        const double u = glm::dot(s, h) / det, v = glm::dot(dir, q) / det,
                     t = glm::dot(e2, q) / det;
        constexpr double kTie = 1e-7;
        if (u < -kTie || v < -kTie || u + v > 1.0 + kTie || t < -kTie || t > 1.0 + kTie) continue;
        if (u < kTie || v < kTie || u + v > 1.0 - kTie || t < kTie || t > 1.0 - kTie) ok = false;
        hit = true;
    }
    return hit;
}

// The union of the group volumes against appendHardShadowVolume (two-sided) or the classic
// "is anything between P and the light" (one-sided closed), at random points of `box`.
void checkVolumes(const Topology& topo, const SilhouetteFrame& frame, const glm::vec3& light,
                  bool oneSided, const Aabb& box, int points, std::mt19937& rng,
                  const std::string& what) {
    SCOPED_TRACE(what);
    const double far = 1e3 * (glm::length(box.extent()) + glm::length(glm::dvec3(light)));
    const std::vector<glm::dvec3> groups =
        truncate(groupVolumeVertices(topo, frame, light), light, far);
    ShadowVolumeGeometry hard;
    appendHardShadowVolume(topo, light, hard);
    const std::vector<glm::dvec3> whole = truncate(hard.vertices, light, far);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    int checked = 0, shadowed = 0;
    for (int attempt = 0; checked < points && attempt < 10 * points; ++attempt) {
        const glm::dvec3 p = glm::dvec3(box.min) + glm::dvec3(unit(rng), unit(rng), unit(rng)) *
                                                       glm::dvec3(box.extent());
        bool ok = true;
        const int fromGroups = winding(groups, p, testutil::gaussianDirection(rng), ok);
        if (oneSided) {
            const bool hit = segmentHitsAnyTriangle(topo, p, glm::dvec3(light), ok);
            if (!ok) continue;
            EXPECT_EQ(fromGroups != 0, hit) << "P (" << p.x << ", " << p.y << ", " << p.z << ")";
            EXPECT_GE(fromGroups, 0);
            EXPECT_LE(fromGroups, 1);
            shadowed += hit;
        } else {
            const int fromHard = winding(whole, p, testutil::gaussianDirection(rng), ok);
            if (!ok) continue;
            EXPECT_EQ(fromGroups, fromHard) << "P (" << p.x << ", " << p.y << ", " << p.z << ")";
            shadowed += fromHard != 0;
        }
        ++checked;
    }
    EXPECT_EQ(checked, points);
    EXPECT_GT(shadowed, 0) << "no shadowed sample: the check proved nothing";
}

// Influence bounds are conservative: random points of the scene inside a group's wedge or volume
// lie inside its influence bounds.
int checkInfluence(const Topology& topo, const SilhouetteFrame& frame, const glm::vec3& light,
                   const Aabb& box, int points, std::mt19937& rng, bool wedges,
                   const std::string& what, bool requireInside = true) {
    SCOPED_TRACE(what);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    int inside = 0;
    for (int i = 0; i < points; ++i) {
        const glm::vec3 p = box.min + glm::vec3(unit(rng), unit(rng), unit(rng)) * box.extent();
        for (const SilhouetteGroup& group : frame.groups) {
            bool in = false;
            for (std::uint32_t k = 0; k < group.edgeCount && wedges && !in; ++k)
                in = wedgeContains(frame.wedges.wedges[group.firstWedge + k], p);
            if (!in) {
                // In the volume: the segment to the light centre crosses a group triangle.
                const glm::dvec3 dir = glm::dvec3(light) - glm::dvec3(p);
                for (std::uint32_t j = group.firstTriangle;
                     j < group.firstTriangle + group.triangleCount && !in; ++j) {
                    const glm::uvec3 tri = topo.triangles()[frame.triangles[j] & ~kTriangleFlipped];
                    const glm::dvec3 a(topo.positions()[tri.x]), e1 = glm::dvec3(
                        topo.positions()[tri.y]) - a, e2 = glm::dvec3(topo.positions()[tri.z]) - a;
                    const glm::dvec3 h = glm::cross(dir, e2), s = glm::dvec3(p) - a,
                                     q = glm::cross(s, e1);
                    const double det = glm::dot(e1, h);
                    if (det == 0.0) continue;
                    const double u = glm::dot(s, h) / det, v = glm::dot(dir, q) / det,
                                 t = glm::dot(e2, q) / det;
                    in = u >= 0 && v >= 0 && u + v <= 1 && t >= 0 && t <= 1;
                }
            }
            if (!in) continue;
            ++inside;
            const Aabb& b = group.influenceBounds;
            EXPECT_TRUE(glm::all(glm::greaterThanEqual(p, b.min)) &&
                        glm::all(glm::lessThanEqual(p, b.max)))
                << "P (" << p.x << ", " << p.y << ", " << p.z << ") outside the bounds";
        }
    }
    if (requireInside) {
        EXPECT_GT(inside, 0) << "no sample inside any region: the check proved nothing";
    }
    return inside;
}

struct Case {
    std::string name;
    MeshData mesh;
    glm::vec3 light;
};

void runFullCheck(const Case& c, const SilhouetteSettings& settings, std::mt19937& rng,
                  int volumePoints = 300) {
    const Topology topo(c.mesh);
    SilhouetteExtractor extractor(topo);
    const Aabb box = boxAround(topo, 3.0f);
    const RectLight light = lightAt(c.light);
    const SilhouetteFrame& frame = extractor.update(light, box, settings);
    // Every case here has the light outside the mesh.
    const bool oneSided =
        settings.oneSidedClosed && topo.manifoldness() == Manifoldness::Closed;
    EXPECT_EQ(frame.oneSided, oneSided) << c.name;
    EXPECT_FALSE(frame.lightInside) << c.name;
    checkFrame(topo, frame, c.light, oneSided, settings, c.name);
    if (settings.buildVolumes) checkVolumes(topo, frame, c.light, oneSided, box, volumePoints,
                                            rng, c.name);
    if (settings.buildVolumes || settings.buildWedges) {
        checkInfluence(topo, frame, c.light, box, 2000, rng, settings.buildWedges, c.name);
    }
}

std::vector<Case> smallCases() {
    std::vector<Case> cases;
    cases.push_back({"sphere", makeSphere({0, 0, 0}, 1.0f, 24), {0.7f, 4.0f, 0.4f}});
    cases.push_back({"cube corner", cube(), {3.0f, 4.0f, 2.5f}});
    cases.push_back({"cube above", cube(), {0.1f, 5.0f, -0.2f}});
    cases.push_back({"torus", torusMesh(2.0f, 0.5f, 32, 16), {0.0f, 10.0f, 0.0f}});
    cases.push_back({"open box", cube(3), {0.3f, 4.0f, 0.2f}});
    cases.push_back({"open box, side light", cube(3), {4.0f, 0.5f, 0.7f}});
    cases.push_back({"quad", makeQuad({0, 0, 0}, {1, 0, 0}, {0, 0, -1}), {0.3f, 3.0f, 0.2f}});
    cases.push_back({"fan of 3", edgeFan(3), {0.4f, 2.5f, 1.7f}});
    return cases;
}

std::uint32_t totalLoops(const SilhouetteFrame& frame) {
    return static_cast<std::uint32_t>(frame.loops.size());
}

// The union of the group volumes blocks exactly the points whose segment to the light centre
// crosses the mesh, whichever rule the frame was classified with. Returns how many of the checked
// points are blocked while lying outside the mesh's bounds (shadows cast on the rest of a scene).
int checkBlocking(const Topology& topo, const SilhouetteFrame& frame, const glm::vec3& light,
                  const Aabb& box, int points, std::mt19937& rng, const std::string& what) {
    SCOPED_TRACE(what);
    const double far = 1e3 * (glm::length(box.extent()) + glm::length(glm::dvec3(light)));
    const std::vector<glm::dvec3> volume =
        truncate(groupVolumeVertices(topo, frame, light), light, far);
    Aabb meshBounds;
    for (const glm::vec3& p : topo.positions())
        meshBounds.extend(p);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    int checked = 0, blockedOutside = 0, wrong = 0;
    for (int attempt = 0; checked < points && attempt < 10 * points; ++attempt) {
        const glm::dvec3 p = glm::dvec3(box.min) + glm::dvec3(unit(rng), unit(rng), unit(rng)) *
                                                       glm::dvec3(box.extent());
        bool ok = true;
        const int count = winding(volume, p, testutil::gaussianDirection(rng), ok);
        const bool hit = segmentHitsAnyTriangle(topo, p, glm::dvec3(light), ok);
        if (!ok) continue;
        ++checked;
        if ((count != 0) != hit) {
            if (++wrong <= 5) {
                ADD_FAILURE() << "P (" << p.x << ", " << p.y << ", " << p.z << "): count "
                              << count << ", segment to the light "
                              << (hit ? "blocked" : "free");
            }
        }
        const bool outside = glm::any(glm::lessThan(glm::vec3(p), meshBounds.min)) ||
                             glm::any(glm::greaterThan(glm::vec3(p), meshBounds.max));
        blockedOutside += hit && outside;
    }
    EXPECT_EQ(checked, points);
    EXPECT_EQ(wrong, 0) << "of " << checked << " points";
    return blockedOutside;
}

// A closed mesh with every triangle reversed (inside out: winding -1 inside).
MeshData insideOut(MeshData mesh) {
    for (glm::uvec3& t : mesh.triangles)
        std::swap(t.y, t.z);
    return mesh;
}

// --- Lean mode -----------------------------------------------------------------------------------

bool inBox(const Aabb& b, const glm::vec3& p) {
    return glm::all(glm::greaterThanEqual(p, b.min)) && glm::all(glm::lessThanEqual(p, b.max));
}

// Where the ray a + t d (t >= 0) leaves the box it starts in (t = 0 when it does not start in it).
double exitParameter(const glm::dvec3& a, const glm::dvec3& d, const Aabb& box) {
    double t = std::numeric_limits<double>::infinity();
    for (int k = 0; k < 3; ++k) {
        if (d[k] > 0.0) t = std::min(t, (double(box.max[k]) - a[k]) / d[k]);
        if (d[k] < 0.0) t = std::min(t, (double(box.min[k]) - a[k]) / d[k]);
    }
    return std::max(t, 0.0);
}

// Influence bounds hold the exact regions, whether or not the frame built them: random points
// a + t (a - y) of each group's exact wedges (a on a silhouette edge, y on the light) and volume
// (a on a group triangle, y the light centre) that lie in the scene box, with t spread over
// [0, 1e4] and half of them where the ray leaves the box (the extreme points), must lie in the
// group's influence bounds. Returns how many points were checked.
int checkExactInfluence(const Topology& topo, const SilhouetteFrame& frame, const RectLight& light,
                        const Aabb& box, int perGroup, std::mt19937& rng,
                        const std::string& what) {
    SCOPED_TRACE(what);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    const auto positions = topo.positions();
    int checked = 0, outside = 0;
    for (std::size_t g = 0; g < frame.groups.size(); ++g) {
        const SilhouetteGroup& group = frame.groups[g];
        // The occluder itself (t = 0), as far as it is in the scene.
        for (int i = 0; i < 8; ++i) {
            const glm::vec3 corner(i & 1 ? group.occluderBounds.max.x : group.occluderBounds.min.x,
                                   i & 2 ? group.occluderBounds.max.y : group.occluderBounds.min.y,
                                   i & 4 ? group.occluderBounds.max.z : group.occluderBounds.min.z);
            const glm::vec3 clamped = glm::clamp(corner, box.min, box.max);
            if (corner == clamped) {
                ++checked;
                EXPECT_TRUE(inBox(group.influenceBounds, corner)) << "group " << g;
            }
        }
        for (int i = 0; i < perGroup; ++i) {
            glm::dvec3 a, y;
            const bool wedge = group.edgeCount > 0 && i % 2 == 0;
            if (wedge) {
                const SilhouetteEdge& e = frame.edges[group.firstEdge + rng() % group.edgeCount];
                a = glm::mix(glm::dvec3(positions[e.v0]), glm::dvec3(positions[e.v1]), unit(rng));
                // Light corners and edges a quarter of the time each: where wedges are widest.
                double su = 2.0 * unit(rng) - 1.0, sv = 2.0 * unit(rng) - 1.0;
                if (i % 8 == 0) su = su < 0.0 ? -1.0 : 1.0;
                if (i % 4 == 0) sv = sv < 0.0 ? -1.0 : 1.0;
                y = glm::dvec3(light.center) + su * glm::dvec3(light.u) + sv * glm::dvec3(light.v);
            } else {
                const glm::uvec3 tri =
                    topo.triangles()[frame.triangles[group.firstTriangle +
                                                     rng() % group.triangleCount] &
                                     ~kTriangleFlipped];
                double u = unit(rng), v = unit(rng);
                if (u + v > 1.0) {
                    u = 1.0 - u;
                    v = 1.0 - v;
                }
                const glm::dvec3 p0(positions[tri.x]), p1(positions[tri.y]), p2(positions[tri.z]);
                a = p0 + u * (p1 - p0) + v * (p2 - p0);
                y = glm::dvec3(light.center);
            }
            const glm::dvec3 d = a - y;
            if (glm::length(d) == 0.0) continue;
            double t = i % 4 < 2 ? 1e-3 * std::pow(1e7, unit(rng)) : exitParameter(a, d, box);
            if (i % 4 >= 2) t *= 1.0 - 1e-6; // just inside the box (rounding)
            const glm::vec3 p(a + t * d);
            if (!inBox(box, p)) continue;
            ++checked;
            if (!inBox(group.influenceBounds, p) && ++outside <= 5) {
                ADD_FAILURE() << "group " << g << (wedge ? " wedge" : " volume") << " point ("
                              << p.x << ", " << p.y << ", " << p.z << ") outside ["
                              << group.influenceBounds.min.x << ", "
                              << group.influenceBounds.min.y << ", "
                              << group.influenceBounds.min.z << "] - ["
                              << group.influenceBounds.max.x << ", "
                              << group.influenceBounds.max.y << ", "
                              << group.influenceBounds.max.z << "]";
            }
        }
    }
    EXPECT_EQ(outside, 0) << "of " << checked << " points";
    return checked;
}

// The same groups (in the same order), triangles, edge copies and occluder bounds.
void expectSameGroups(const SilhouetteFrame& a, const SilhouetteFrame& b, const std::string& what) {
    SCOPED_TRACE(what);
    EXPECT_EQ(a.oneSided, b.oneSided);
    EXPECT_EQ(a.lightInside, b.lightInside);
    ASSERT_EQ(a.groups.size(), b.groups.size());
    ASSERT_EQ(a.triangles.size(), b.triangles.size());
    ASSERT_EQ(a.edges.size(), b.edges.size());
    const auto edgeKey = [](const SilhouetteEdge& e) {
        return std::array<std::uint32_t, 3>{e.edge, e.v0, e.v1};
    };
    for (std::size_t g = 0; g < a.groups.size(); ++g) {
        const SilhouetteGroup& ga = a.groups[g];
        const SilhouetteGroup& gb = b.groups[g];
        ASSERT_EQ(ga.firstTriangle, gb.firstTriangle);
        ASSERT_EQ(ga.triangleCount, gb.triangleCount);
        ASSERT_EQ(ga.firstEdge, gb.firstEdge);
        ASSERT_EQ(ga.edgeCount, gb.edgeCount);
        EXPECT_EQ(ga.occluderBounds.min, gb.occluderBounds.min);
        EXPECT_EQ(ga.occluderBounds.max, gb.occluderBounds.max);
        std::vector<std::uint32_t> ta(a.triangles.begin() + ga.firstTriangle,
                                      a.triangles.begin() + ga.firstTriangle + ga.triangleCount);
        std::vector<std::uint32_t> tb(b.triangles.begin() + gb.firstTriangle,
                                      b.triangles.begin() + gb.firstTriangle + gb.triangleCount);
        std::sort(ta.begin(), ta.end());
        std::sort(tb.begin(), tb.end());
        EXPECT_TRUE(ta == tb) << "group " << g << " triangles differ";
        std::vector<std::array<std::uint32_t, 3>> ea, eb;
        for (std::uint32_t i = 0; i < ga.edgeCount; ++i) {
            ea.push_back(edgeKey(a.edges[ga.firstEdge + i]));
            eb.push_back(edgeKey(b.edges[gb.firstEdge + i]));
        }
        std::sort(ea.begin(), ea.end());
        std::sort(eb.begin(), eb.end());
        EXPECT_TRUE(ea == eb) << "group " << g << " edges differ";
    }
}

// --- Tests ---------------------------------------------------------------------------------------

// A closed mesh around the light shadows everything outside it. The one-sided rule would keep
// only light-facing triangles, and from inside none of an outward mesh faces the light: nothing
// would be cast (V = 1 on a floor under a lamp's closed shade).
TEST(Silhouette, ClosedMeshAroundTheLightShadowsEverythingOutside) {
    struct InsideCase {
        std::string name;
        MeshData mesh;
        glm::vec3 light;
    };
    const std::vector<InsideCase> cases = {
        {"cube", cube(), {0.1f, 0.2f, -0.15f}},
        {"icosphere", makeIcosphere({0, 0, 0}, 1.0f, 3), {0.2f, -0.3f, 0.1f}},
        // Inside the tube: rays from the light leave the tube and enter it again across the
        // hole, so the volume needs the light-facing triangles too.
        {"torus tube", torusMesh(2.0f, 0.5f, 32, 16), {2.05f, 0.1f, 0.05f}},
        {"inside-out cube", insideOut(cube()), {0.1f, 0.2f, -0.15f}},
    };
    std::mt19937 rng(77);
    for (const InsideCase& c : cases) {
        SCOPED_TRACE(c.name);
        const Topology topo(c.mesh);
        ASSERT_EQ(topo.manifoldness(), Manifoldness::Closed);
        SilhouetteExtractor extractor(topo);
        const Aabb box = boxAround(topo, 3.0f);
        for (const bool capVertices : {false, true}) {
            const SilhouetteSettings settings{.capVertices = capVertices, .buildWedges = false};
            const SilhouetteFrame& frame = extractor.update(lightAt(c.light, 0.05f), box, settings);
            EXPECT_TRUE(frame.lightInside);
            EXPECT_FALSE(frame.oneSided);
            checkFrame(topo, frame, c.light, false, settings, c.name);
            // About 97% of the box lies outside the mesh's bounds, all of it in shadow.
            EXPECT_GT(checkBlocking(topo, frame, c.light, box, 300, rng, c.name), 200);
        }
        // A floor under the mesh: every point of it is in the volume (V = 0 under the lamp).
        const SilhouetteFrame& frame = extractor.update(lightAt(c.light, 0.05f), box, {});
        const double far = 1e4;
        const std::vector<glm::dvec3> volume =
            truncate(groupVolumeVertices(topo, frame, c.light), c.light, far);
        int lit = 0, checked = 0;
        for (int i = 0; i < 15; ++i) {
            for (int j = 0; j < 15; ++j) {
                const glm::dvec3 p(-3.0 + 6.0 * (i + 0.5) / 15.0, -2.5,
                                   -3.0 + 6.0 * (j + 0.5) / 15.0);
                bool ok = true;
                const int count = winding(volume, p, testutil::gaussianDirection(rng), ok);
                if (!ok) continue;
                ++checked;
                lit += count == 0;
            }
        }
        EXPECT_GT(checked, 200);
        EXPECT_EQ(lit, 0) << "floor points outside the volume";
    }
}

TEST(Silhouette, ClosedMeshKeepsTheOneSidedRuleWhileTheLightIsOutside) {
    std::mt19937 rng(78);
    const std::vector<std::pair<std::string, MeshData>> meshes = {
        {"cube", cube()},
        {"icosphere", makeIcosphere({0, 0, 0}, 1.0f, 3)},
        {"torus", torusMesh(2.0f, 0.5f, 32, 16)}};
    // Outside the bounds (the box test decides), and inside the bounds but outside the mesh (the
    // ray decides): the torus's hole, next to the icosphere within its box's corner.
    const std::vector<std::pair<int, glm::vec3>> lights = {
        {0, {3.0f, 4.0f, 2.5f}}, {1, {0.75f, 0.7f, 0.72f}}, {2, {0.3f, 0.2f, -0.1f}},
        {2, {0.1f, 3.0f, 0.2f}}};
    for (const auto& [index, l] : lights) {
        const auto& [name, mesh] = meshes[index];
        SCOPED_TRACE(name);
        const Topology topo(mesh);
        SilhouetteExtractor extractor(topo);
        const Aabb box = boxAround(topo, 3.0f);
        const SilhouetteSettings settings{.buildWedges = false};
        const SilhouetteFrame& frame = extractor.update(lightAt(l, 0.05f), box, settings);
        EXPECT_FALSE(frame.lightInside);
        EXPECT_TRUE(frame.oneSided);
        checkFrame(topo, frame, l, true, settings, name);
        EXPECT_GT(checkBlocking(topo, frame, l, box, 300, rng, name), 0);
    }
}

// A light centre exactly in a cube face's plane (x = 1: every coordinate exact in float). The
// classic rule takes the face's two triangles as facing the light; wedges-bitmask's potential
// silhouettes (flatTrianglesFace = false) leave them out: their volume is flat. Counted either
// way; the other four faces that the plane does not hold keep their orientation.
TEST(Silhouette, TrianglesWhosePlaneHoldsTheLightCentre) {
    const Topology topo(makeBox({0.5f, 0.0f, 0.0f}, {1.0f, 1.0f, 1.0f}));
    const glm::vec3 l(1.0f, 0.25f, 3.0f); // in the plane x = 1 of the face, outside the box
    const Aabb box = boxAround(topo, 3.0f);
    for (const bool face : {true, false}) {
        SCOPED_TRACE(face ? "facing" : "left out");
        SilhouetteExtractor extractor(topo);
        SilhouetteSettings settings = SilhouetteSettings::lean();
        settings.oneSidedClosed = false;
        settings.flatTrianglesFace = face;
        const SilhouetteFrame& frame = extractor.update(lightAt(l, 0.05f), box, settings);
        EXPECT_EQ(frame.flatTriangles, 2u);
        // Two-sided: every triangle takes part but those left out.
        EXPECT_EQ(frame.triangles.size(), face ? 12u : 10u);
    }
}

TEST(Silhouette, ContainmentEdgeCases) {
    const Aabb box{{-5.0f, -5.0f, -5.0f}, {5.0f, 5.0f, 5.0f}};
    // On the surface: too close to tell, treated as inside (two-sided, correct either way).
    {
        const Topology topo(cube());
        SilhouetteExtractor extractor(topo);
        const SilhouetteFrame& frame =
            extractor.update(lightAt({1.0f, 0.3f, 0.2f}, 0.05f), box, {.buildWedges = false});
        EXPECT_TRUE(frame.lightInside);
        EXPECT_FALSE(frame.oneSided);
        // Just outside, well clear of the rounding: outside again.
        extractor.update(lightAt({1.01f, 0.3f, 0.2f}, 0.05f), box, {.buildWedges = false});
        EXPECT_FALSE(extractor.frame().lightInside);
        EXPECT_TRUE(extractor.frame().oneSided);
    }
    // An inside-out mesh never takes the one-sided rule: from outside it, it would shadow
    // nothing inside it.
    {
        const Topology topo(insideOut(cube()));
        SilhouetteExtractor extractor(topo);
        const glm::vec3 l(3.0f, 4.0f, 2.5f);
        const SilhouetteSettings settings{.buildWedges = false};
        const SilhouetteFrame& frame = extractor.update(lightAt(l, 0.05f), box, settings);
        EXPECT_FALSE(frame.lightInside);
        EXPECT_FALSE(frame.oneSided);
        checkFrame(topo, frame, l, false, settings, "inside-out cube");
        std::mt19937 rng(79);
        checkBlocking(topo, frame, l, Aabb{{-1.5f, -1.5f, -1.5f}, {1.5f, 1.5f, 1.5f}}, 300, rng,
                      "inside-out cube");
    }
    // Two components, the light in one of them.
    {
        MeshData two = cube();
        const MeshData other = makeIcosphere({4.0f, 0.0f, 0.0f}, 1.0f, 2);
        const auto base = static_cast<std::uint32_t>(two.positions.size());
        two.positions.insert(two.positions.end(), other.positions.begin(), other.positions.end());
        for (const glm::uvec3& t : other.triangles)
            two.triangles.push_back(t + glm::uvec3(base));
        const Topology topo(two);
        ASSERT_EQ(topo.manifoldness(), Manifoldness::Closed);
        SilhouetteExtractor extractor(topo);
        const glm::vec3 inSphere(4.1f, 0.2f, -0.1f), between(2.5f, 0.2f, 0.1f);
        extractor.update(lightAt(inSphere, 0.05f), box, {.buildWedges = false});
        EXPECT_TRUE(extractor.frame().lightInside);
        std::mt19937 rng(80);
        checkBlocking(topo, extractor.frame(), inSphere, box, 200, rng, "light in the sphere");
        extractor.update(lightAt(between, 0.05f), box, {.buildWedges = false});
        EXPECT_FALSE(extractor.frame().lightInside);
        EXPECT_TRUE(extractor.frame().oneSided);
        // Same centre, other settings: the same answer (the containment is kept per centre).
        extractor.update(lightAt(between, 0.05f), box, {});
        EXPECT_FALSE(extractor.frame().lightInside);
        EXPECT_TRUE(extractor.frame().oneSided);
        // Open meshes never report it.
        const Topology open(cube(3));
        SilhouetteExtractor openExtractor(open);
        openExtractor.update(lightAt({0.1f, 0.2f, 0.3f}, 0.05f), box, {.buildWedges = false});
        EXPECT_FALSE(openExtractor.frame().lightInside);
        EXPECT_FALSE(openExtractor.frame().oneSided);
    }
}

TEST(Silhouette, ClosedSphereHasOneGroupOneLoop) {
    const Topology topo(makeSphere({0, 0, 0}, 1.0f, 32));
    ASSERT_EQ(topo.manifoldness(), Manifoldness::Closed);
    SilhouetteExtractor extractor(topo);
    for (const glm::vec3 l : {glm::vec3(0.3f, 4.0f, 0.2f), glm::vec3(-5.0f, 0.7f, 2.0f),
                              glm::vec3(1.5f, -1.2f, 1.1f)}) {
        const SilhouetteSettings settings{.buildWedges = false};
        const SilhouetteFrame& frame =
            extractor.update(lightAt(l), boxAround(topo, 2.0f), settings);
        ASSERT_EQ(frame.groups.size(), 1u);
        EXPECT_EQ(totalLoops(frame), 1u);
        EXPECT_GT(frame.edges.size(), 20u);
        checkFrame(topo, frame, l, true, settings, "sphere");
    }
}

TEST(Silhouette, CubeLoopsHaveSixOrFourEdges) {
    const Topology topo(cube());
    SilhouetteExtractor extractor(topo);
    const Aabb box = boxAround(topo, 3.0f);
    const SilhouetteFrame& corner =
        extractor.update(lightAt({3.0f, 4.0f, 2.5f}), box, {.buildWedges = false});
    ASSERT_EQ(corner.groups.size(), 1u);
    ASSERT_EQ(corner.loops.size(), 1u);
    EXPECT_EQ(corner.loops[0].edgeCount, 6u);
    EXPECT_EQ(corner.groups[0].triangleCount, 6u); // three faces
    const SilhouetteFrame& above =
        extractor.update(lightAt({0.1f, 5.0f, -0.2f}), box, {.buildWedges = false});
    ASSERT_EQ(above.groups.size(), 1u);
    ASSERT_EQ(above.loops.size(), 1u);
    EXPECT_EQ(above.loops[0].edgeCount, 4u);
    EXPECT_EQ(above.groups[0].triangleCount, 2u);
}

TEST(Silhouette, TorusFromAboveHasTwoLoops) {
    const Topology topo(torusMesh(2.0f, 0.5f, 48, 24));
    ASSERT_EQ(topo.manifoldness(), Manifoldness::Closed);
    SilhouetteExtractor extractor(topo);
    const SilhouetteSettings settings{.buildWedges = false};
    const SilhouetteFrame& frame =
        extractor.update(lightAt({0.0f, 10.0f, 0.0f}), boxAround(topo, 2.0f), settings);
    ASSERT_EQ(frame.groups.size(), 1u);
    EXPECT_EQ(frame.groups[0].loopCount, 2u);
    checkFrame(topo, frame, {0.0f, 10.0f, 0.0f}, true, settings, "torus");
}

TEST(Silhouette, QuadHasOneLoopOfFourEdges) {
    const Topology topo(makeQuad({0, 0, 0}, {1, 0, 0}, {0, 0, -1}));
    SilhouetteExtractor extractor(topo);
    for (const float y : {3.0f, -3.0f}) { // two-sided: from either side
        const glm::vec3 l(0.3f, y, 0.2f);
        const SilhouetteSettings settings{.buildWedges = false};
        const SilhouetteFrame& frame =
            extractor.update(lightAt(l), boxAround(topo, 3.0f), settings);
        ASSERT_EQ(frame.groups.size(), 1u);
        ASSERT_EQ(frame.loops.size(), 1u);
        EXPECT_EQ(frame.loops[0].edgeCount, 4u);
        checkFrame(topo, frame, l, false, settings, "quad");
    }
}

TEST(Silhouette, OpenBoxAndFanBalance) {
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> coord(-4.0f, 4.0f);
    for (const Case& c : {Case{"open box", cube(3), {}}, Case{"fan of 3", edgeFan(3), {}}}) {
        const Topology topo(c.mesh);
        ASSERT_NE(topo.manifoldness(), Manifoldness::Closed);
        SilhouetteExtractor extractor(topo);
        for (int trial = 0; trial < 40; ++trial) {
            const glm::vec3 l(coord(rng), coord(rng), coord(rng));
            // Alternate the cap modes: the flags must be right in both.
            const SilhouetteSettings settings{.capVertices = trial % 2 == 1, .buildWedges = false};
            const SilhouetteFrame& frame =
                extractor.update(lightAt(l), boxAround(topo, 3.0f), settings);
            checkFrame(topo, frame, l, false, settings, c.name);
            if (HasFatalFailure()) return;
        }
    }
}

TEST(Silhouette, GroupVolumesMatchHardVolume) {
    // Both cap modes: by reference (caps built from `triangles` and their flags, as the GPU
    // draws them) and as vertices.
    for (const bool capVertices : {false, true}) {
        SCOPED_TRACE(capVertices ? "caps as vertices" : "caps by reference");
        std::mt19937 rng(2024);
        for (const Case& c : smallCases())
            runFullCheck(c, {.capVertices = capVertices, .buildWedges = false}, rng);
        // Closed meshes with the two-sided rule too (both sides cast: counts up to 2).
        runFullCheck({"cube two-sided", cube(), {3.0f, 4.0f, 2.5f}},
                     {.oneSidedClosed = false, .capVertices = capVertices, .buildWedges = false},
                     rng);
        runFullCheck({"torus two-sided", torusMesh(2.0f, 0.5f, 24, 12), {1.0f, 3.0f, 0.5f}},
                     {.oneSidedClosed = false, .capVertices = capVertices, .buildWedges = false},
                     rng);
    }
}

TEST(Silhouette, WedgesFollowEdgesAndBoundsAreConservative) {
    ASSERT_TRUE(wedgesAvailable()) << "geometry/shadow/src/Wedge.cpp has not landed yet";
    std::mt19937 rng(99);
    for (const Case& c : smallCases()) {
        runFullCheck(c, {}, rng, 100);
        runFullCheck(c, {.capVertices = true}, rng, 50);
        // Light close to the occluder: wide penumbrae, the case that needs the box-edge crossings.
        Case close = c;
        close.light = 0.45f * c.light;
        runFullCheck(close, {}, rng, 100);
    }
}

// Lean mode: the same groups, triangles and directed edge copies as the full mode (its oracle),
// no loops, volumes or wedges, and conservative cone bounds, on every kind of small mesh.
TEST(Silhouette, LeanModeMatchesFullMode) {
    constexpr SilhouetteSettings lean = SilhouetteSettings::lean();
    static_assert(!lean.buildVolumes && !lean.buildWedges && !lean.chainLoops &&
                  lean.influenceBounds == InfluenceBoundsMode::OccluderCone);
    std::mt19937 rng(2027);
    for (const Case& c : smallCases()) {
        for (const float scale : {1.0f, 0.45f}) { // 0.45: light close, wide penumbrae
            const glm::vec3 l = scale * c.light;
            const Topology topo(c.mesh);
            const Aabb box = boxAround(topo, 3.0f);
            SilhouetteExtractor fullExtractor(topo), leanExtractor(topo);
            const SilhouetteFrame& full = fullExtractor.update(lightAt(l), box, {});
            const SilhouetteFrame& frame = leanExtractor.update(lightAt(l), box, lean);
            const bool oneSided = frame.oneSided;
            checkFrame(topo, frame, l, oneSided, lean, c.name);
            expectSameGroups(full, frame, c.name);
            EXPECT_TRUE(frame.loops.empty());
            EXPECT_TRUE(frame.volumeVertices.empty());
            EXPECT_TRUE(frame.wedges.wedges.empty());
            EXPECT_GT(checkExactInfluence(topo, frame, lightAt(l), box, 400, rng, c.name), 200);
            // The cone bounds hold the (tighter) bounds from the built wedges' rays.
            for (std::size_t g = 0; g < frame.groups.size(); ++g) {
                EXPECT_TRUE(inBox(frame.groups[g].influenceBounds,
                                  full.groups[g].influenceBounds.min) &&
                            inBox(frame.groups[g].influenceBounds,
                                  full.groups[g].influenceBounds.max))
                    << c.name << " group " << g;
            }
            if (HasFatalFailure()) return;
        }
    }
}

// Every mode combination with chaining off or cone bounds still builds correct volumes and
// wedges (side quads and wedges do not need loops), and cone bounds contain the built wedges.
TEST(Silhouette, UnchainedAndConeBoundsWithVolumesAndWedges) {
    ASSERT_TRUE(wedgesAvailable());
    std::mt19937 rng(2028);
    for (const Case& c : smallCases()) {
        runFullCheck(c, {.buildWedges = false, .chainLoops = false}, rng, 100);
        constexpr auto cone = InfluenceBoundsMode::OccluderCone;
        runFullCheck(c, {.chainLoops = false, .influenceBounds = cone}, rng, 100);
        runFullCheck(c, {.capVertices = true, .influenceBounds = cone}, rng, 50);
    }
}

// Cone bounds against random occluders, lights (near, inside and far from the occluders' boxes)
// and scene boxes that cut through the occluders: the case where clipping rays to the box alone
// would not be conservative.
TEST(Silhouette, ConeBoundsAreConservativeUnderClipping) {
    std::mt19937 rng(4242);
    std::uniform_real_distribution<float> coord(-2.0f, 2.0f), size(0.05f, 1.0f);
    int checked = 0, insideBuilt = 0;
    for (int trial = 0; trial < 60; ++trial) {
        MeshData mesh;
        const int triangleCount = 1 + static_cast<int>(rng() % 6);
        for (int i = 0; i < triangleCount; ++i) {
            const glm::vec3 base(coord(rng), coord(rng), coord(rng));
            for (int k = 0; k < 3; ++k) {
                const glm::vec3 offset(coord(rng), coord(rng), coord(rng));
                mesh.positions.push_back(base + 0.5f * offset);
            }
            const auto v = static_cast<std::uint32_t>(3 * i);
            mesh.triangles.emplace_back(v, v + 1, v + 2);
        }
        const Topology topo(mesh);
        RectLight light;
        light.center = {coord(rng), coord(rng), coord(rng)};
        if (trial % 3 == 0) light.center *= 3.0f;
        light.u = size(rng) * glm::normalize(glm::vec3(coord(rng), coord(rng), coord(rng)));
        const glm::vec3 other(coord(rng), coord(rng), coord(rng));
        light.v = size(rng) * glm::normalize(glm::cross(light.u, other));
        // Around one of the vertices, so that it cuts through the occluders.
        const glm::vec3 anchor = mesh.positions[rng() % mesh.positions.size()];
        Aabb box;
        box.extend(anchor - glm::abs(glm::vec3(coord(rng), coord(rng), coord(rng))));
        box.extend(anchor + glm::abs(glm::vec3(coord(rng), coord(rng), coord(rng))));
        SilhouetteExtractor extractor(topo);
        const std::string what = "trial " + std::to_string(trial);
        const SilhouetteFrame& frame = extractor.update(light, box, SilhouetteSettings::lean());
        checked += checkExactInfluence(topo, frame, light, box, 300, rng, what);
        for (const SilhouetteGroup& g : frame.groups) {
            if (g.influenceBounds.empty()) continue;
            EXPECT_TRUE(inBox(box, g.influenceBounds.min) && inBox(box, g.influenceBounds.max))
                << what << ": bounds beyond the scene";
        }
        // With the wedges built (float planes, pushed outward): random points inside them.
        SilhouetteSettings withWedges = SilhouetteSettings::lean();
        withWedges.buildWedges = true;
        withWedges.buildVolumes = true;
        const SilhouetteFrame& built = extractor.update(light, box, withWedges);
        if (!box.empty()) {
            insideBuilt +=
                checkInfluence(topo, built, light.center, box, 300, rng, true, what, false);
        }
        if (HasFatalFailure()) return;
    }
    EXPECT_GT(checked, 10000);
    EXPECT_GT(insideBuilt, 1000);
}

// oa_dm1 from ../shared and the box around it (boxAround, margin 0); a fatal failure when the
// level is missing.
void loadGameLevel(std::optional<Topology>& topo, Aabb& box) {
    const std::filesystem::path level =
        std::filesystem::path(PENUMBRA_SHARED_DIR) / "levels" / "oa_dm1.glb";
    ASSERT_TRUE(std::filesystem::exists(level))
        << "missing " << level << " (../shared must be beside the repo)";
    topo.emplace(loadGltf(level));
    box = boxAround(*topo, 0.0f);
}

TEST(Silhouette, LeanModeOnGameLevel) {
    std::optional<Topology> level;
    Aabb box;
    ASSERT_NO_FATAL_FAILURE(loadGameLevel(level, box));
    const Topology& topo = *level;
    const RectLight light = lightAt(box.center() + glm::vec3(0.37f, 2.1f, -0.23f), 0.5f);
    SilhouetteExtractor fullExtractor(topo), leanExtractor(topo);
    const SilhouetteFrame& full = fullExtractor.update(light, box, {});
    const SilhouetteFrame& frame = leanExtractor.update(light, box, SilhouetteSettings::lean());
    checkFrame(topo, frame, light.center, false, SilhouetteSettings::lean(), "oa_dm1 lean");
    expectSameGroups(full, frame, "oa_dm1");
    std::mt19937 rng(5);
    EXPECT_GT(checkExactInfluence(topo, frame, light, box, 40, rng, "oa_dm1"), 10000);
    // Per-frame upload: triangle ids, edges and per group its ranges and two boxes.
    const std::size_t bytes = 4 * frame.triangles.size() + 12 * frame.edges.size() +
                              64 * frame.groups.size();
    std::printf("[ level    ] oa_dm1 lean: %zu groups, %zu edges, %zu bytes per frame\n",
                frame.groups.size(), frame.edges.size(), bytes);
    EXPECT_LT(bytes, 2u << 20);
}

// Lights in the planes of triangles: the float classification leaves them to the exact test,
// which must agree with classifyFacing (checkFrame compares triangle by triangle).
TEST(Silhouette, LightInTrianglePlanes) {
    for (const bool lean : {false, true}) {
        const SilhouetteSettings settings =
            lean ? SilhouetteSettings::lean() : SilhouetteSettings{.buildWedges = false};
        for (const Case& c : {Case{"cube", cube(), {3.0f, 1.0f, 0.5f}},
                              Case{"cube edge line", cube(), {1.0f, 1.0f, 4.0f}},
                              Case{"open box", cube(3), {0.25f, 1.0f, 3.0f}},
                              Case{"quad", makeQuad({0, 0, 0}, {1, 0, 0}, {0, 0, -1}),
                                   {2.0f, 0.0f, 0.3f}}}) {
            const Topology topo(c.mesh);
            SilhouetteExtractor extractor(topo);
            const SilhouetteFrame& frame =
                extractor.update(lightAt(c.light), boxAround(topo, 3.0f), settings);
            checkFrame(topo, frame, c.light, frame.oneSided, settings, c.name);
        }
    }
}

TEST(Silhouette, ReusesAnUnchangedLight) {
    const Topology topo(torusMesh(2.0f, 0.5f, 24, 12));
    SilhouetteExtractor extractor(topo);
    const Aabb box = boxAround(topo, 2.0f);
    const SilhouetteSettings settings{.buildWedges = false};
    const SilhouetteFrame& first = extractor.update(lightAt({0.5f, 4.0f, 0.3f}), box, settings);
    EXPECT_FALSE(extractor.reused());
    const std::vector<SilhouetteEdge> edges = first.edges;
    const std::vector<glm::vec4> volume = first.volumeVertices;
    const SilhouetteFrame& second = extractor.update(lightAt({0.5f, 4.0f, 0.3f}), box, settings);
    EXPECT_TRUE(extractor.reused());
    EXPECT_EQ(&first, &second);
    ASSERT_EQ(second.edges.size(), edges.size());
    for (std::size_t i = 0; i < edges.size(); ++i)
        EXPECT_EQ(second.edges[i].edge, edges[i].edge);
    EXPECT_TRUE(second.volumeVertices == volume);
    // A moved light, other bounds or other settings recompute.
    extractor.update(lightAt({0.5f, 4.0f, 0.31f}), box, settings);
    EXPECT_FALSE(extractor.reused());
    extractor.update(lightAt({0.5f, 4.0f, 0.31f}), boxAround(topo, 2.5f), settings);
    EXPECT_FALSE(extractor.reused());
    extractor.update(lightAt({0.5f, 4.0f, 0.31f}), boxAround(topo, 2.5f), {});
    EXPECT_FALSE(extractor.reused());
    extractor.update(lightAt({0.5f, 4.0f, 0.31f}), boxAround(topo, 2.5f), {.capVertices = true});
    EXPECT_FALSE(extractor.reused());
    extractor.update(lightAt({0.5f, 4.0f, 0.31f}), boxAround(topo, 2.5f),
                     {.capVertices = true, .chainLoops = false});
    EXPECT_FALSE(extractor.reused());
    extractor.update(lightAt({0.5f, 4.0f, 0.31f}), boxAround(topo, 2.5f),
                     {.capVertices = true,
                      .chainLoops = false,
                      .influenceBounds = InfluenceBoundsMode::OccluderCone});
    EXPECT_FALSE(extractor.reused());
    // Recomputing the first light gives the first result again (deterministic).
    const SilhouetteFrame& again = extractor.update(lightAt({0.5f, 4.0f, 0.3f}), box, settings);
    EXPECT_FALSE(extractor.reused());
    ASSERT_EQ(again.edges.size(), edges.size());
    for (std::size_t i = 0; i < edges.size(); ++i)
        EXPECT_EQ(again.edges[i].edge, edges[i].edge);
    EXPECT_TRUE(again.volumeVertices == volume);
}

TEST(Silhouette, GameLevel) {
    std::optional<Topology> level;
    Aabb box;
    ASSERT_NO_FATAL_FAILURE(loadGameLevel(level, box));
    const Topology& topo = *level;
    SilhouetteExtractor extractor(topo);
    const glm::vec3 l = box.center() + glm::vec3(0.37f, 2.1f, -0.23f);
    const bool wedges = wedgesAvailable();
    const SilhouetteSettings settings{.buildWedges = wedges};
    const SilhouetteFrame& frame = extractor.update(lightAt(l, 0.5f), box, settings);
    std::printf("[ level    ] oa_dm1 (%s): %zu triangles, %zu groups, %zu loops, %zu silhouette "
                "edges%s\n",
                toString(topo.manifoldness()), topo.triangles().size(), frame.groups.size(),
                frame.loops.size(), frame.edges.size(), wedges ? "" : " (no wedges yet)");
    checkFrame(topo, frame, l, false, settings, "oa_dm1");
    // The union of the group volumes is the hard volume: same caps (two-sided: every triangle
    // is some group's cap), and per edge the signed side copies of all groups add up to m_e (so
    // the stencil count is the same everywhere).
    ShadowVolumeGeometry hard;
    appendHardShadowVolume(topo, l, hard);
    EXPECT_EQ(hard.capTriangles, 2 * topo.triangles().size());
    EXPECT_EQ(frame.triangles.size(), topo.triangles().size());
    EXPECT_EQ(frame.volumeVertices.size(), 6 * frame.edges.size()); // caps by reference
    const Reference ref = reference(topo, l, false);
    std::vector<std::int32_t> net(topo.edges().size(), 0);
    for (const SilhouetteEdge& se : frame.edges)
        net[se.edge] += se.v0 == topo.edges()[se.edge].v0 ? 1 : -1;
    EXPECT_TRUE(net == ref.multiplicity);
    std::mt19937 rng(31);
    if (wedges) checkInfluence(topo, frame, l, box, 300, rng, true, "oa_dm1");
    // Caps as vertices: the same frame plus both caps of every triangle.
    const std::size_t sides = frame.volumeVertices.size();
    const SilhouetteSettings withCaps{.capVertices = true, .buildWedges = wedges};
    const SilhouetteFrame& capped = extractor.update(lightAt(l, 0.5f), box, withCaps);
    checkFrame(topo, capped, l, false, withCaps, "oa_dm1, caps as vertices");
    EXPECT_EQ(capped.volumeVertices.size(), 6 * topo.triangles().size() + sides);
}


// Potential silhouettes (wedges-bitmask): an edge between two triangles that lie exactly in one
// plane, on either side of it (a flat face's diagonal), is a silhouette from no point at all, so
// it is left out even where the face's plane straddles the light (data/stability/light-grazing's
// shelf, 4 mm under its light: two of those diagonals were full-screen wedges). Exactly: the
// same face bent by one float step out of its plane keeps its diagonal.
TEST(PotentialSilhouetteEdges, FlatFaceDiagonalsAreLeftOut) {
    RectLight light;
    light.center = {0.0f, 2.5f, -0.696f};
    light.u = {0.45f, 0.0f, 0.0f};
    light.v = {0.0f, 0.0f, 0.3f};
    const MeshData box = makeBox({-1.0f, 2.476f, -0.85f}, {2.0f, 0.04f, 0.3f});
    const Topology shelf(box);
    ASSERT_EQ(shelf.edges().size(), 18u); // 12 edges and 6 diagonals
    std::vector<PotentialEdge> edges;
    const PotentialEdgeStats s = potentialSilhouetteEdges(shelf, light, edges);
    EXPECT_EQ(s.interior + s.skipped, 18u);
    EXPECT_EQ(s.boundary + s.nonManifold, 0u);
    const auto positions = shelf.positions();
    int diagonals = 0;
    for (const PotentialEdge& e : edges) {
        // A box edge's end points differ in one coordinate, a diagonal's in two.
        const glm::vec3 d = positions[e.v1] - positions[e.v0];
        diagonals += (d.x != 0.0f) + (d.y != 0.0f) + (d.z != 0.0f) == 2;
    }
    EXPECT_EQ(diagonals, 0);
    // The box's straddled faces' diagonals were kept before: the front (z = -0.7) and the end
    // (x = 0) planes cut the light, and so do the four edges between them and the top and bottom.
    EXPECT_GE(s.skipped, 6u);
    EXPECT_GE(edges.size(), 5u);

    // The shelf's front face alone (a quad in the plane z = -0.7, which cuts the light): four
    // boundary edges; its diagonal left out, unless the face is bent by one float step.
    MeshData front;
    front.positions = {{-2.0f, 2.456f, -0.7f}, {0.0f, 2.456f, -0.7f}, {0.0f, 2.496f, -0.7f},
                       {-2.0f, 2.496f, -0.7f}};
    front.triangles = {{0, 1, 2}, {0, 2, 3}};
    const PotentialEdgeStats flat = potentialSilhouetteEdges(Topology(front), light, edges);
    EXPECT_EQ(flat.boundary, 4u);
    EXPECT_EQ(flat.interior, 0u);
    EXPECT_EQ(flat.skipped, 1u);
    EXPECT_EQ(edges.size(), 4u);
    front.positions[3].z = std::nextafter(-0.7f, 0.0f);
    const PotentialEdgeStats bent = potentialSilhouetteEdges(Topology(front), light, edges);
    EXPECT_EQ(bent.interior, 1u);
    EXPECT_EQ(bent.skipped, 0u);
    EXPECT_EQ(edges.size(), 5u);
}

// PotentialSilhouettes keeps what does not depend on the light (the side test's lengths, the
// third vertices, the flat diagonals found so far) from frame to frame: a light moved over a
// jagged sphere gives, frame after frame, what a fresh start gives for that light.
TEST(PotentialSilhouetteEdges, KeptStateMatchesAFreshStart) {
    MeshData sphere = makeIcosphere(glm::vec3(0.0f), 1.0f, 3);
    displaceRadially(sphere, glm::vec3(0.0f), 0.06f, 77u);
    const Topology topo(sphere);
    PotentialSilhouettes kept(topo);
    std::vector<PotentialEdge> a, b;
    std::size_t different = 0;
    for (int k = 0; k < 12; ++k) {
        const float angle = 0.5f * float(k);
        const RectLight light = testmeshes::squareLight(
            {3.0f * std::cos(angle), 2.0f + 0.3f * float(k), 3.0f * std::sin(angle)}, 0.2f + 0.1f * float(k));
        const PotentialEdgeStats s = kept.update(light, a);
        const PotentialEdgeStats f = potentialSilhouetteEdges(topo, light, b);
        ASSERT_EQ(a.size(), b.size()) << "light " << k;
        for (std::size_t i = 0; i < a.size(); ++i)
            different += a[i].v0 != b[i].v0 || a[i].v1 != b[i].v1 || a[i].apex[0] != b[i].apex[0] ||
                         a[i].apex[1] != b[i].apex[1];
        EXPECT_EQ(s.interior, f.interior);
        EXPECT_EQ(s.skipped, f.skipped);
        EXPECT_GT(s.skipped, 0u);  // the far side of the sphere
        EXPECT_GT(s.interior, 0u); // the band around the terminator
        EXPECT_NE(a.size(), 0u);
    }
    EXPECT_EQ(different, 0u);
}

// The side test's tolerance: a light corner exactly in a triangle's plane straddles it (its
// square-root branch, where the cheap bound cannot decide), so a ridge whose two faces keep the
// light on opposite sides is left out, and kept once a corner touches one face's plane.
TEST(PotentialSilhouetteEdges, ACornerInAFacesPlaneKeepsItsEdge) {
    MeshData roof;
    roof.positions = {{-1.0f, 0.0f, -1.0f}, {-1.0f, 0.0f, 1.0f}, {0.0f, 1.0f, 0.0f},
                      {1.0f, 0.0f, 0.0f}};
    // Faces (0, 1, 2), in the plane x - y = -1, and (1, 3, 2), in x + y + 2z = 1: a convex ridge
    // along 1 -> 2, consistently oriented; only that edge has two triangles.
    roof.triangles = {{0, 1, 2}, {1, 3, 2}};
    const Topology topo(roof);
    PotentialSilhouettes potential(topo);
    std::vector<PotentialEdge> edges;
    RectLight light = testmeshes::squareLight({0.2f, 3.0f, 0.1f}, 0.125f);
    const PotentialEdgeStats above = potential.update(light, edges);
    EXPECT_EQ(above.boundary, 4u);
    // The light wholly in front of both faces: the ridge is a silhouette from nowhere.
    EXPECT_EQ(above.skipped, 1u);
    EXPECT_EQ(edges.size(), 4u);
    // The corner of largest x on the first face's plane, the other three in front of it and the
    // whole light in front of the second face (coordinates exact in float).
    light.center = {0.375f, 1.5f, 0.125f};
    const glm::vec3 corner = light.center + light.u - light.v;
    ASSERT_EQ(corner.x - corner.y, -1.0f);
    const PotentialEdgeStats touching = potential.update(light, edges);
    EXPECT_EQ(touching.interior, 1u);
    EXPECT_EQ(touching.skipped, 0u);
    EXPECT_EQ(edges.size(), 5u);
}

} // namespace
} // namespace geometry
