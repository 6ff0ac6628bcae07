// Outside the union of the penumbra wedges, brute-force visibility equals the hard-shadow value
// exactly (issue 3). A wedge must contain every point whose visibility its edge can change
// (geometry/shadow/Wedge.h), so a point in no wedge of any silhouette group of any object sees either
// the whole light or none of it, and which one is decided by the light centre.
//
// - Receivers: surface points seen by the camera, from a grid of jittered rays (fixed seed)
//   intersected with the scene by Embree; the normal is the geometric one turned to the camera.
// - Wedges: SilhouetteExtractor's, per object from its own Topology, tested with wedgeContains
//   and a small positive eps. Added to them: the wedges of edges that are silhouettes only from
//   other points of the light than its centre (see appendOffCentreWedges; the centre silhouette
//   is an approximation there). Points that only those hold are counted and reported. For the
//   curved occluders (torus, noisy sphere) the centre wedges alone do miss some penumbra points;
//   for the planar ones (box, quad, boxes, level) they must not, which is checked: there the
//   issue's statement holds literally with the extractor's wedges.
// - A point is outside when both the surface point and the ray tracer's offset origin (the hit
//   moved along the normal by RayTraceSettings::offsetScale times the scene diagonal) are.
// - Brute force: RayTracer::visibility with 1024 stratified light samples against
//   RayTracer::hardVisibility from the light centre; for points outside every wedge they must be
//   equal as floats (0 or 1 exactly).
// - Not vacuous: every scene must have many points outside all wedges and many inside some, and
//   the points inside must include real penumbra (0 < V < 1).
#include <geometry/scene/Primitives.h>
#include <geometry/reference/RayTracer.h>
#include <geometry/scene/Scene.h>
#include <geometry/reference/Framing.h>
#include <geometry/shadow/Silhouette.h>
#include <geometry/shadow/Topology.h>
#include <geometry/shadow/Wedge.h>

#include <gtest/gtest.h>

#include <glm/gtc/matrix_transform.hpp>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <random>
#include <string>
#include <vector>

