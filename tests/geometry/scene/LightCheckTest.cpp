#include <geometry/core/Error.h>
#include <geometry/scene/GltfLoader.h>
#include <geometry/scene/LightCheck.h>
#include <geometry/scene/Primitives.h>

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <initializer_list>
#include <limits>
#include <optional>
#include <string>
#include <utility>

namespace {

using geometry::findLightContact;
using geometry::MeshData;
using geometry::Scene;
using geometry::SceneObject;
using geometry::ShadowMethod;

// Lights are horizontal (normal along y) unless stated. kTol is below what validateLightClear
// uses for these lights (contactTolerance: 1e-4 x the light diagonal, 2.8e-4 for a 2 x 2 light).
constexpr float kTol = 1e-5f;

geometry::RectLight light(glm::vec3 center, glm::vec3 u = {1, 0, 0}, glm::vec3 v = {0, 0, 1}) {
    geometry::RectLight l;
    l.center = center;
    l.u = u;
    l.v = v;
    return l;
}

MeshData triangle(glm::vec3 a, glm::vec3 b, glm::vec3 c) {
    MeshData m;
    m.positions = {a, b, c};
    m.triangles = {{0u, 1u, 2u}};
    return m;
}

Scene scene(const geometry::RectLight& l,
            std::initializer_list<std::pair<std::string, MeshData>> objects,
            ShadowMethod method = ShadowMethod::Auto) {
    Scene s;
    s.light = l;
    for (const auto& [name, mesh] : objects)
        s.objects.push_back(SceneObject{name, method, mesh});
    return s;
}

TEST(LightCheck, LightWellAboveBoxIsClear) {
    const Scene s = scene(light({0, 6, 0}), {{"box", geometry::makeBox({0, 0.5f, 0}, {1, 1, 1})}});
    EXPECT_FALSE(findLightContact(s, kTol));
    EXPECT_NO_THROW(geometry::validateLightClear(s));
}

TEST(LightCheck, LightCuttingThroughBoxNamesThatObject) {
    // The first box is clear; the light, wider than the second box, slices through its sides.
    const Scene s = scene(light({4, 1, 0}, {3, 0, 0}, {0, 0, 3}),
                          {{"far", geometry::makeBox({-5, 1, 0}, {1, 1, 1})},
                           {"crate", geometry::makeBox({4, 1, 0}, {2, 2, 2})}});
    const auto c = findLightContact(s, kTol);
    ASSERT_TRUE(c);
    EXPECT_EQ(c->object, 1u);
    EXPECT_LT(c->triangle, 12u);
    EXPECT_LE(std::abs(c->st.x), 1.0f);
    EXPECT_LE(std::abs(c->st.y), 1.0f);
}

TEST(LightCheck, CoplanarOverlappingQuadTouches) {
    // Quad spanning x in [0.5, 2.5] in the light plane: overlaps the light for s in [0.5, 1].
    const Scene s = scene(light({0, 2, 0}),
                          {{"panel", geometry::makeQuad({1.5f, 2, 0}, {1, 0, 0}, {0, 0, 1})}});
    const auto c = findLightContact(s, kTol);
    ASSERT_TRUE(c);
    EXPECT_GE(c->st.x, 0.5f - 1e-4f);
    EXPECT_LE(c->st.x, 1.0f);
}

TEST(LightCheck, CoplanarDisjointQuadIsClear) {
    const Scene s = scene(light({0, 2, 0}),
                          {{"panel", geometry::makeQuad({3.5f, 2, 0}, {1, 0, 0}, {0, 0, 1})}});
    EXPECT_FALSE(findLightContact(s, kTol));
}

TEST(LightCheck, CrossingSegmentBesideTheSquareIsClear) {
    // Crosses y = 0 along z = 1.2, x in [-2.5, 2.5]: beside the square, although the triangle's
    // projection onto the light plane covers much of the square.
    const Scene s =
        scene(light({0, 0, 0}), {{"ramp", triangle({-5, -1, 0.2f}, {5, -1, 0.2f}, {0, 1, 2.2f})}});
    EXPECT_FALSE(findLightContact(s, kTol));
}

TEST(LightCheck, CrossingSegmentThroughCornerTouches) {
    // Crosses y = 0 along x + z = 1.8, cutting the corner (1, 1) of the square.
    const Scene s = scene(light({0, 0, 0}),
                          {{"blade", triangle({3, -1, -1.2f}, {-1.2f, -1, 3}, {0.9f, 1, 0.9f})}});
    const auto c = findLightContact(s, kTol);
    ASSERT_TRUE(c);
    EXPECT_NEAR(c->st.x + c->st.y, 1.8f, 1e-3f);
    EXPECT_GE(c->st.x, 0.8f - 1e-3f);
    EXPECT_GE(c->st.y, 0.8f - 1e-3f);

    // The same blade moved out to x + z = 2.2 passes the corner: bounding boxes still overlap.
    const Scene miss =
        scene(light({0, 0, 0}),
              {{"blade", triangle({3.2f, -1, -1.0f}, {-1.0f, -1, 3.2f}, {1.1f, 1, 1.1f})}});
    EXPECT_FALSE(findLightContact(miss, kTol));
}

TEST(LightCheck, TouchingWithinToleranceCounts) {
    // The light lies 1e-7 above a 20 x 20 floor: far below 1e-4 x the light diagonal.
    const Scene s = scene(light({0, 1e-7f, 0}),
                          {{"floor", geometry::makeQuad({0, 0, 0}, {10, 0, 0}, {0, 0, 10})}});
    EXPECT_TRUE(findLightContact(s, kTol));
    EXPECT_THROW(geometry::validateLightClear(s), geometry::InputError);

    // Exactly on the surface still touches with zero tolerance.
    const Scene on =
        scene(light({0, 0, 0}), {{"floor", geometry::makeQuad({0, 0, 0}, {10, 0, 0}, {0, 0, 10})}});
    EXPECT_TRUE(findLightContact(on, 0.0f));

    // A single vertex resting on the light, and one floating just above it.
    const MeshData tip = triangle({0.5f, 0, 0.5f}, {0.5f, 1, 0}, {0, 1, 0.5f});
    EXPECT_TRUE(findLightContact(scene(light({0, 0, 0}), {{"tip", tip}}), 0.0f));
    const MeshData above = triangle({0.5f, 1e-3f, 0.5f}, {0.5f, 1, 0}, {0, 1, 0.5f});
    EXPECT_FALSE(findLightContact(scene(light({0, 0, 0}), {{"tip", above}}), kTol));

    // A light edge ending 1e-7 short of a wall touches; 1e-2 short does not.
    const MeshData wall = geometry::makeQuad({1 + 1e-7f, 0, 0}, {0, 5, 0}, {0, 0, 5});
    EXPECT_TRUE(findLightContact(scene(light({0, 0, 0}), {{"wall", wall}}), kTol));
    const MeshData far = geometry::makeQuad({1.01f, 0, 0}, {0, 5, 0}, {0, 0, 5});
    EXPECT_FALSE(findLightContact(scene(light({0, 0, 0}), {{"wall", far}}), kTol));
}

TEST(LightCheck, NonOrthogonalAxesUseTrueLightCoordinates) {
    // A parallelogram: u = (1, 0, 0), v = (1, 0, 1). The point c + 0.9u + 0.9v = (1.8, 0, 0.9)
    // is on the light, although dot(p - c, u) / |u|^2 = 1.8 would call it outside.
    const geometry::RectLight l = light({0, 0, 0}, {1, 0, 0}, {1, 0, 1});
    auto spike = [](glm::vec3 q) {
        return triangle(q + glm::vec3(-0.01f, -1, 0), q + glm::vec3(0.01f, -1, 0),
                        q + glm::vec3(0, 1, 0));
    };
    const auto c = findLightContact(scene(l, {{"spike", spike({1.8f, 0, 0.9f})}}), kTol);
    ASSERT_TRUE(c);
    EXPECT_NEAR(c->st.x, 0.9f, 0.02f);
    EXPECT_NEAR(c->st.y, 0.9f, 0.02f);

    // (0, 0, 1.5) is s = -1.5, t = 1.5: off the light, although the naive projections
    // (0, 0.75) would put it inside.
    EXPECT_FALSE(findLightContact(scene(l, {{"spike", spike({0, 0, 1.5f})}}), kTol));
}

TEST(LightCheck, LightInsideClosedRoomIsClear) {
    const Scene s = scene(light({0, 8, 0}, {2, 0, 0}, {0, 0, 2}),
                          {{"room", geometry::makeBox({0, 5, 0}, {20, 10, 20})}});
    EXPECT_FALSE(findLightContact(s, kTol));
    EXPECT_NO_THROW(geometry::validateLightClear(s));
}

TEST(LightCheck, MethodNoneObjectStillCounts) {
    const Scene s = scene(light({0, 1, 0}), {{"ghost", geometry::makeBox({0, 1, 0}, {1, 1, 1})}},
                          ShadowMethod::None);
    const auto c = findLightContact(s, kTol);
    ASSERT_TRUE(c);
    EXPECT_EQ(c->object, 0u);
}

TEST(LightCheck, MessageNamesObjectTriangleAndPlace) {
    const Scene s = scene(light({4, 1, 0}, {3, 0, 0}, {0, 0, 3}),
                          {{"far", geometry::makeBox({-5, 1, 0}, {1, 1, 1})},
                           {"crate", geometry::makeBox({4, 1, 0}, {2, 2, 2})}});
    try {
        geometry::validateLightClear(s);
        FAIL() << "expected InputError";
    } catch (const geometry::InputError& e) {
        const std::string msg = e.what();
        EXPECT_NE(msg.find("light intersects object 'crate' (triangle "), std::string::npos) << msg;
        EXPECT_NE(msg.find("near light (s "), std::string::npos) << msg;
        EXPECT_NE(msg.find("move or shrink the light"), std::string::npos) << msg;
        EXPECT_EQ(msg.find("'far'"), std::string::npos) << msg;
    }
}

// A refused light is a LightRefusedError (penumbra-soak and the viewer catch that type to fall
// back to another light), and still an InputError (bad input, exit 2, for everyone else):
// touching geometry, and, through validateLight, a light with no area or a non-finite one. Other
// bad input stays a plain InputError.
TEST(LightCheck, RefusedLightIsALightRefusedError) {
    const Scene s = scene(light({0, 1, 0}), {{"box", geometry::makeBox({0, 1, 0}, {1, 1, 1})}});
    EXPECT_THROW(geometry::validateLightClear(s), geometry::LightRefusedError);
    EXPECT_THROW(geometry::validateLightClear(s), geometry::InputError);
    EXPECT_THROW(geometry::validateLight(s, s.light, "moved light"), geometry::LightRefusedError);

    const Scene clear =
        scene(light({0, 6, 0}), {{"box", geometry::makeBox({0, 0.5f, 0}, {1, 1, 1})}});
    EXPECT_NO_THROW(geometry::validateLight(clear, clear.light, "moved light"));
    geometry::RectLight flat = clear.light;
    flat.v = flat.u; // zero area
    EXPECT_THROW(geometry::validateLight(clear, flat, "moved light"), geometry::LightRefusedError);
    geometry::RectLight point = clear.light;
    point.u = glm::vec3(0.0f); // zero size
    EXPECT_THROW(geometry::validateLight(clear, point, "moved light"), geometry::LightRefusedError);
    geometry::RectLight lost = clear.light;
    lost.center.x = std::numeric_limits<float>::quiet_NaN();
    try {
        geometry::validateLight(clear, lost, "moved light");
        FAIL() << "a light at NaN was accepted";
    } catch (const geometry::LightRefusedError& e) {
        EXPECT_NE(std::string(e.what()).find("moved light.center: must be finite"),
                  std::string::npos)
            << e.what();
    }

    // Not a light: a camera looking nowhere is bad input of another kind.
    geometry::Camera camera;
    camera.eye = camera.target = glm::vec3(1.0f);
    try {
        geometry::validateCamera(camera, "camera");
        FAIL() << "a camera with eye == target was accepted";
    } catch (const geometry::InputError& e) {
        EXPECT_EQ(dynamic_cast<const geometry::LightRefusedError*>(&e), nullptr) << e.what();
    }
}

// The tolerance is the light's: a huge object far away (here 9e6 from the light, inside the
// coordinate bound) once made it 1e-5 x a 2e7 diagonal, so the floor 4 below the light
// "touched" it and was named.
TEST(LightCheck, ToleranceFollowsTheLightNotTheSceneExtent) {
    const geometry::RectLight l = light({0, 4, 0}, {0.5f, 0, 0}, {0, 0, 0.5f});
    const MeshData floor = geometry::makeQuad({0, 0, 0}, {3, 0, 0}, {0, 0, -3});
    const MeshData giant = geometry::makeQuad({0, 0, 9e6f}, {1e6f, 0, 0}, {0, 1e6f, 0});
    EXPECT_LT(geometry::contactTolerance(l), 1e-3f);
    EXPECT_NO_THROW(geometry::validateLightClear(scene(l, {{"floor", floor}, {"giant", giant}})));

    // A real contact is still found, and the object named is the one touching.
    const MeshData crate = geometry::makeBox({0, 4, 0}, {0.4f, 0.4f, 0.4f});
    try {
        geometry::validateLightClear(
            scene(l, {{"floor", floor}, {"giant", giant}, {"crate", crate}}));
        FAIL() << "expected InputError";
    } catch (const geometry::InputError& e) {
        const std::string msg = e.what();
        EXPECT_NE(msg.find("light intersects object 'crate'"), std::string::npos) << msg;
    }

    // Far from the origin the tolerance covers float rounding of the light's coordinates.
    const geometry::RectLight far = light({5e6f, 4, 0}, {0.5f, 0, 0}, {0, 0, 0.5f});
    EXPECT_GE(geometry::contactTolerance(far),
              4.0f * std::numeric_limits<float>::epsilon() * 5e6f);
}

// A light above oa_dm5's bounds is clear: the full scan of its 66k triangles finds no contact.
// The scan's cost (this light, and one at the centre of the level) is geometry_bench's
// light_check/oa_dm5/{above,inside}.
TEST(LightCheck, LargeLevelLightAboveIsClear) {
    const std::filesystem::path level =
        std::filesystem::path(PENUMBRA_SHARED_DIR) / "levels" / "oa_dm5.glb";
    ASSERT_TRUE(std::filesystem::exists(level))
        << "missing " << level << " (../shared must be beside the repo)";
    Scene s;
    s.objects.push_back(SceneObject{"oa_dm5.glb", ShadowMethod::Auto, geometry::loadGltf(level)});
    const geometry::Aabb b = s.bounds();
    const float half = 0.01f * glm::length(b.extent());
    s.light =
        light(glm::vec3(b.center().x, b.max.y + 1.0f, b.center().z), {half, 0, 0}, {0, 0, half});
    EXPECT_FALSE(findLightContact(s, 1e-5f * glm::length(b.extent())));
}

} // namespace
