// Penumbra wedges (geometry/shadow/Wedge.h): containment of every shadow ray through the edge, tightness
// against an independent brute force, the closed boundary mesh, the flags, and the per-edge
// coverage formula V = V_hard - Σ edgeCoverage against closed forms and dense light sampling.
#include <geometry/reference/Analytic.h>
#include <geometry/shadow/Wedge.h>

#include "geometry/BruteVisibility.h"
#include "geometry/WedgeCases.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <map>
#include <random>
#include <string>
#include <vector>

namespace {

using geometry::RectLight;
using geometry::Wedge;
using geometry::WedgeArrays;
using glm::dvec3;
using glm::vec3;

using testutil::Rng;
using namespace wedgecases; // randomLight, randomEdge, EdgeKind, TestEdge, frameOf, lightPoint

// Independent brute force (doubles, no tilt, no push): all 36 pairs of {d, e_i - c_j},
// kept when every direction is on the inner side. Signed margin > 0 means outside.
struct BrutePlanes {
    std::vector<dvec3> normals;
    std::vector<double> offsets; // plane: dot(n, x) - offset <= 0
    double margin(const dvec3& p) const {
        double m = -1e300;
        for (std::size_t i = 0; i < normals.size(); ++i)
            m = std::max(m, glm::dot(normals[i], p) - offsets[i]);
        return m;
    }
};

BrutePlanes brutePlanes(const vec3& e0f, const vec3& e1f, const RectLight& light) {
    const Frame f = frameOf(light);
    const dvec3 e0(e0f), e1(e1f);
    std::vector<dvec3> dirs = {glm::normalize(e1 - e0)};
    for (double s : {-1.0, 1.0})
        for (double t : {-1.0, 1.0})
            for (const dvec3& e : {e0, e1})
                dirs.push_back(glm::normalize(e - (f.c + s * f.u + t * f.v)));
    BrutePlanes out;
    for (std::size_t i = 0; i < dirs.size(); ++i) {
        for (std::size_t j = i + 1; j < dirs.size(); ++j) {
            dvec3 n = glm::cross(dirs[i], dirs[j]);
            if (glm::length(n) < 1e-6) continue;
            n = glm::normalize(n);
            double lo = 1, hi = -1;
            for (std::size_t k = 1; k < dirs.size(); ++k) {
                lo = std::min(lo, glm::dot(n, dirs[k]));
                hi = std::max(hi, glm::dot(n, dirs[k]));
            }
            if (hi > 1e-9) n = -n;
            if (hi > 1e-9 && lo < -1e-9) continue;
            out.normals.push_back(n);
            out.offsets.push_back(std::max(glm::dot(n, e0), glm::dot(n, e1)));
        }
    }
    return out;
}

// Does some shadow ray through the edge reach p? Samples points a on the edge and follows the
// line p -> a on to the light's plane: y must lie on the light, beyond a.
bool sampledRayReaches(const dvec3& p, const vec3& e0f, const vec3& e1f, const RectLight& light,
                       int samples) {
    const Frame f = frameOf(light);
    const dvec3 e0(e0f), e1(e1f);
    const dvec3 us = glm::cross(f.v, f.n) / glm::dot(f.u, glm::cross(f.v, f.n));
    const dvec3 vs = glm::cross(f.n, f.u) / glm::dot(f.v, glm::cross(f.n, f.u));
    const double hp = glm::dot(f.n, p - f.c);
    for (int i = 0; i <= samples; ++i) {
        const dvec3 a = e0 + (static_cast<double>(i) / samples) * (e1 - e0);
        const double ha = glm::dot(f.n, a - f.c);
        if (hp == ha) continue;
        const double sigma = hp / (hp - ha); // y = p + sigma (a - p)
        if (sigma < 1.0) continue;
        const dvec3 y = p + sigma * (a - p);
        if (std::abs(glm::dot(us, y - f.c)) <= 1.0 && std::abs(glm::dot(vs, y - f.c)) <= 1.0)
            return true;
    }
    return false;
}

// Exact segment-triangle tests and the midpoint grid of light points (BruteVisibility.h).
using testutil::gridVisibility;
using testutil::segmentHitsTriangle;

using Triangle = std::array<vec3, 3>;
struct DirectedEdge {
    vec3 v0, v1;
};

// Silhouette loop edges from the light centre, oriented as in Silhouette.h (occluder to the left
// of v0 -> v1 seen from the centre): keep the triangles facing the centre (two-sided ones are
// flipped first), and the directed edges whose reverse is not also used.
std::vector<DirectedEdge> silhouetteEdges(const std::vector<Triangle>& tris, const vec3& centre,
                                          bool twoSided) {
    std::vector<DirectedEdge> edges;
    for (Triangle t : tris) {
        const dvec3 a(t[0]), b(t[1]), c(t[2]);
        const double facing = glm::dot(glm::cross(b - a, c - a), dvec3(centre) - a);
        if (facing < 0.0) {
            if (!twoSided) continue;
            std::swap(t[1], t[2]);
        }
        for (int i = 0; i < 3; ++i) edges.push_back({t[i], t[(i + 1) % 3]});
    }
    std::vector<DirectedEdge> loop;
    for (const DirectedEdge& e : edges) {
        bool cancelled = false;
        for (const DirectedEdge& o : edges) cancelled |= (o.v0 == e.v1 && o.v1 == e.v0);
        if (!cancelled) loop.push_back(e);
    }
    return loop;
}

double formulaVisibility(const std::vector<DirectedEdge>& loop, const std::vector<Triangle>& tris,
                         const RectLight& light, const vec3& p) {
    bool centreBlocked = false;
    for (const Triangle& t : tris)
        centreBlocked |= segmentHitsTriangle(dvec3(p), dvec3(light.center), dvec3(t[0]),
                                             dvec3(t[1]), dvec3(t[2]));
    double v = centreBlocked ? 0.0 : 1.0;
    for (const DirectedEdge& e : loop) v -= geometry::edgeCoverage(p, e.v0, e.v1, light);
    return v;
}

std::vector<Triangle> quadTriangles(const vec3& c, const vec3& a, const vec3& b) {
    const vec3 p00 = c - a - b, p10 = c + a - b, p11 = c + a + b, p01 = c - a + b;
    return {{p00, p10, p11}, {p00, p11, p01}};
}

// Axis-aligned box, outward-facing (counter-clockwise from outside) triangles.
std::vector<Triangle> boxTriangles(const vec3& lo, const vec3& hi) {
    auto corner = [&](int i) {
        return vec3(i & 1 ? hi.x : lo.x, i & 2 ? hi.y : lo.y, i & 4 ? hi.z : lo.z);
    };
    const int faces[6][4] = {{0, 4, 6, 2}, {1, 3, 7, 5}, {0, 1, 5, 4},
                             {2, 6, 7, 3}, {0, 2, 3, 1}, {4, 5, 7, 6}};
    std::vector<Triangle> tris;
    for (const auto& q : faces) {
        tris.push_back({corner(q[0]), corner(q[1]), corner(q[2])});
        tris.push_back({corner(q[0]), corner(q[2]), corner(q[3])});
    }
    return tris;
}

std::string describe(const TestEdge& e, const RectLight& l) {
    char buf[512];
    std::snprintf(buf, sizeof buf,
                  "e0 (%.9g, %.9g, %.9g) e1 (%.9g, %.9g, %.9g) light c (%.9g, %.9g, %.9g) "
                  "u (%.9g, %.9g, %.9g) v (%.9g, %.9g, %.9g)",
                  e.e0.x, e.e0.y, e.e0.z, e.e1.x, e.e1.y, e.e1.z, l.center.x, l.center.y,
                  l.center.z, l.u.x, l.u.y, l.u.z, l.v.x, l.v.y, l.v.z);
    return buf;
}

const Wedge& build(WedgeArrays& arrays, const vec3& e0, const vec3& e1, const RectLight& light) {
    const std::uint32_t i = geometry::appendWedge(e0, e1, light, arrays);
    return arrays.wedges[i];
}

// Directed edges (a corner and the next, as float quadruples) of a wedge's boundary triangles,
// with how often each appears.
using DirectedEdges = std::map<std::array<float, 8>, int>;
DirectedEdges directedEdges(const WedgeArrays& arrays, const Wedge& w) {
    const glm::vec4* v = arrays.vertices.data() + w.firstVertex;
    DirectedEdges directed;
    for (std::uint32_t t = 0; t < w.vertexCount; t += 3) {
        for (int k = 0; k < 3; ++k) {
            const glm::vec4& a = v[t + k];
            const glm::vec4& b = v[t + (k + 1) % 3];
            ++directed[{a.x, a.y, a.z, a.w, b.x, b.y, b.z, b.w}];
        }
    }
    return directed;
}

// The same edge walked the other way.
std::array<float, 8> reversed(const std::array<float, 8>& key) {
    return {key[4], key[5], key[6], key[7], key[0], key[1], key[2], key[3]};
}

// Winding number of the boundary mesh around p, counted along the ray p + t dir: directions
// (w = 0) are lifted far out from `mid`, so the truncated surface stays closed (its cap is the
// far cap). 1 inside, 0 outside.
int meshWinding(const WedgeArrays& arrays, const Wedge& w, const dvec3& mid, double size,
                const dvec3& p, const dvec3& dir) {
    const glm::vec4* v = arrays.vertices.data() + w.firstVertex;
    auto lift = [&](const glm::vec4& q) {
        return q.w == 0.0f ? mid + 1e6 * size * dvec3(vec3(q)) : dvec3(vec3(q));
    };
    int winding = 0;
    for (std::uint32_t t = 0; t < w.vertexCount; t += 3) {
        const dvec3 a = lift(v[t]), b = lift(v[t + 1]), c = lift(v[t + 2]);
        if (segmentHitsTriangle(p, p + 1e9 * size * dir, a, b, c))
            winding += glm::dot(glm::cross(b - a, c - a), dir) > 0.0 ? 1 : -1;
    }
    return winding;
}

} // namespace

