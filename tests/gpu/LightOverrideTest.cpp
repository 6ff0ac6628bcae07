// RenderSettings::light: a frame rendered with a replaced light equals a frame of the scene whose
// light was edited to match (same renderer, so the bench's sweeps and scales need no reload), and
// a replaced light is validated like the scene's.
#include "GlTestEnv.h"
#include "RenderTestUtil.h"
#include "TestErrors.h"

#include <geometry/core/Error.h>
#include <geometry/reference/Framing.h>

#include <cmath>
#include <optional>
#include <string>

namespace {

class LightOverride : public GlTest {};

TEST_F(LightOverride, EqualsTheEditedScene) {
    const geometry::Scene scene = geometry::loadScene(testutil::dataPath("plates-three.json"));
    geometry::RectLight moved = scene.light;
    moved.center += 0.5f * scene.light.u; // half a light half-width along u
    moved.u *= 0.7f;
    geometry::Scene edited = scene;
    edited.light = moved;
    for (const char* method : {"hard", "wedges-blend", "occlusion", "pcss", "reference"}) {
        const geometry::FloatImage a = testutil::renderOverridden(scene, method, {.light = moved});
        const geometry::FloatImage b = testutil::renderOverridden(edited, method, {});
        EXPECT_EQ(testutil::countDiffering(a, b, 0.0f), 0u) << method;
        // And the light did change the picture (the override is not ignored).
        const geometry::FloatImage c = testutil::renderOverridden(scene, method, {});
        EXPECT_GT(testutil::countDiffering(a, c, 0.02f), 50u) << method;
    }
}

TEST_F(LightOverride, RefusesALightThatTouchesGeometry) {
    const geometry::Scene scene = geometry::loadScene(testutil::dataPath("plates-three.json"));
    testutil::SceneRenderer sr(scene);
    gpu::RenderSettings s;
    s.width = s.height = 32;
    const auto renderError = [&] {
        return testutil::errorOf<geometry::InputError>([&] { sr.renderer.renderFrame(s); });
    };
    geometry::RectLight low = scene.light;
    low.center.y = 1.8f; // the plane of the highest plate, over it
    low.center.z = -0.45f;
    s.light = low;
    const std::optional<std::string> touching = renderError();
    ASSERT_TRUE(touching) << "a light in the plane of a plate was accepted";
    EXPECT_NE(touching->find("RenderSettings::light intersects object 'high'"), std::string::npos)
        << *touching;
    geometry::RectLight flat = scene.light;
    flat.v = flat.u;
    s.light = flat;
    const std::optional<std::string> zeroArea = renderError();
    ASSERT_TRUE(zeroArea) << "a light with parallel axes was accepted";
    EXPECT_NE(zeroArea->find("zero area"), std::string::npos) << *zeroArea;
}

// The renderer refuses a replaced light with geometry::LightRefusedError (what penumbra-soak and
// the viewer catch to fall back to the light they had); other bad settings stay InputErrors.
TEST_F(LightOverride, ARefusedLightIsALightRefusedError) {
    const geometry::Scene scene = geometry::loadScene(testutil::dataPath("plates-three.json"));
    gpu::ShaderLoader shaders(gpu::defaultShaderDir());
    gpu::Renderer renderer(scene, shaders);
    gpu::RenderSettings s;
    s.width = s.height = 32;
    geometry::RectLight low = scene.light;
    low.center.y = 1.8f; // the plane of the highest plate, over it
    low.center.z = -0.45f;
    s.light = low;
    EXPECT_THROW(renderer.renderFrame(s), geometry::LightRefusedError);
    geometry::RectLight flat = scene.light;
    flat.v = flat.u;
    s.light = flat;
    EXPECT_THROW(renderer.renderFrame(s), geometry::LightRefusedError);
    s.light = scene.light;
    s.method = "nope";
    try {
        renderer.renderFrame(s);
        FAIL() << "an unknown method was accepted";
    } catch (const geometry::InputError& e) {
        EXPECT_EQ(dynamic_cast<const geometry::LightRefusedError*>(&e), nullptr) << e.what();
    }
}

} // namespace
