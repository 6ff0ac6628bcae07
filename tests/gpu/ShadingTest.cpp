// The image's n.l reads the files' vertex normals (MeshData::normals, interpolated) through the
// G-buffer's shading normal; visibility never does: every method's V comes from the triangles'
// own planes.
#include "GlTestEnv.h"
#include "RenderTestUtil.h"

#include <geometry/scene/Primitives.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

namespace {

class Shading : public GlTest {};

constexpr int kSize = 64;

// A floor (face normal +y) under a box, lit from above; `normal` given to every floor vertex
// (none when zero).
geometry::Scene floorScene(const glm::vec3& normal) {
    geometry::Scene scene;
    scene.camera.eye = {0.5f, 4.0f, 3.0f};
    scene.camera.target = {0.0f, 0.0f, 0.0f};
    scene.light.center = {0.3f, 3.0f, 0.2f};
    scene.light.u = {0.4f, 0.0f, 0.0f};
    scene.light.v = {0.0f, 0.0f, 0.4f};
    geometry::MeshData floor = geometry::makeQuad({0, 0, 0}, {0, 0, 2}, {2, 0, 0});
    if (normal != glm::vec3(0.0f)) floor.normals.assign(floor.positions.size(), normal);
    scene.objects.push_back({"floor", geometry::ShadowMethod::Auto, std::move(floor)});
    scene.objects.push_back({"box", geometry::ShadowMethod::Auto,
                             geometry::makeBox({0.0f, 1.0f, 0.0f}, {0.5f, 0.5f, 0.5f})});
    return scene;
}

struct Frame {
    std::vector<std::uint8_t> image; // RGBA8, rows top to bottom
    geometry::FloatImage visibility, position;
};

Frame renderFloor(const glm::vec3& normal, const std::string& method) {
    const geometry::Scene scene = floorScene(normal); // the renderer keeps a reference
    testutil::SceneRenderer sr(scene);
    gpu::RenderSettings s = testutil::frameSettings(method, kSize, kSize);
    s.samples = 64;
    sr.renderer.renderFrame(s);
    return {sr.renderer.imageRgba8(), sr.renderer.visibility(), sr.renderer.position()};
}

// shade.frag's sRGB encoding of a linear value.
float srgb(float c) {
    c = std::clamp(c, 0.0f, 1.0f);
    return c <= 0.0031308f ? 12.92f * c : 1.055f * std::pow(c, 1.0f / 2.4f) - 0.055f;
}

TEST_F(Shading, VertexNormalsShadeButDoNotMoveVisibility) {
    const glm::vec3 tilted = glm::normalize(glm::vec3(0.6f, 0.8f, 0.0f));
    const gpu::RenderSettings defaults;
    for (const std::string method : {"hard", "wedges-bitmask", "pcss"}) {
        SCOPED_TRACE(method);
        const Frame flat = renderFloor(glm::vec3(0.0f), method);
        const Frame smooth = renderFloor(tilted, method);
        // A normal against the winding is turned over to the triangle's side first.
        const Frame reversed = renderFloor(-tilted, method);
        ASSERT_EQ(flat.visibility.data.size(), smooth.visibility.data.size());
        // V bit for bit (NaN where no surface on both).
        std::size_t vDiffer = 0;
        for (std::size_t i = 0; i < flat.visibility.data.size(); ++i) {
            const float a = flat.visibility.data[i], b = smooth.visibility.data[i];
            vDiffer += !(a == b || (std::isnan(a) && std::isnan(b)));
        }
        EXPECT_EQ(vDiffer, 0u);
        EXPECT_EQ(smooth.image, reversed.image);

        // On the floor, the image is albedo 0.8 * (ambient + (1 - ambient) V max(0, n.l)) with
        // n = `tilted` (flat: +y), l towards the light's centre.
        const glm::vec3 light = floorScene(tilted).light.center;
        int floorPixels = 0, wrongSmooth = 0, wrongFlat = 0, changed = 0;
        for (int i = 0; i < kSize * kSize; ++i) {
            const float v = flat.visibility.data[i];
            const glm::vec3 p(flat.position.data[3 * i], flat.position.data[3 * i + 1],
                              flat.position.data[3 * i + 2]);
            if (std::isnan(v) || std::abs(p.y) > 1e-4f) continue; // not the floor
            ++floorPixels;
            const glm::vec3 l = glm::normalize(light - p);
            const auto expected = [&](const glm::vec3& n) {
                const float c = 0.8f * (defaults.ambient +
                                        (1.0f - defaults.ambient) * v *
                                            std::max(glm::dot(n, l), 0.0f));
                return 255.0f * srgb(c * defaults.exposure);
            };
            wrongSmooth += std::abs(float(smooth.image[4 * i]) - expected(tilted)) > 1.5f;
            wrongFlat += std::abs(float(flat.image[4 * i]) - expected({0, 1, 0})) > 1.5f;
            changed += smooth.image[4 * i] != flat.image[4 * i];
        }
        EXPECT_GT(floorPixels, kSize * kSize / 4);
        EXPECT_EQ(wrongSmooth, 0) << "of " << floorPixels << " floor pixels";
        EXPECT_EQ(wrongFlat, 0) << "of " << floorPixels << " floor pixels";
        EXPECT_GT(changed, floorPixels / 2);
    }
}

} // namespace