TEST(WedgeTest, LayoutIsGpuReady) {
    EXPECT_EQ(sizeof(Wedge) % 16, 0u);
    EXPECT_EQ(offsetof(Wedge, planeCount), sizeof(glm::vec4) * (geometry::kMaxWedgePlanes + 2));
}

TEST(WedgeTest, DegenerateAndUnboundedFlags) {
    RectLight light; // centre (0, 6, 0), half sizes 0.5
    WedgeArrays arrays;
    const Wedge zero = build(arrays, vec3(1, 2, 3), vec3(1, 2, 3), light);
    EXPECT_EQ(zero.flags, geometry::kWedgeDegenerate);
    EXPECT_EQ(zero.planeCount, 0u);
    EXPECT_EQ(zero.vertexCount, 0u);
    EXPECT_FALSE(geometry::wedgeContains(zero, vec3(1, 2, 3), 1.0f));

    // Crossing the light, ending on it, touching its border and its corner: unbounded.
    const std::array<std::array<vec3, 2>, 5> touching = {{
        {vec3(0.1f, 5.0f, 0.2f), vec3(-0.1f, 7.0f, 0.0f)},
        {vec3(0.1f, 6.0f, 0.2f), vec3(2.0f, 3.0f, 1.0f)},
        {vec3(0.5f, 6.0f, 0.0f), vec3(2.0f, 3.0f, 1.0f)},
        {vec3(0.5f, 6.0f, 0.5f), vec3(2.0f, 3.0f, 1.0f)},
        {vec3(-2.0f, 6.0f, 0.3f), vec3(2.0f, 6.0f, 0.3f)}, // in the plane, across the light
    }};
    for (const auto& e : touching) {
        const Wedge w = build(arrays, e[0], e[1], light);
        EXPECT_EQ(w.flags, geometry::kWedgeUnbounded);
        EXPECT_EQ(w.planeCount, 0u);
        EXPECT_EQ(w.vertexCount, 0u);
        EXPECT_TRUE(geometry::wedgeContains(w, vec3(100, -50, 7)));
    }
    // Crossing the light's plane beside the light, lying in it beside the light: bounded.
    const Wedge beside = build(arrays, vec3(2, 5, 0), vec3(2, 7, 0), light);
    EXPECT_EQ(beside.flags, 0u);
    EXPECT_GE(beside.planeCount, 3u);
    const Wedge inPlane = build(arrays, vec3(2, 6, -1), vec3(3, 6, 1), light);
    EXPECT_EQ(inPlane.flags, 0u);
    EXPECT_GE(inPlane.planeCount, 3u);
    // The flat wedge holds its in-plane shadow rays and nothing well above or below.
    EXPECT_TRUE(geometry::wedgeContains(inPlane, vec3(4, 6, 0), 0.0f));
    EXPECT_FALSE(geometry::wedgeContains(inPlane, vec3(4, 6.01f, 0), 0.0f));
    EXPECT_FALSE(geometry::wedgeContains(inPlane, vec3(4, 5.99f, 0), 0.0f));
}

