// The PCSS shadow maps' frame (geometry/shadow/PcssFrame.h):
// - every receiver vertex deeper than zNear lands inside its side's map, and the shadow pass's
//   projection puts it where textureCoord says, at depth zNear / z;
// - casterNear is the least caster depth inside the frustum (the occluder's, not the floor's);
// - receivers beyond the light's plane get the second side, receivers reaching the light's
//   plane clamp the frustum at maxTan (and say so);
// - the light's half extents along its axes are |u| and |v|.
#include <geometry/shadow/PcssFrame.h>
#include <geometry/scene/Primitives.h>
#include <geometry/scene/Scene.h>
#include <geometry/reference/Framing.h>

#include <gtest/gtest.h>

#include <filesystem>

namespace {

geometry::Scene loadData(const char* name) {
    return geometry::loadScene(std::filesystem::path(PENUMBRA_SOURCE_DIR) / "data" / name);
}

std::vector<std::size_t> allObjects(const geometry::Scene& scene) {
    std::vector<std::size_t> all(scene.objects.size());
    for (std::size_t i = 0; i < all.size(); ++i)
        all[i] = i;
    return all;
}

// Every vertex deeper than zNear on a side: inside that side's map, and the projection agrees.
void expectReceiversInside(const geometry::Scene& scene, const geometry::PcssFrame& f) {
    for (const auto& o : scene.objects)
        for (const glm::vec3& q : o.mesh.positions)
            for (int side = 0; side < 2; ++side) {
                const float z = f.depth(q, side);
                if (z <= f.zNear) continue;
                ASSERT_TRUE(f.sides[side].present);
                const glm::vec2 uv = f.textureCoord(q, side);
                EXPECT_GE(uv.x, 0.0f);
                EXPECT_LE(uv.x, 1.0f);
                EXPECT_GE(uv.y, 0.0f);
                EXPECT_LE(uv.y, 1.0f);
                const glm::vec4 clip = f.projection(side) * glm::vec4(q, 1.0f);
                EXPECT_NEAR(clip.w, z, 1e-4f * (1.0f + z));
                EXPECT_NEAR(0.5f * clip.x / clip.w + 0.5f, uv.x, 1e-5f);
                EXPECT_NEAR(0.5f * clip.y / clip.w + 0.5f, uv.y, 1e-5f);
                EXPECT_NEAR(clip.z / clip.w, f.zNear / z, 1e-6f);
            }
}

} // namespace

TEST(PcssFrame, ParallelSquare) {
    const geometry::Scene scene = loadData("parallel-square.json");
    const geometry::PcssFrame f = geometry::fitPcssFrame(scene, allObjects(scene));
    EXPECT_TRUE(f.sides[0].present); // the light faces down (u × v = -y)
    EXPECT_FALSE(f.sides[1].present);
    EXPECT_FALSE(f.sides[0].clamped);
    EXPECT_NEAR(f.normal.y, -1.0f, 1e-6f);
    EXPECT_NEAR(f.halfSize.x, 0.5f, 1e-6f);
    EXPECT_NEAR(f.halfSize.y, 0.5f, 1e-6f);
    // The floor (3 m half-width at depth 3) spans m in [-1, 1], plus the small margin.
    EXPECT_NEAR(f.sides[0].lo.x, -1.0f, 0.01f);
    EXPECT_NEAR(f.sides[0].hi.y, 1.0f, 0.01f);
    // The occluder at y = 1, depth 2; the floor is deeper.
    EXPECT_NEAR(f.sides[0].casterNear, 2.0f, 1e-5f);
    expectReceiversInside(scene, f);
    // Only the floor casting: its depth.
    const std::size_t floorOnly[] = {0};
    EXPECT_NEAR(geometry::fitPcssFrame(scene, floorOnly).sides[0].casterNear, 3.0f, 1e-5f);
}

TEST(PcssFrame, RectangularLightHalfExtents) {
    geometry::Scene scene = loadData("demo.json"); // u = 0.6 x, v = 0.4 z
    const geometry::PcssFrame f = geometry::fitPcssFrame(scene, allObjects(scene));
    EXPECT_NEAR(f.halfSize.x, 0.6f, 1e-6f);
    EXPECT_NEAR(f.halfSize.y, 0.4f, 1e-6f);
    EXPECT_NEAR(glm::dot(f.eu, f.ev), 0.0f, 1e-6f);
    EXPECT_NEAR(glm::dot(f.eu, f.normal), 0.0f, 1e-6f);
    // The walls reach 0.2 m below the light, 4 m beside it: the frustum is capped.
    EXPECT_TRUE(f.sides[0].clamped);
    EXPECT_NEAR(f.sides[0].lo.x, -geometry::PcssFitSettings{}.maxTan, 0.01f);
    EXPECT_FALSE(f.sides[1].present);
    // Receivers within the cap are in the map (the walls' upper parts are not: not checked).
    for (const auto& o : scene.objects)
        for (const glm::vec3& q : o.mesh.positions) {
            const float z = f.depth(q, 0);
            const glm::vec2 m = f.lateral(q) / z;
            if (z <= f.zNear || std::max(std::abs(m.x), std::abs(m.y)) > 2.9f) continue;
            const glm::vec2 uv = f.textureCoord(q, 0);
            EXPECT_TRUE(uv.x >= 0.0f && uv.x <= 1.0f && uv.y >= 0.0f && uv.y <= 1.0f) << o.name;
        }
}

TEST(PcssFrame, ReceiversAboveTheLightGetTheSecondSide) {
    geometry::Scene scene = loadData("parallel-square.json");
    // A ceiling 2 m above the light and a plate between them.
    scene.objects.push_back({"ceiling", geometry::ShadowMethod::Auto,
                             geometry::makeQuad({0, 5, 0}, {3, 0, 0}, {0, 0, 3})});
    scene.objects.push_back({"upper plate", geometry::ShadowMethod::Auto,
                             geometry::makeQuad({0.2f, 4, 0}, {0.4f, 0, 0}, {0, 0, 0.4f})});
    const geometry::PcssFrame f = geometry::fitPcssFrame(scene, allObjects(scene));
    EXPECT_TRUE(f.sides[0].present);
    EXPECT_TRUE(f.sides[1].present);
    EXPECT_NEAR(f.sides[0].casterNear, 2.0f, 1e-5f);
    EXPECT_NEAR(f.sides[1].casterNear, 1.0f, 1e-5f);
    EXPECT_NEAR(f.sides[1].hi.x, 1.5f, 0.01f); // the ceiling: 3 m half-width at depth 2
    expectReceiversInside(scene, f);
}
