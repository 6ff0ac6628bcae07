// Hard shadows (z-fail stencil shadow volumes from the light centre) against closed forms and
// against Embree hard-shadow rays, on closed, open and non-manifold geometry.
#include "GlTestEnv.h"
#include "RenderTestUtil.h"

#include <geometry/reference/Analytic.h>
#include <geometry/scene/Primitives.h>
#include <geometry/reference/RayTracer.h>
#include <geometry/reference/Framing.h>

#include <cmath>
#include <optional>
#include <ostream>

namespace {

using testutil::Rendered;

// Point-light visibility of floor point p past horizontal rectangles, and the distance of the
// shadow ray's crossing from the nearest rectangle edge (to skip pixels on the boundary).
struct HardTruth {
    float v = 1.0f;
    float margin = 1e9f;
};

HardTruth hardTruth(const glm::vec3& light, std::span<const geometry::HorizontalRect> rects,
                    const glm::vec3& p) {
    HardTruth t;
    for (const auto& r : rects) {
        const float s = (r.y - p.y) / (light.y - p.y);
        const glm::vec3 x = p + s * (light - p);
        const float dx = std::min(x.x - r.x0, r.x1 - x.x), dz = std::min(x.z - r.z0, r.z1 - x.z);
        const bool inside = dx > 0 && dz > 0;
        if (inside) t.v = 0.0f;
        const float edge = inside ? std::min(dx, dz)
                                  : std::hypot(std::max(-dx, 0.0f), std::max(-dz, 0.0f));
        t.margin = std::min(t.margin, edge);
    }
    return t;
}

const geometry::HorizontalRect kParallelOccluder{-0.5f, 0.5f, -0.5f, 0.5f, 1.0f};

// Counts floor pixels whose hard V differs from the closed form, away from the shadow edge.
struct FloorCheck {
    int floorPixels = 0, checked = 0, wrong = 0, umbra = 0, lit = 0;
};

FloorCheck checkFloor(const Rendered& r, const geometry::Scene& scene,
                      std::span<const geometry::HorizontalRect> rects, float margin) {
    FloorCheck c;
    for (std::size_t i = 0; i < r.visibility.data.size(); ++i) {
        const float v = r.visibility.data[i];
        if (!std::isfinite(v)) continue;
        const glm::vec3 p = testutil::pixelPosition(r.position, i);
        if (std::fabs(p.y) > 1e-3f) continue;
        ++c.floorPixels;
        // The floor's own outline edges are extruded too (it is an open quad, |x|, |z| <= 3):
        // a pixel on that edge ties with its side quad, so it is not a shadow-edge test.
        if (std::max(std::fabs(p.x), std::fabs(p.z)) > 3.0f - margin) continue;
        const HardTruth t = hardTruth(scene.light.center, rects, p);
        if (t.margin < margin) continue;
        ++c.checked;
        (t.v == 0.0f ? c.umbra : c.lit)++;
        if (v != t.v) {
            ++c.wrong;
            std::printf("  wrong pixel %zu (x %zu, y %zu): p (%.4f %.4f %.4f) V %.1f expected %.1f, "
                        "margin %.4f\n",
                        i, i % r.visibility.width, i / r.visibility.width, p.x, p.y, p.z, v, t.v,
                        t.margin);
        }
    }
    return c;
}

class HardShadow : public GlTest {};

TEST_F(HardShadow, ParallelSquareMatchesPointLightClosedForm) {
    const auto scene = geometry::loadScene(testutil::dataPath("parallel-square.json"));
    const Rendered r = testutil::render(scene, "hard", 128);
    // Margin: one pixel on the floor is ~4 cm here, ~3 cm where the shadow ray crosses the
    // occluder plane; 5 cm keeps pixels whose centre is within ~1.5 px of the edge out.
    const FloorCheck c = checkFloor(r, scene, {&kParallelOccluder, 1}, 0.05f);
    EXPECT_GT(c.floorPixels, 5000);
    EXPECT_GT(c.umbra, 200);
    EXPECT_GT(c.lit, 3000);
    EXPECT_EQ(c.wrong, 0) << "of " << c.checked << " floor pixels away from the shadow edge";

    // The occluder's top faces the light: lit (its own cap must not shadow it).
    int top = 0, topLit = 0;
    for (std::size_t i = 0; i < r.visibility.data.size(); ++i) {
        const glm::vec3 p = testutil::pixelPosition(r.position, i);
        if (!std::isfinite(r.visibility.data[i]) || std::fabs(p.y - 1.0f) > 1e-3f) continue;
        ++top;
        topLit += r.visibility.data[i] == 1.0f;
    }
    EXPECT_GT(top, 100);
    EXPECT_EQ(topLit, top);
    EXPECT_GT(r.stats.silhouetteEdges, 0u);
}

// z-fail: a camera inside the shadow volume must see the same shadow as one outside it.
TEST_F(HardShadow, CameraInsideVolumeGivesSameVisibility) {
    auto scene = geometry::loadScene(testutil::dataPath("parallel-square.json"));
    // Under the occluder, inside the point light's volume: the segment to the light is blocked.
    scene.camera.eye = {0.1f, 0.6f, 0.15f};
    scene.camera.target = {1.2f, 0.0f, 1.0f};
    const HardTruth inside = hardTruth(scene.light.center, {&kParallelOccluder, 1}, scene.camera.eye);
    ASSERT_EQ(inside.v, 0.0f) << "test setup: the camera must start inside the volume";
    scene.camera.fovYDeg = 70.0f;
    const Rendered r = testutil::render(scene, "hard", 128);
    const FloorCheck c = checkFloor(r, scene, {&kParallelOccluder, 1}, 0.05f);
    EXPECT_GT(c.umbra, 200);
    EXPECT_GT(c.lit, 200);
    EXPECT_EQ(c.wrong, 0) << "of " << c.checked << " floor pixels";
}

// Compares hard V with Embree rays to the light centre at the rendered positions.
struct EmbreeComparison {
    double meanAbs = 0.0;
    std::size_t pixels = 0, differing = 0;
    // V = 0 in `hard` where Embree says 1 and both say 1 at all 8 neighbours: a black speck on
    // a lit surface, the symptom of a broken stencil count (a boundary cannot pass there).
    std::size_t isolatedBlack = 0;
};

EmbreeComparison compareWithEmbree(const geometry::Scene& scene, const Rendered& r,
                                   const std::string& name) {
    const std::size_t n = r.visibility.data.size();
    std::vector<glm::vec3> points(n), normals(n);
    for (std::size_t i = 0; i < n; ++i) {
        points[i] = testutil::pixelPosition(r.position, i);
        normals[i] = testutil::pixelPosition(r.normal, i);
    }
    geometry::RayTracer tracer(scene);
    std::vector<float> expected(n);
    tracer.hardVisibility(scene.light.center, points, normals, {}, expected);
    EmbreeComparison c;
    const int w = r.visibility.width, h = r.visibility.height;
    const auto& v = r.visibility.data;
    for (std::size_t i = 0; i < n; ++i) {
        if (!std::isfinite(v[i]) || !std::isfinite(expected[i])) continue;
        ++c.pixels;
        const double d = std::fabs(v[i] - expected[i]);
        c.meanAbs += d;
        if (d <= 0.5) continue;
        ++c.differing;
        const int x = static_cast<int>(i % w), y = static_cast<int>(i / w);
        std::printf("  %s: pixel (%d, %d) hard %.0f Embree %.0f at (%.5f %.5f %.5f)\n",
                    name.c_str(), x, y, v[i], expected[i], points[i].x, points[i].y, points[i].z);
        if (v[i] != 0.0f || x == 0 || y == 0 || x == w - 1 || y == h - 1) continue;
        bool litAround = true;
        for (int dy = -1; dy <= 1; ++dy)
            for (int dx = -1; dx <= 1; ++dx) {
                const std::size_t j = i + static_cast<std::size_t>(dy * w + dx);
                if (j != i) litAround = litAround && v[j] == 1.0f && expected[j] == 1.0f;
            }
        c.isolatedBlack += litAround;
    }
    if (c.pixels) c.meanAbs /= static_cast<double>(c.pixels);
    if (c.differing > 0) testutil::writeComparisonImages(name, r.visibility, expected);
    return c;
}

TEST_F(HardShadow, TwoSidedQuadMatchesEmbree) {
    geometry::Scene scene;
    scene.camera = {{2.5f, 3.0f, 3.5f}, {0, 0, 0}, {0, 1, 0}, 50.0f};
    scene.light = {{0.3f, 3.0f, 0.2f}, {0.4f, 0, 0}, {0, 0, 0.4f}};
    scene.objects.push_back({"floor", geometry::ShadowMethod::Auto,
                             geometry::makeQuad({0, 0, 0}, {3, 0, 0}, {0, 0, -3})});
    // Tilted, and seen from its back by the camera for part of the view: one open quad.
    scene.objects.push_back({"card", geometry::ShadowMethod::Auto,
                             geometry::makeQuad({0, 1.2f, 0}, {0.6f, 0.2f, 0}, {0, 0.3f, 0.5f})});
    const Rendered r = testutil::render(scene, "hard", 128);
    const auto c = compareWithEmbree(scene, r, "hard-quad");
    EXPECT_GT(c.pixels, 8000u);
    // Only pixels whose position lies within rounding (or the ray tracer's offset) of the
    // shadow edge may differ.
    EXPECT_LE(c.differing, 3u) << "of " << c.pixels << " pixels";
    EXPECT_EQ(c.isolatedBlack, 0u);
    std::printf("quad hard vs Embree: %zu of %zu pixels differ\n", c.differing, c.pixels);
}

TEST_F(HardShadow, OpenArenaLevelMatchesEmbree) {
    const auto scene = testutil::framedLevel("levels/oa_dm1.glb");
    const Rendered r = testutil::render(scene, "hard", 128);
    const auto c = compareWithEmbree(scene, r, "hard-oa_dm1");
    EXPECT_GT(c.pixels, 4000u);
    // Residual: see LevelViews below (1 pixel here, on a corner).
    EXPECT_LE(c.differing, 3u) << "of " << c.pixels << " pixels";
    EXPECT_EQ(c.isolatedBlack, 0u);
    std::printf("oa_dm1 hard vs Embree: %zu of %zu pixels differ (mean |dV| %.5f)\n", c.differing,
                c.pixels, c.meanAbs);
}

// Views of the shared levels at 256x192: framed from inside (the automatic view of a .glb
// without cameras), the first view of a player at a spawn point with a small light ahead, and
// the view `--scene level.glb` opens at (its first spawn camera, the framed light).
struct LevelView {
    const char* name;
    std::optional<testutil::SpawnView> spawn; // none: the framed view of `name`.glb
    const char* asLoaded = nullptr;           // set: loadScene of this level, nothing changed
};

void PrintTo(const LevelView& v, std::ostream* os) { *os << v.name; }

class HardShadowLevel : public HardShadow, public ::testing::WithParamInterface<LevelView> {};

// Pixels differing from Embree, before -> after the volume depth clamp (shaders/volume.geom)
// and the ray tracer's smaller offset and near limit (geometry/reference/RayTracer.h): kaos2 16 -> 1,
// oa_dm4 22 -> 2, oa_dm5 29 -> 2; at oa_dm4's spawn 2, pixel row 76 lands on the corner line
// under a door lintel: with the light 3 m ahead, Embree made it black (24 -> 0), with the light
// 6 m ahead the stencil did, which Embree's own error there hid (24 -> 0 once Embree is right).
// What was wrong:
// - side quads seen edge-on by the camera got extrapolated depths on the GPU (volume.geom), so
//   closed volumes lost a face at some pixels: isolated or whole rows of black pixels on lit
//   walls (kaos2: 5 isolated);
// - Embree started rays inside the plane of a face meeting the surface at a concave corner and
//   reported them blocked at t = 0; its 1e-4 * diagonal origin offset (6-9 mm) moved shadow
//   edges by a pixel.
// What remains (at most 2 pixels per view measured; the bound is 3): pixel centres within the
// ray tracer's offset (1e-5 * diagonal, < 1 mm here) of a shadow edge, and G-buffer samples on
// the edge between two faces or on a face seen edge-on, whose position lies on one face and
// whose normal comes from the other: the stencil decides by position, Embree by the normal's
// tangent plane.
TEST_P(HardShadowLevel, MatchesEmbreeUpToBoundaryPixels) {
    const LevelView& view = GetParam();
    const geometry::Scene scene =
        view.asLoaded
            ? geometry::loadScene(testutil::sharedPath(std::string("levels/") + view.asLoaded))
        : view.spawn ? testutil::spawnScene(*view.spawn)
                     : testutil::framedLevel(std::string("levels/") + view.name + ".glb");
    const Rendered r = testutil::render(scene, "hard", 256, 192, 1);
    const auto c = compareWithEmbree(scene, r, std::string("hard-") + view.name);
    std::printf("%s hard vs Embree: %zu of %zu pixels differ, %zu isolated black\n", view.name,
                c.differing, c.pixels, c.isolatedBlack);
    EXPECT_GT(c.pixels, 40000u);
    EXPECT_LE(c.differing, 3u);
    EXPECT_EQ(c.isolatedBlack, 0u);
}

// oa_dm4 spawn 2 (info_player_deathmatch): eye (-1.6256, -6.858, -13.0048), facing +z.
constexpr glm::vec3 kOaDm4Spawn2{-1.6256f, -6.858f, -13.0048f};

INSTANTIATE_TEST_SUITE_P(
    Levels, HardShadowLevel,
    ::testing::Values(LevelView{"kaos2", std::nullopt}, LevelView{"oa_dm4", std::nullopt},
                      LevelView{"oa_dm5", std::nullopt},
                      LevelView{"oa_dm4_spawn2_near_light",
                                testutil::SpawnView{"oa_dm4.glb", "spawn 2", kOaDm4Spawn2, 180.0f,
                                                    3.0f, 1.0f, 0.15f}},
                      LevelView{"oa_dm4_spawn2_far_light",
                                testutil::SpawnView{"oa_dm4.glb", "spawn 2", kOaDm4Spawn2, 180.0f,
                                                    6.0f, 0.5f, 0.2f}},
                      LevelView{"kaos2_camera0", std::nullopt, "kaos2.glb"},
                      LevelView{"oa_dm1_camera0", std::nullopt, "oa_dm1.glb"},
                      LevelView{"oa_dm4_camera0", std::nullopt, "oa_dm4.glb"},
                      LevelView{"oa_dm5_camera0", std::nullopt, "oa_dm5.glb"}),
    [](const auto& info) { return std::string(info.param.name); });

} // namespace