// For random edges and lights, including every robust case, every point of every shadow ray
// through the edge (a + t (a - y), a on the edge, y on the light) lies in the float wedge, at
// t from 0 to 1e5 and where the ray meets a random receiver plane.
TEST(WedgeTest, ContainsEveryShadowRay) {
    Rng rng(20030611);
    WedgeArrays arrays;
    const std::array<double, 8> ts = {0.0, 1e-6, 1e-3, 0.1, 1.0, 10.0, 1e3, 1e5};
    int checked = 0, unbounded = 0;
    std::array<int, static_cast<int>(EdgeKind::Count)> perKind{};
    for (int c = 0; c < 4500; ++c) {
        const RectLight light = randomLight(rng);
        const auto kind = static_cast<EdgeKind>(c % static_cast<int>(EdgeKind::Count));
        const TestEdge edge = randomEdge(rng, light, kind);
        arrays.clear();
        const Wedge& w = build(arrays, edge.e0, edge.e1, light);
        ASSERT_LE(w.planeCount, static_cast<std::uint32_t>(geometry::kMaxWedgePlanes));
        ASSERT_EQ(w.flags & geometry::kWedgeDegenerate, 0u);
        if (kind == EdgeKind::Touching) {
            EXPECT_EQ(w.flags, geometry::kWedgeUnbounded);
        }
        if (w.flags & geometry::kWedgeUnbounded) {
            ++unbounded;
            continue;
        }
        ++perKind[static_cast<int>(kind)];
        const Frame f = frameOf(light);
        const dvec3 e0(edge.e0), e1(edge.e1);
        const dvec3 receiverN = rng.direction();
        const dvec3 receiverP = dvec3(edge.e0) + 3.0 * rng.direction();
        for (int li = 0; li < 13; ++li) {
            // Corners, edge midpoints-ish and interior points of the light.
            double s, t;
            if (li < 4) {
                s = li & 1 ? 1.0 : -1.0;
                t = li & 2 ? 1.0 : -1.0;
            } else if (li < 8) {
                s = li < 6 ? (li & 1 ? 1.0 : -1.0) : rng.uniform(-1, 1);
                t = li < 6 ? rng.uniform(-1, 1) : (li & 1 ? 1.0 : -1.0);
            } else {
                s = rng.uniform(-1, 1);
                t = rng.uniform(-1, 1);
            }
            const dvec3 y = f.c + s * f.u + t * f.v;
            for (int ai = 0; ai < 5; ++ai) {
                const double lambda = ai == 0 ? 0.0 : ai == 1 ? 1.0 : rng.uniform(0, 1);
                const dvec3 a = e0 + lambda * (e1 - e0);
                const dvec3 dir = a - y;
                for (double tt : ts) {
                    const vec3 hit(a + tt * dir);
                    ASSERT_TRUE(geometry::wedgeContains(w, hit, 0.0f))
                        << "kind " << static_cast<int>(kind) << " case " << c << " t " << tt
                        << " lambda " << lambda << " s " << s << " t " << t << "\n"
                        << describe(edge, light);
                    ++checked;
                }
                const double den = glm::dot(receiverN, dir);
                if (den != 0.0) {
                    const double sigma = glm::dot(receiverN, receiverP - a) / den;
                    if (sigma > 0.0 && sigma < 1e6) {
                        ASSERT_TRUE(geometry::wedgeContains(w, vec3(a + sigma * dir), 0.0f))
                            << "receiver, kind " << static_cast<int>(kind) << " case " << c;
                        ++checked;
                    }
                }
            }
        }
    }
    for (std::size_t k = 0; k + 1 < perKind.size(); ++k)
        EXPECT_GT(perKind[k], 100) << "edge kind " << k << " mostly unbounded";
    std::printf("[ wedge    ] %d shadow-ray points checked, %d unbounded wedges\n", checked,
                unbounded);
}

