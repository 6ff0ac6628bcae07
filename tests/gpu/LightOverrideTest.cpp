// RenderSettings::light: a frame rendered with a replaced light equals a frame of the scene whose
// light was edited to match (same renderer, so the bench's sweeps and scales need no reload), and
// a replaced light is validated like the scene's.
#include "GlTestEnv.h"
#include "RenderTestUtil.h"

#include <geometry/Error.h>

#include <cmath>
#include <string>

namespace {

class LightOverride : public GlTest {};

geometry::FloatImage renderWith(const geometry::Scene& scene, const std::string& method,
                                const std::optional<geometry::RectLight>& light) {
    gpu::ShaderLoader shaders(gpu::defaultShaderDir());
    gpu::Renderer renderer(scene, shaders);
    gpu::RenderSettings s;
    s.method = method;
    s.width = s.height = 96;
    s.samples = 64;
    // A first frame with the scene's own light: the override must not reuse its state.
    renderer.renderFrame(s);
    s.light = light;
    renderer.renderFrame(s);
    return renderer.visibility();
}

TEST_F(LightOverride, EqualsTheEditedScene) {
    const geometry::Scene scene = geometry::loadScene(testutil::dataPath("plates-three.json"));
    geometry::RectLight moved = scene.light;
    moved.center += 0.5f * scene.light.u; // half a light half-width along u
    moved.u *= 0.7f;
    geometry::Scene edited = scene;
    edited.light = moved;
    for (const char* method : {"hard", "wedges-blend", "occlusion", "pcss", "reference"}) {
        const geometry::FloatImage a = renderWith(scene, method, moved);
        const geometry::FloatImage b = renderWith(edited, method, std::nullopt);
        EXPECT_EQ(testutil::countDiffering(a, b, 0.0f), 0u) << method;
        // And the light did change the picture (the override is not ignored).
        const geometry::FloatImage c = renderWith(scene, method, std::nullopt);
        EXPECT_GT(testutil::countDiffering(a, c, 0.02f), 50u) << method;
    }
}

TEST_F(LightOverride, RefusesALightThatTouchesGeometry) {
    const geometry::Scene scene = geometry::loadScene(testutil::dataPath("plates-three.json"));
    gpu::ShaderLoader shaders(gpu::defaultShaderDir());
    gpu::Renderer renderer(scene, shaders);
    gpu::RenderSettings s;
    s.width = s.height = 32;
    geometry::RectLight low = scene.light;
    low.center.y = 1.8f; // the plane of the highest plate, over it
    low.center.z = -0.45f;
    s.light = low;
    try {
        renderer.renderFrame(s);
        FAIL() << "a light in the plane of a plate was accepted";
    } catch (const geometry::InputError& e) {
        EXPECT_NE(std::string(e.what()).find("RenderSettings::light intersects object 'high'"),
                  std::string::npos)
            << e.what();
    }
    geometry::RectLight flat = scene.light;
    flat.v = flat.u;
    s.light = flat;
    try {
        renderer.renderFrame(s);
        FAIL() << "a light with parallel axes was accepted";
    } catch (const geometry::InputError& e) {
        EXPECT_NE(std::string(e.what()).find("zero area"), std::string::npos) << e.what();
    }
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