TEST_F(HardShadow, ClosedMeshAroundTheLightShadowsEverythingOutside) {
    // A closed box around the light (a lamp shade without openings) above a floor: every floor
    // point is in its shadow. The one-sided rule alone would see only back faces from inside
    // and shadow nothing; the renderer must notice the light is inside and say so.
    const auto scene = geometry::parseScene(R"({
        "camera": {"eye": [0, 4, 5], "target": [0, 0, 0], "up": [0, 1, 0], "fov_y_deg": 50},
        "light": {"center": [0, 2, 0], "u": [0.2, 0, 0], "v": [0, 0, 0.2]},
        "objects": [
            {"name": "floor", "type": "quad", "center": [0, 0, 0], "u": [3, 0, 0], "v": [0, 0, -3]},
            {"name": "shade", "type": "box", "center": [0, 2, 0], "size": [1, 1, 1]}
        ]})", testutil::dataPath("."), "lamp shade");
    const Rendered r = testutil::render(scene, "hard", 64);
    std::size_t floor = 0, lit = 0;
    for (std::size_t i = 0; i < r.visibility.data.size(); ++i) {
        if (!std::isfinite(r.visibility.data[i])) continue;
        if (std::fabs(testutil::pixelPosition(r.position, i).y) > 1e-3f) continue;
        ++floor;
        lit += r.visibility.data[i] > 0.0f;
    }
    EXPECT_GT(floor, 1000u);
    EXPECT_EQ(lit, 0u);
    double containing = -1;
    for (const auto& c : r.stats.counters)
        if (c.name == "casters_containing_light") containing = c.value;
    EXPECT_EQ(containing, 1.0);
}