// Random points clearly outside the exact region (independent 36-pair brute force) are outside
// the wedge, get zero coverage and no sampled shadow ray; points clearly inside are inside and
// get a non-zero coverage. Points just outside each facet are outside.
TEST(WedgeTest, TightAndAgreesWithBruteForce) {
    Rng rng(42);
    WedgeArrays arrays;
    int outside = 0, inside = 0;
    for (int c = 0; c < 1500; ++c) {
        const RectLight light = randomLight(rng);
        const auto kind = static_cast<EdgeKind>(c % (static_cast<int>(EdgeKind::Count) - 1));
        if (kind == EdgeKind::NearlyInPlane) continue; // measure-zero region: nothing to sample
        const TestEdge edge = randomEdge(rng, light, kind);
        arrays.clear();
        const Wedge& w = build(arrays, edge.e0, edge.e1, light);
        if (w.flags != 0u) continue;
        const BrutePlanes brute = brutePlanes(edge.e0, edge.e1, light);
        ASSERT_FALSE(brute.normals.empty());
        const Frame f = frameOf(light);
        const dvec3 mid = 0.5 * (dvec3(edge.e0) + dvec3(edge.e1));
        const double size = glm::length(mid - f.c) + glm::length(f.u) + glm::length(f.v);
        for (int i = 0; i < 60; ++i) {
            const dvec3 p = mid + rng.uniform(0, 3) * size * rng.direction();
            const double m = brute.margin(p);
            if (m > 1e-3 * size) {
                ++outside;
                ASSERT_FALSE(geometry::wedgeContains(w, vec3(p), 0.0f)) << "case " << c;
                EXPECT_LE(std::abs(geometry::edgeCoverage(vec3(p), edge.e0, edge.e1, light)),
                          1e-7f);
                EXPECT_FALSE(sampledRayReaches(p, edge.e0, edge.e1, light, 400)) << "case " << c;
            } else if (m < -1e-3 * size) {
                ++inside;
                ASSERT_TRUE(geometry::wedgeContains(w, vec3(p), 0.0f)) << "case " << c;
                EXPECT_NE(geometry::edgeCoverage(vec3(p), edge.e0, edge.e1, light), 0.0f);
            }
        }
        // Just outside each facet, next to the edge: outside.
        for (std::uint32_t i = 0; i < w.planeCount; ++i) {
            const dvec3 n(vec3(w.planes[i]));
            for (const vec3& e : {edge.e0, edge.e1}) {
                const dvec3 onPlane = dvec3(e) - (glm::dot(n, dvec3(e)) + w.planes[i].w) * n;
                EXPECT_FALSE(geometry::wedgeContains(w, vec3(onPlane + 1e-3 * size * n), 0.0f));
            }
        }
    }
    EXPECT_GT(outside, 10000);
    EXPECT_GT(inside, 5000);
    std::printf("[ wedge    ] %d outside and %d inside points agree with the brute force\n",
                outside, inside);
}

// The boundary triangles form a closed, consistently oriented surface in projective space:
// every directed edge appears once with its reverse, and the winding number of the (truncated)
// surface around random points equals wedgeContains.
TEST(WedgeTest, BoundaryMeshIsClosed) {
    Rng rng(7);
    WedgeArrays arrays;
    int tested = 0;
    for (int c = 0; c < 1000; ++c) {
        const RectLight light = randomLight(rng);
        const auto kind = static_cast<EdgeKind>(c % (static_cast<int>(EdgeKind::Count) - 1));
        if (kind == EdgeKind::NearlyInPlane) continue; // (almost) no volume: nothing to test
        const TestEdge edge = randomEdge(rng, light, kind);
        arrays.clear();
        const Wedge& w = build(arrays, edge.e0, edge.e1, light);
        if (w.flags != 0u) continue;
        ASSERT_EQ(w.vertexCount % 3, 0u);
        ASSERT_GE(w.vertexCount, 12u);
        const DirectedEdges directed = directedEdges(arrays, w);
        for (const auto& [key, count] : directed) {
            ASSERT_EQ(count, 1) << "case " << c << "\n" << describe(edge, light);
            const std::array<float, 8> reverse = reversed(key);
            ASSERT_EQ(directed.count(reverse), 1u) << "case " << c << " kind "
                                                   << static_cast<int>(kind);
        }
        // Winding number (meshWinding: directions lifted far out from mid).
        const dvec3 mid = 0.5 * (dvec3(edge.e0) + dvec3(edge.e1));
        const Frame f = frameOf(light);
        const double size = glm::length(mid - f.c) + glm::length(f.u) + glm::length(f.v);
        const BrutePlanes brute = brutePlanes(edge.e0, edge.e1, light);
        for (int i = 0; i < 20; ++i) {
            const dvec3 p = mid + rng.uniform(0, 3) * size * rng.direction();
            if (std::abs(brute.margin(p)) < 1e-3 * size) continue;
            const dvec3 dir = rng.direction();
            const int winding = meshWinding(arrays, w, mid, size, p, dir);
            ASSERT_EQ(winding, geometry::wedgeContains(w, vec3(p)) ? 1 : 0) << "case " << c;
            ++tested;
        }
    }
    EXPECT_GT(tested, 5000);
}

// (1) A square occluder parallel to a square light: Σ formula equals the closed form, also with
// the light's frame mirrored (v -> -v), for receivers in and around the penumbra.
TEST(WedgeTest, CoverageMatchesParallelRectangles) {
    Rng rng(11);
    double worst = 0.0;
    for (int c = 0; c < 40; ++c) {
        RectLight light;
        light.center = vec3(rng.uniform(-1, 1), rng.uniform(5, 7), rng.uniform(-1, 1));
        light.u = vec3(rng.uniform(0.1, 1.0), 0, 0);
        light.v = vec3(0, 0, rng.uniform(0.1, 1.0));
        geometry::HorizontalRect rect{};
        rect.x0 = static_cast<float>(rng.uniform(-2, 0));
        rect.x1 = rect.x0 + static_cast<float>(rng.uniform(0.2, 2));
        rect.z0 = static_cast<float>(rng.uniform(-2, 0));
        rect.z1 = rect.z0 + static_cast<float>(rng.uniform(0.2, 2));
        rect.y = static_cast<float>(rng.uniform(1.5, 4.5));
        const vec3 centre(0.5f * (rect.x0 + rect.x1), rect.y, 0.5f * (rect.z0 + rect.z1));
        const std::vector<Triangle> tris =
            quadTriangles(centre, vec3(0.5f * (rect.x1 - rect.x0), 0, 0),
                          vec3(0, 0, 0.5f * (rect.z1 - rect.z0)));
        const std::vector<DirectedEdge> loop = silhouetteEdges(tris, light.center, true);
        ASSERT_EQ(loop.size(), 4u);
        RectLight mirrored = light;
        mirrored.v = -light.v;
        for (int i = 0; i < 200; ++i) {
            const vec3 p(rng.uniform(-5, 5), rng.uniform(0, rect.y - 0.05), rng.uniform(-5, 5));
            const double exact = geometry::visibilityParallelRects(light, {&rect, 1}, p);
            const double v = formulaVisibility(loop, tris, light, p);
            const double vm = formulaVisibility(loop, tris, mirrored, p);
            ASSERT_NEAR(v, exact, 1e-5) << "case " << c << " p " << p.x << " " << p.y << " "
                                        << p.z;
            ASSERT_NEAR(vm, exact, 1e-5);
            worst = std::max(worst, std::abs(v - exact));
        }
    }
    std::printf("[ wedge    ] parallel rectangles: max |V - exact| = %.3g\n", worst);
}