namespace {

using geometry::MeshData;
using geometry::Scene;

constexpr int kSamples = 1024;      // light samples of the brute-force visibility
constexpr std::uint32_t kSeed = 17; // camera-ray jitter and light-sample rotation

struct Receivers {
    std::vector<glm::vec3> points;  // surface hits
    std::vector<glm::vec3> normals; // unit, facing the camera
};

// Image window in [0, 1]^2 (x right, y down) sampled by the receiver grid.
struct Window {
    float x0 = 0.0f, y0 = 0.0f, x1 = 1.0f, y1 = 1.0f;
};

// n x n jittered camera rays over `window` of a square image; the hits become receivers.
Receivers castReceivers(const Scene& scene, const geometry::RayTracer& tracer, int n,
                        const Window& window) {
    const geometry::Camera& cam = scene.camera;
    const glm::vec3 forward = glm::normalize(cam.target - cam.eye);
    const glm::vec3 right = glm::normalize(glm::cross(forward, cam.up));
    const glm::vec3 up = glm::cross(right, forward);
    const float tanHalf = std::tan(glm::radians(0.5f * cam.fovYDeg));
    std::mt19937 rng(kSeed);
    std::uniform_real_distribution<float> jitter(0.0f, 1.0f);
    Receivers r;
    for (int j = 0; j < n; ++j) {
        for (int i = 0; i < n; ++i) {
            const float fx = window.x0 + (window.x1 - window.x0) * (i + jitter(rng)) / n;
            const float fy = window.y0 + (window.y1 - window.y0) * (j + jitter(rng)) / n;
            const glm::vec3 dir = glm::normalize(forward + (2.0f * fx - 1.0f) * tanHalf * right +
                                                 (1.0f - 2.0f * fy) * tanHalf * up);
            float t = 0.0f;
            glm::vec3 normal;
            if (!tracer.intersect(cam.eye, dir, t, normal)) continue;
            // The receiver is the side the camera sees (DESIGN.md §2: the offset goes there).
            if (glm::dot(normal, dir) > 0.0f) normal = -normal;
            r.points.push_back(cam.eye + t * dir);
            r.normals.push_back(normal);
        }
    }
    return r;
}

// The RayTracer's offset length: offsetScale times the diagonal of all object positions.
float sceneDiagonal(const Scene& scene) {
    geometry::Aabb b;
    for (const auto& object : scene.objects) {
        for (const glm::vec3& p : object.mesh.positions)
            b.extend(p);
    }
    return glm::length(b.extent());
}

// Light-facing of a triangle from y, as the silhouette classification decides it.
int facing(const glm::vec3& a, const glm::vec3& b, const glm::vec3& c, const glm::vec3& y) {
    const float d = glm::dot(glm::cross(b - a, c - a), y - a);
    return d > 0.0f ? 1 : (d < 0.0f ? -1 : 0);
}

// Edges that are silhouette edges from some light point but not from the centre.
//
// SilhouetteExtractor builds wedges for the silhouette seen from the light centre (DESIGN.md §4,
// Assarsson & Akenine-Möller 2003). Where a triangle's plane cuts the light, the silhouette seen
// from other light points differs, and the centre's wedges need not contain every point whose
// visibility changes (a tessellated curved occluder; a point lit at a grazing angle that its own
// surface shadows from part of the light). Those edges are: multiplicity 0 from the centre, and
// some incident triangle faces part of the light and not the rest, unless all incident triangles
// are coplanar (then their facings change together and the multiplicity stays 0). The test
// builds their wedges itself, so the union property can be checked exactly in every scene, and
// reports how many points only these extra wedges hold and how many of those the centre wedges
// alone get wrong (the approximation error of the centre silhouette).
void appendOffCentreWedges(const geometry::Topology& topo, const geometry::RectLight& light,
                           bool oneSided, geometry::WedgeArrays& out) {
    const auto pos = topo.positions();
    const auto tris = topo.triangles();
    const glm::vec3 corners[4] = {light.point(-1, -1), light.point(1, -1), light.point(1, 1),
                                  light.point(-1, 1)};
    std::vector<int> weight(tris.size());  // participation from the centre
    std::vector<char> varies(tris.size()); // facing not constant over the light
    std::vector<glm::vec3> normal(tris.size());
    for (std::size_t t = 0; t < tris.size(); ++t) {
        const glm::vec3 a = pos[tris[t].x], b = pos[tris[t].y], c = pos[tris[t].z];
        const int f = facing(a, b, c, light.center);
        weight[t] = f > 0 ? 1 : (oneSided ? 0 : -1);
        bool v = f == 0;
        for (const glm::vec3& y : corners)
            v = v || facing(a, b, c, y) != f;
        varies[t] = v;
        const glm::vec3 n = glm::cross(b - a, c - a);
        normal[t] = glm::length(n) > 0.0f ? glm::normalize(n) : glm::vec3(0.0f);
    }
    const auto edges = topo.edges();
    const auto offsets = topo.edgeUseOffsets();
    const auto uses = topo.edgeUses();
    for (std::size_t e = 0; e < edges.size(); ++e) {
        int multiplicity = 0;
        bool anyVaries = false, coplanar = true;
        const glm::vec3 n0 = normal[uses[offsets[e]].triangle];
        for (std::uint32_t k = offsets[e]; k < offsets[e + 1]; ++k) {
            const std::uint32_t t = uses[k].triangle;
            multiplicity += uses[k].sign * weight[t];
            anyVaries = anyVaries || varies[t];
            coplanar = coplanar && std::abs(glm::dot(normal[t], n0)) >= 1.0f - 1e-6f;
        }
        if (multiplicity != 0 || !anyVaries || coplanar) continue;
        geometry::appendWedge(pos[edges[e].v0], pos[edges[e].v1], light, out);
    }
}

struct UnionResult {
    int points = 0;
    int outside = 0;      // in no wedge (centre or off-centre): V must equal V_hard
    int inside = 0;       // in some centre wedge
    int penumbra = 0;     // inside, with 0 < V < 1
    int mismatches = 0;   // outside, V != V_hard: a failure
    int offCentre = 0;    // in no centre wedge, only in off-centre ones
    int centreMisses = 0; // offCentre points with V != V_hard: the centre approximation's error
    int groups = 0;
    int wedges = 0;
    int offCentreWedges = 0;
};

bool inAnyWedge(const std::vector<const geometry::Wedge*>& wedges, const glm::vec3& p, float eps) {
    for (const geometry::Wedge* w : wedges) {
        if (geometry::wedgeContains(*w, p, eps)) return true;
    }
    return false;
}

// The union check on one scene. `wedgeEps` grows every wedge (world units) to absorb rounding on
// wedge boundaries, where visibility is still exactly the hard value.
UnionResult checkUnion(const Scene& scene, int grid, const Window& window, float wedgeEps) {
    const geometry::RayTracer tracer(scene);
    const Receivers rec = castReceivers(scene, tracer, grid, window);

    // Silhouettes per object, from its own topology, as the renderer builds them.
    const geometry::Aabb bounds = scene.bounds();
    const geometry::SilhouetteSettings silhouetteSettings;
    std::vector<geometry::SilhouetteFrame> frames;
    geometry::WedgeArrays offCentre;
    for (const auto& object : scene.objects) {
        if (object.method == geometry::ShadowMethod::None) continue;
        const geometry::Topology topo(object.mesh);
        geometry::SilhouetteExtractor extractor(topo);
        frames.push_back(extractor.update(scene.light, bounds, silhouetteSettings));
        const bool oneSided = silhouetteSettings.oneSidedClosed &&
                              topo.manifoldness() == geometry::Manifoldness::Closed;
        appendOffCentreWedges(topo, scene.light, oneSided, offCentre);
    }
    UnionResult result;
    std::vector<const geometry::Wedge*> centreWedges, offCentreWedges;
    for (const geometry::SilhouetteFrame& frame : frames) {
        result.groups += static_cast<int>(frame.groups.size());
        for (const geometry::SilhouetteGroup& g : frame.groups) {
            for (std::uint32_t k = 0; k < g.edgeCount; ++k) {
                centreWedges.push_back(&frame.wedges.wedges.at(g.firstWedge + k));
            }
        }
    }
    for (const geometry::Wedge& w : offCentre.wedges)
        offCentreWedges.push_back(&w);
    result.wedges = static_cast<int>(centreWedges.size());
    result.offCentreWedges = static_cast<int>(offCentreWedges.size());

    geometry::RayTraceSettings settings;
    settings.samples = kSamples;
    settings.seed = kSeed;
    const float offset = settings.offsetScale * sceneDiagonal(scene);

    const std::size_t count = rec.points.size();
    result.points = static_cast<int>(count);
    std::vector<float> v(count), hard(count);
    tracer.visibility(scene.light, rec.points, rec.normals, settings, v);
    tracer.hardVisibility(scene.light.center, rec.points, rec.normals, settings, hard);

    int reported = 0;
    for (std::size_t i = 0; i < count; ++i) {
        // The reference decides samples behind the tangent plane at the surface point exactly
        // and shoots the others from the offset origin, so its value can change where either
        // point is in a wedge: a point is outside only when both are.
        const glm::vec3 surface = rec.points[i];
        const glm::vec3 origin = surface + offset * rec.normals[i];
        const auto inUnion = [&](const std::vector<const geometry::Wedge*>& wedges) {
            return inAnyWedge(wedges, surface, wedgeEps) || inAnyWedge(wedges, origin, wedgeEps);
        };
        if (inUnion(centreWedges)) {
            ++result.inside;
            if (v[i] > 0.0f && v[i] < 1.0f) ++result.penumbra;
        } else if (inUnion(offCentreWedges)) {
            ++result.offCentre;
            if (v[i] != hard[i]) ++result.centreMisses;
        } else {
            ++result.outside;
            if (v[i] != hard[i]) {
                ++result.mismatches;
                if (reported++ < 10) {
                    ADD_FAILURE() << "outside every wedge but V = " << v[i]
                                  << " != V_hard = " << hard[i] << " at (" << origin.x << ", "
                                  << origin.y << ", " << origin.z << "), normal ("
                                  << rec.normals[i].x << ", " << rec.normals[i].y << ", "
                                  << rec.normals[i].z << ")";
                }
            }
        }
    }
    return result;
}

void report(const char* name, const UnionResult& r) {
    std::printf("[ union    ] %-13s groups %3d wedges %5d (+%4d off-centre) | points %5d: "
                "outside %5d, inside %5d (penumbra %4d), off-centre only %4d (centre misses "
                "%3d) | mismatches %d\n",
                name, r.groups, r.wedges, r.offCentreWedges, r.points, r.outside, r.inside,
                r.penumbra, r.offCentre, r.centreMisses, r.mismatches);
}

// Whether the light-centre silhouette is expected to hold every penumbra point by itself.
enum class Centre { Exact, Approximate };

// The hard-to-fake part: exact agreement outside, and enough points on both sides (and real
// penumbra inside) that the agreement means something.
void expectUnionProperty(const char* name, const UnionResult& r, int minOutside, int minInside,
                         Centre centre) {
    report(name, r);
    EXPECT_EQ(r.mismatches, 0) << name;
    if (centre == Centre::Exact) {
        EXPECT_EQ(r.centreMisses, 0) << name << ": penumbra outside the extractor's wedges";
    }
    EXPECT_GE(r.outside, minOutside) << name << ": too few points outside all wedges";
    EXPECT_GE(r.inside, minInside) << name << ": too few points inside some wedge";
    EXPECT_GE(r.penumbra, minInside / 4) << name << ": too little penumbra among the receivers";
}

MeshData transformed(MeshData mesh, const glm::mat4& m) {
    for (glm::vec3& p : mesh.positions)
        p = glm::vec3(m * glm::vec4(p, 1.0f));
    return mesh;
}

// Small scenes share a floor (10 x 10 quad, normal up), a 1.2 x 1.2 light 4 above it and a
// camera looking down at the occluders from the side, framed tightly so that many receivers
// fall in their penumbrae.
Scene smallScene(std::vector<MeshData> occluders) {
    Scene scene;
    scene.light.center = {0.2f, 4.0f, 0.1f};
    scene.light.u = {0.6f, 0.0f, 0.0f};
    scene.light.v = {0.0f, 0.0f, 0.6f};
    scene.camera.eye = {0.0f, 5.0f, 5.5f};
    scene.camera.target = {0.0f, 0.3f, 0.0f};
    scene.camera.fovYDeg = 36.0f;
    // u = z, v = x: cross(u, v) = +y.
    scene.objects.push_back(
        {"floor", geometry::ShadowMethod::Auto,
         geometry::makeQuad({0.0f, 0.0f, 0.0f}, {0.0f, 0.0f, 5.0f}, {5.0f, 0.0f, 0.0f})});
    for (std::size_t i = 0; i < occluders.size(); ++i) {
        scene.objects.push_back({"occluder" + std::to_string(i), geometry::ShadowMethod::Auto,
                                 std::move(occluders[i])});
    }
    geometry::validateScene(scene); // the light touches nothing
    return scene;
}

constexpr int kSmallGrid = 72;     // 5,184 camera rays per small scene
constexpr float kSmallEps = 1e-5f; // 1e-6 of the ~10-unit scene diagonal: rounding only
const Window kFullView{};
// Of ~4,700 receivers per small scene: a third of them outside all wedges and several hundred
// inside leave every scene well above these (the box, the smallest penumbra, has ~500 inside).
constexpr int kSmallMinOutside = 1500;
constexpr int kSmallMinInside = 400;

TEST(WedgeUnionTest, BoxAboveFloor) {
    const Scene scene = smallScene({geometry::makeBox({0.0f, 1.0f, 0.0f}, {1.0f, 0.5f, 1.0f})});
    expectUnionProperty("box", checkUnion(scene, kSmallGrid, kFullView, kSmallEps),
                        kSmallMinOutside, kSmallMinInside, Centre::Exact);
}

TEST(WedgeUnionTest, TiltedQuad) {
    // Tilted so that its plane passes through the light: its own shading has a penumbra too.
    const Scene scene = smallScene(
        {geometry::makeQuad({0.3f, 1.5f, 0.0f}, {0.8f, 0.3f, 0.0f}, {0.0f, 0.25f, 0.7f})});
    const UnionResult r = checkUnion(scene, kSmallGrid, kFullView, kSmallEps);
    expectUnionProperty("tilted quad", r, kSmallMinOutside, kSmallMinInside, Centre::Exact);
    // A planar polygon's silhouette is its boundary from every light point: nothing is added to
    // the centre wedges here, so this scene checks the statement literally.
    EXPECT_EQ(r.offCentreWedges, 0);
}

TEST(WedgeUnionTest, TiltedTorus) {
    // Two silhouette loops; tilted so that the hole's shadow is not symmetric.
    const glm::mat4 m = glm::rotate(glm::translate(glm::mat4(1.0f), {0.0f, 1.3f, 0.0f}),
                                    glm::radians(25.0f), glm::vec3(1.0f, 0.0f, 0.3f));
    const Scene scene =
        smallScene({transformed(geometry::makeTorus({0.0f, 0.0f, 0.0f}, 0.8f, 0.25f, 48, 24), m)});
    // Curved: its silhouette changes over the light, and its lit side shadows itself at grazing
    // angles from part of the light; the centre wedges alone miss some of that penumbra.
    expectUnionProperty("torus", checkUnion(scene, kSmallGrid, kFullView, kSmallEps),
                        kSmallMinOutside, kSmallMinInside, Centre::Approximate);
}

TEST(WedgeUnionTest, NoisySphere) {
    const glm::vec3 c(0.0f, 1.3f, 0.0f);
    MeshData sphere = geometry::makeIcosphere(c, 0.7f, 3);
    geometry::displaceRadially(sphere, c, 0.03f, kSeed); // about a third of an edge
    const Scene scene = smallScene({std::move(sphere)});
    // Curved and bumpy, like the torus.
    expectUnionProperty("noisy sphere", checkUnion(scene, kSmallGrid, kFullView, kSmallEps),
                        kSmallMinOutside, kSmallMinInside, Centre::Approximate);
}

TEST(WedgeUnionTest, TwoOverlappingOccluders) {
    // A low box and a higher, rotated box whose shadows overlap on the floor and on the low box.
    const glm::mat4 m = glm::rotate(glm::translate(glm::mat4(1.0f), {0.35f, 2.0f, 0.2f}),
                                    glm::radians(30.0f), glm::vec3(0.0f, 1.0f, 0.0f));
    const Scene scene =
        smallScene({geometry::makeBox({-0.2f, 0.8f, 0.0f}, {1.2f, 0.3f, 0.8f}),
                    transformed(geometry::makeBox({0.0f, 0.0f, 0.0f}, {0.8f, 0.2f, 0.8f}), m)});
    expectUnionProperty("two occluders", checkUnion(scene, kSmallGrid, kFullView, kSmallEps),
                        kSmallMinOutside, kSmallMinInside, Centre::Exact);
}

TEST(WedgeUnionTest, OpenArenaLevelCrop) {
    const std::filesystem::path level =
        std::filesystem::path(PENUMBRA_SHARED_DIR) / "levels" / "oa_dm1.glb";
    ASSERT_TRUE(std::filesystem::exists(level)) << level << " is missing";
    // Interior framing: camera inside the arena, light under the ceiling above the viewed spot
    // (not the level's spawn camera, which loadScene picks).
    Scene scene = geometry::loadScene(level);
    geometry::selectFramedCamera(scene);
    // The lower middle of the view: floor and walls under the light, where its shadows fall.
    const Window crop{0.2f, 0.35f, 0.8f, 0.95f};
    const float eps = 1e-6f * sceneDiagonal(scene);
    expectUnionProperty("oa_dm1 crop", checkUnion(scene, 64, crop, eps), 1500, 300, Centre::Exact);
}

} // namespace