// (2) A tilted quad and a closed box against a 256 x 256 midpoint grid of light points with exact
// segment-triangle tests. Grid error bound: a straight boundary line crossing the light gives
// per column of width h = 2/256 an error of at most h/2 in length, so at most 256 h^2 / 2 = h in
// area, h/4 as a fraction of the light's area 4. The occluded region's boundary inside the light
// is the projection of the loop, so |error| <= edges * h / 4 (0.0078 for a quad, 0.0117 for a
// hexagonal box outline); observed errors are far smaller.
TEST(WedgeTest, CoverageMatchesGridForTiltedQuadAndBox) {
    Rng rng(5);
    const int grid = 256;
    const double h = 2.0 / grid;
    double worstQuad = 0.0, worstBox = 0.0;
    int penumbra = 0;
    for (int c = 0; c < 16; ++c) {
        RectLight light;
        light.center = vec3(0, 6, 0);
        light.u = vec3(rng.uniform(0.3, 1.0), 0, rng.uniform(-0.2, 0.2));
        light.v = vec3(rng.uniform(-0.3, 0.3), rng.uniform(-0.1, 0.1), rng.uniform(0.3, 1.0));
        const bool box = c % 2 == 1;
        // The formula with the silhouette from the centre is exact when every occluder face
        // faces all of the light alike (no face plane cuts the light); draw until that holds.
        std::vector<Triangle> tris;
        for (bool cuts = true; cuts;) {
            if (box) {
                const vec3 lo(rng.uniform(-3, 2), rng.uniform(1, 2), rng.uniform(-3, 2));
                tris = boxTriangles(lo, lo + vec3(rng.uniform(0.4, 3), rng.uniform(0.3, 1.5),
                                                  rng.uniform(0.4, 3)));
            } else {
                const dvec3 axis =
                    glm::normalize(dvec3(rng.uniform(-1, 1), 1.5, rng.uniform(-1, 1)));
                const dvec3 a = glm::normalize(glm::cross(axis, dvec3(1, 0, 0.3)));
                const dvec3 b = glm::cross(axis, a);
                tris = quadTriangles(
                    vec3(rng.uniform(-1, 1), rng.uniform(2, 3.5), rng.uniform(-1, 1)),
                    vec3(a * rng.uniform(0.3, 1.0)), vec3(b * rng.uniform(0.3, 1.0)));
            }
            cuts = false;
            for (const Triangle& t : tris) {
                const dvec3 n = glm::cross(dvec3(t[1] - t[0]), dvec3(t[2] - t[0]));
                int above = 0;
                for (int k = 0; k < 4; ++k) {
                    const vec3 y = light.point(k & 1 ? 1.0f : -1.0f, k & 2 ? 1.0f : -1.0f);
                    above += glm::dot(n, dvec3(y - t[0])) > 0.0 ? 1 : 0;
                }
                cuts |= above != 0 && above != 4;
            }
        }
        const std::vector<DirectedEdge> loop = silhouetteEdges(tris, light.center, !box);
        const double bound = static_cast<double>(loop.size()) * h / 4.0;
        for (int i = 0; i < 25; ++i) {
            // Receivers on the ground and, for the box, beside it (part of it beyond the
            // receiver's level: the clipping rule).
            const double y = box && i % 3 == 0 ? rng.uniform(1.0, 2.5) : rng.uniform(0.0, 0.9);
            vec3 p(rng.uniform(-4, 4), y, rng.uniform(-4, 4));
            int crossings = 0; // parity of a ray against the closed box: inside or not
            for (const Triangle& t : tris)
                crossings += segmentHitsTriangle(dvec3(p), dvec3(p) + dvec3(1e3, 1.2345, 0.3),
                                                 dvec3(t[0]), dvec3(t[1]), dvec3(t[2]));
            if (box && crossings % 2 == 1) continue; // inside the box
            const double v = formulaVisibility(loop, tris, light, p);
            const double ref = gridVisibility(tris, light, p, grid);
            if (ref > 0.0 && ref < 1.0) ++penumbra;
            ASSERT_NEAR(v, ref, bound) << (box ? "box" : "quad") << " case " << c << " p "
                                       << p.x << " " << p.y << " " << p.z;
            (box ? worstBox : worstQuad) = std::max(box ? worstBox : worstQuad, std::abs(v - ref));
        }
    }
    EXPECT_GT(penumbra, 15);
    std::printf("[ wedge    ] vs 256^2 grid: max error quad %.2g, box %.2g (bounds 0.0078 for 4 "
                "edges, 0.0117 for 6); %d penumbra points\n",
                worstQuad, worstBox, penumbra);
}

// The clipping rule: an edge entirely beyond the receiver's level, or beyond the light's plane,
// changes nothing; an edge crossing the receiver's level counts only its part between the
// receiver and the light (here compared with the pre-clipped edge).
TEST(WedgeTest, CoverageClipsToTheSlabBetweenPointAndLight) {
    RectLight light; // centre (0, 6, 0), half sizes 0.5
    const vec3 p(0.3f, 1.0f, 0.1f);
    EXPECT_EQ(geometry::edgeCoverage(p, vec3(-1, 0.5f, 0.2f), vec3(1, 0.2f, 0.2f), light), 0.0f);
    EXPECT_EQ(geometry::edgeCoverage(p, vec3(-1, 7.0f, 0.2f), vec3(1, 8.0f, 0.2f), light), 0.0f);
    EXPECT_EQ(geometry::edgeCoverage(p, vec3(-1, 1.0f, 0.2f), vec3(1, 1.0f, 0.2f), light), 0.0f);
    EXPECT_EQ(geometry::edgeCoverage(vec3(0, 6, 3), vec3(-1, 4, 0.2f), vec3(1, 4, 0.2f), light),
              0.0f);
    // Edge from below p's level up to 3: same as the part from p's level (y = 1) up.
    const vec3 a(0.1f, -1.0f, 0.6f), b(0.35f, 3.0f, 0.0f);
    const vec3 m = a + (b - a) * (2.0f / 4.0f); // y = 1
    const float full = geometry::edgeCoverage(p, a, b, light);
    const float clipped = geometry::edgeCoverage(p, m + (b - m) * 1e-6f, b, light);
    EXPECT_NE(full, 0.0f);
    EXPECT_NEAR(full, clipped, 1e-4f);
    // An edge crossing the light's plane: only the part below it counts.
    const vec3 c(0.2f, 4.0f, -0.8f), d(0.2f, 8.0f, 0.8f);
    EXPECT_NEAR(geometry::edgeCoverage(p, c, d, light),
                geometry::edgeCoverage(p, c, c + (d - c) * 0.5f, light), 1e-6f);
    // Reversing the edge flips the sign.
    EXPECT_FLOAT_EQ(geometry::edgeCoverage(p, b, a, light), -full);
}

namespace {

// A light with u, v along x and z (rectangular, axis-aligned) and an edge on a grid, parallel to
// x or z at one height, or vertical: the exact ties of the fast path's hull (coinciding support
// lines), frequent in game levels with axis-aligned architecture and lights.
std::pair<RectLight, TestEdge> axisAlignedCase(Rng& rng) {
    RectLight light;
    light.center = vec3(std::round(rng.uniform(-4, 4)), std::round(rng.uniform(4, 8)),
                        std::round(rng.uniform(-4, 4)));
    light.u = vec3(std::round(rng.uniform(1, 4)) * 0.25f, 0, 0);
    light.v = vec3(0, 0, std::round(rng.uniform(1, 4)) * 0.25f);
    if (rng.uniform(0, 1) < 0.5) std::swap(light.u, light.v); // normal -y: the other side
    const vec3 e0(std::round(rng.uniform(-8, 8)), std::round(rng.uniform(0, 3)),
                  std::round(rng.uniform(-8, 8)));
    vec3 dir(0.0f);
    dir[rng.uniform(0, 1) < 0.45 ? 0 : rng.uniform(0, 1) < 0.8 ? 2 : 1] = 1.0f;
    const float len = std::round(static_cast<float>(rng.uniform(1, 6)));
    return {light, {e0, e0 + len * dir, EdgeKind::ParallelToSide}};
}

// Every directed boundary edge appears once, with its reverse (BoundaryMeshIsClosed's criterion).
bool meshIsClosed(const WedgeArrays& arrays, const Wedge& w) {
    const DirectedEdges directed = directedEdges(arrays, w);
    for (const auto& [key, count] : directed) {
        if (count != 1 || directed.count(reversed(key)) != 1) return false;
    }
    return w.vertexCount >= 12 && w.vertexCount % 3 == 0;
}

// Signed distance-like margin of p for the float planes of a wedge, in double: > 0 outside.
double planeMargin(const Wedge& w, const dvec3& p) {
    double m = -1e300;
    for (std::uint32_t i = 0; i < w.planeCount; ++i)
        m = std::max(m, glm::dot(dvec3(vec3(w.planes[i])), p) + double(w.planes[i].w));
    return m;
}

} // namespace

// The common-case fast path against the exact general construction (WedgeBuilder::Path::Exact)
// on thousands of random edges that take it: random lights (half of them parallelograms) with
// generic, side-parallel, light-pointing, corner-pointing and short edges, and axis-aligned
// lights with grid-aligned edges (exact ties in the fast path's hull). Both tilt every exact
// facet normal by at most kMargin / kappa (4e-6 over the polar cone's margin, Wedge.cpp), and
// kappa >= min_i h_i / max |e_i - c_j| =: k for both tilt directions, so planes must agree within
// tolN = 2 * 4e-6 / k (+ float rounding) and offsets within tolN |anchor| plus the push; then
//   - each plane of one has a match in the other (the exact path repeats its bridges as front and
//     back planes, and the fast path may keep a collinear copy of a facet at a tie: sets, not
//     sequences, are compared);
//   - every sampled shadow-ray point is in both, and random points farther than the tolerance
//     band from the exact wedge's boundary are in both or in neither;
//   - the fast path's boundary mesh is closed, it never has more planes than the exact one, and
//     for both paths the mesh's winding number agrees with the planes off the band (the exact
//     path once built a wrong cone at such ties: loose planes, rescued by the tilt, and a mesh
//     that did not match them).
TEST(WedgeTest, FastPathMatchesExactPath) {
    Rng rng(314159);
    WedgeArrays exactArrays, fastArrays;
    const std::array<EdgeKind, 6> kinds = {EdgeKind::Generic,      EdgeKind::ParallelToSide,
                                           EdgeKind::TowardLight,  EdgeKind::TowardCorner,
                                           EdgeKind::Short,        EdgeKind::CloseToLight};
    std::array<int, 7> fastPerKind{}, totalPerKind{};
    int compared = 0, rayPoints = 0, agreeOutside = 0, agreeInside = 0, inBand = 0, windings = 0;
    double worstN = 0.0, worstNRel = 0.0;
    for (int c = 0; c < 8000; ++c) {
        RectLight light;
        TestEdge edge;
        int kindSlot;
        if (c % 4 == 3) {
            std::tie(light, edge) = axisAlignedCase(rng);
            kindSlot = 6;
        } else {
            light = randomLight(rng);
            kindSlot = static_cast<int>(rng.uniform(0, kinds.size()));
            edge = randomEdge(rng, light, kinds[kindSlot]);
        }
        ++totalPerKind[kindSlot];
        const geometry::WedgeBuilder exact(light, geometry::WedgeBuilder::Path::Exact);
        const geometry::WedgeBuilder fast(light);
        ASSERT_FALSE(exact.takesFastPath(edge.e0, edge.e1));
        if (!fast.takesFastPath(edge.e0, edge.e1)) continue;
        ++fastPerKind[kindSlot];
        exactArrays.clear();
        fastArrays.clear();
        const Wedge we = exactArrays.wedges[exact.append(edge.e0, edge.e1, exactArrays)];
        const Wedge wf = fastArrays.wedges[fast.append(edge.e0, edge.e1, fastArrays)];
        ASSERT_EQ(we.flags, 0u) << describe(edge, light);
        ASSERT_EQ(wf.flags, 0u);
        ASSERT_GE(wf.planeCount, 4u);
        ASSERT_LE(wf.planeCount, we.planeCount) << describe(edge, light);
        ASSERT_TRUE(meshIsClosed(fastArrays, wf)) << describe(edge, light);
        for (std::uint32_t i = wf.planeCount; i < geometry::kMaxWedgePlanes; ++i)
            ASSERT_EQ(wf.planes[i], glm::vec4(0.0f));

        // Tolerances from the tilt bound (see above).
        const Frame f = frameOf(light);
        const dvec3 e0(edge.e0), e1(edge.e1);
        double minH = 1e300, maxG = 0.0;
        for (const dvec3& e : {e0, e1}) {
            minH = std::min(minH, std::abs(glm::dot(f.n, e - f.c)));
            for (int k = 0; k < 4; ++k) {
                const dvec3 y = f.c + (k & 1 ? 1.0 : -1.0) * f.u + (k & 2 ? 1.0 : -1.0) * f.v;
                maxG = std::max(maxG, glm::length(e - y));
            }
        }
        const double tolN = 2.0 * 4e-6 / (minH / maxG) + 1e-6;
        const double reach = glm::length(e0) + glm::length(e1) + glm::length(e1 - e0);
        const double tolW = tolN * reach + 1e-5 * reach;
        auto matches = [&](const Wedge& a, const Wedge& b) {
            for (std::uint32_t i = 0; i < a.planeCount; ++i) {
                double best = 1e300;
                bool found = false;
                for (std::uint32_t j = 0; j < b.planeCount; ++j) {
                    const double dn = glm::length(dvec3(vec3(a.planes[i])) -
                                                  dvec3(vec3(b.planes[j])));
                    best = std::min(best, dn);
                    found |= dn <= tolN &&
                             std::abs(double(a.planes[i].w) - double(b.planes[j].w)) <= tolW;
                }
                worstN = std::max(worstN, best);
                worstNRel = std::max(worstNRel, best / tolN);
                if (!found) return false;
            }
            return true;
        };
        ASSERT_TRUE(matches(wf, we)) << "case " << c << "\n" << describe(edge, light);
        ASSERT_TRUE(matches(we, wf)) << "case " << c << "\n" << describe(edge, light);

        // Shadow-ray points (must be in both) and random points off the tolerance band.
        const dvec3 mid = 0.5 * (e0 + e1);
        const double size = glm::length(mid - f.c) + glm::length(f.u) + glm::length(f.v);
        for (int i = 0; i < 24; ++i) {
            const dvec3 y = f.c + rng.uniform(-1, 1) * f.u + rng.uniform(-1, 1) * f.v;
            const dvec3 a = e0 + rng.uniform(0, 1) * (e1 - e0);
            const vec3 p(a + std::pow(10.0, rng.uniform(-4, 2)) * (a - y));
            ASSERT_TRUE(geometry::wedgeContains(wf, p, 0.0f)) << "case " << c;
            ASSERT_TRUE(geometry::wedgeContains(we, p, 0.0f)) << "case " << c;
            ++rayPoints;
        }
        for (int i = 0; i < 40; ++i) {
            const vec3 p(mid + rng.uniform(0, 3) * size * rng.direction());
            const double m = planeMargin(we, dvec3(p));
            const double band = tolN * glm::length(dvec3(p) - mid) + 2.0 * tolW;
            if (std::abs(m) <= band) {
                ++inBand;
                continue;
            }
            const bool in = m < 0.0;
            ASSERT_EQ(geometry::wedgeContains(wf, p, 0.0f), in) << "case " << c;
            ++(in ? agreeInside : agreeOutside);
            if (i % 4 == 0) {
                const dvec3 dir = rng.direction();
                ASSERT_EQ(meshWinding(fastArrays, wf, mid, size, dvec3(p), dir), in ? 1 : 0)
                    << "fast, case " << c << "\n" << describe(edge, light);
                ASSERT_EQ(meshWinding(exactArrays, we, mid, size, dvec3(p), dir), in ? 1 : 0)
                    << "exact, case " << c << "\n" << describe(edge, light);
                ++windings;
            }
        }
        ++compared;
    }
    // The fast path must really be the common case, not a silent fallback: generic edges and
    // the axis-aligned level-like cases take it almost always.
    EXPECT_GT(fastPerKind[0], 0.95 * totalPerKind[0]);
    EXPECT_GT(fastPerKind[1], 0.8 * totalPerKind[1]);
    EXPECT_GT(fastPerKind[6], 0.95 * totalPerKind[6]);
    EXPECT_GT(compared, 4000);
    EXPECT_GT(agreeInside, 10000);
    EXPECT_GT(agreeOutside, 50000);
    std::printf("[ wedge    ] fast path on %d of 8000 edges (generic %d/%d, side-parallel %d/%d, "
                "toward light %d/%d, toward corner %d/%d, short %d/%d, close %d/%d, "
                "axis-aligned %d/%d)\n",
                compared, fastPerKind[0], totalPerKind[0], fastPerKind[1], totalPerKind[1],
                fastPerKind[2], totalPerKind[2], fastPerKind[3], totalPerKind[3], fastPerKind[4],
                totalPerKind[4], fastPerKind[5], totalPerKind[5], fastPerKind[6],
                totalPerKind[6]);
    std::printf("[ wedge    ] fast = exact: %d shadow-ray points in both, %d inside / %d outside "
                "agree, %d in the band, %d mesh windings match; worst normal gap %.2g (%.2g of "
                "its tolerance)\n",
                rayPoints, agreeInside, agreeOutside, inBand, windings, worstN, worstNRel);
}

// Regression: an axis-aligned light over an axis-aligned edge (as on every box and in game
// levels) once made the hull drop a real cone direction on a 1e-17 rounding tie, so the boundary
// mesh — what the GPU rasterises — missed part of the wedge. Every shadow-ray point must be
// inside the mesh, not only inside the planes.
TEST(WedgeTest, AxisAlignedTieKeepsEveryShadowRayInsideTheMesh) {
    RectLight light;
    light.center = {0.1f, 5.0f, -0.2f};
    light.u = {0.3f, 0.0f, 0.0f};
    light.v = {0.0f, 0.0f, 0.3f};
    const vec3 e0(1.0f, 1.0f, -1.0f), e1(-1.0f, 1.0f, -1.0f);
    WedgeArrays arrays;
    const Wedge& w = arrays.wedges[geometry::appendWedge(e0, e1, light, arrays)];
    ASSERT_EQ(w.flags, 0u);
    ASSERT_GT(w.vertexCount, 0u);
    const dvec3 mid = 0.5 * (dvec3(e0) + dvec3(e1));
    const double size = 10.0;
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> unit(-1.0f, 1.0f);
    int checked = 0;
    // Points strictly inside W: light samples and edge points kept off the light's and the
    // edge's ends, whose shadow rays are W's boundary (where a winding count is a tie).
    for (int i = 0; i < 2000; ++i) {
        const float s = 0.98f * unit(rng), t = 0.98f * unit(rng);
        const vec3 y = light.point(s, t);
        const float along = 0.5f + 0.49f * unit(rng);
        const vec3 a = glm::mix(e0, e1, along);
        for (const float k : {0.01f, 0.5f, 3.0f, 40.0f}) {
            const vec3 p = a + k * (a - y);
            ASSERT_TRUE(geometry::wedgeContains(w, p)) << "planes miss " << i;
            // Any ray direction works for the winding; avoid the mesh's symmetry axes.
            const dvec3 dir = glm::normalize(dvec3(0.31, 0.47, 0.83));
            ASSERT_EQ(meshWinding(arrays, w, mid, size, dvec3(p), dir), 1)
                << "mesh misses a shadow-ray point, sample " << i << " k " << k;
            ++checked;
        }
    }
    EXPECT_EQ(checked, 8000);
}

namespace {

// The recession rays WedgeBuilder reports with a wedge (the fast path derives them from its
// planes' cyclic order) are those wedgeRecessionRays derives from the stored planes, and each
// lies in the cone the stored planes bound (influence bounds rely on both).
TEST(WedgeTest, ReportedRaysAreThoseOfTheStoredPlanes) {
    Rng rng(4711);
    WedgeArrays arrays;
    int fast = 0, compared = 0;
    for (int c = 0; c < 3000; ++c) {
        const RectLight light = randomLight(rng);
        const auto kind = static_cast<EdgeKind>(c % static_cast<int>(EdgeKind::Count));
        const TestEdge edge = randomEdge(rng, light, kind);
        const geometry::WedgeBuilder builder(light);
        fast += builder.takesFastPath(edge.e0, edge.e1);
        arrays.clear();
        geometry::WedgeRays reported, derived;
        const Wedge& w = arrays.wedges[builder.append(edge.e0, edge.e1, arrays, reported)];
        geometry::wedgeRecessionRays(w, derived);
        ASSERT_EQ(reported.count, derived.count) << "edge " << c;
        if (w.flags & geometry::kWedgeUnbounded) {
            EXPECT_EQ(reported.count, -1);
            continue;
        }
        for (int i = 0; i < reported.count; ++i) {
            const vec3 r = reported.dirs[i];
            EXPECT_NEAR(glm::length(r), 1.0f, 1e-6f);
            bool found = false;
            for (int j = 0; j < derived.count && !found; ++j)
                found = glm::all(glm::lessThanEqual(glm::abs(derived.dirs[j] - r), vec3(1e-6f)));
            EXPECT_TRUE(found) << "edge " << c << ": ray " << i << " not derived from the planes";
            for (std::uint32_t p = 0; p < w.planeCount; ++p) {
                EXPECT_LE(glm::dot(dvec3(glm::vec3(w.planes[p])), dvec3(r)), 1e-6)
                    << "edge " << c << ": ray " << i << " outside plane " << p;
            }
        }
        ++compared;
    }
    EXPECT_GT(fast, 1000) << "the fast path's rays were hardly exercised";
    EXPECT_GT(compared, 2000);
}

} // namespace
