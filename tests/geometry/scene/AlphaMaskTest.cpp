// Alpha-masked materials (geometry/scene/AlphaMask.h) and the ray tracer's alpha filter.
#include <geometry/scene/AlphaMask.h>
#include <geometry/reference/Framing.h>
#include <geometry/reference/RayTracer.h>
#include <geometry/scene/GltfLoader.h>
#include <geometry/scene/Scene.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

namespace {

// width x 1 texture with the given alphas (colour white).
geometry::TextureImage alphaRow(const std::vector<int>& alphas) {
    geometry::TextureImage image;
    image.width = static_cast<int>(alphas.size());
    image.height = 1;
    for (const int a : alphas) {
        image.rgba8.insert(image.rgba8.end(), {255, 255, 255, static_cast<std::uint8_t>(a)});
    }
    return image;
}

TEST(AlphaMaskTest, SampleIsBilinearBetweenTexelCentresAndWraps) {
    const geometry::TextureImage image = alphaRow({0, 255, 255, 51});
    EXPECT_FLOAT_EQ(geometry::sampleAlpha(image, {0.125f, 0.5f}), 0.0f); // texel 0's centre
    EXPECT_FLOAT_EQ(geometry::sampleAlpha(image, {0.375f, 0.5f}), 1.0f); // texel 1's centre
    EXPECT_NEAR(geometry::sampleAlpha(image, {0.25f, 0.5f}), 0.5f, 1e-6f);  // halfway 0 .. 1
    // Repeat: u = 0 lies halfway between texel 3 (0.2) and texel 0 (0), like u = 1 and u = -1.
    EXPECT_NEAR(geometry::sampleAlpha(image, {0.0f, 0.5f}), 0.1f, 1e-6f);
    EXPECT_NEAR(geometry::sampleAlpha(image, {1.0f, 0.5f}), 0.1f, 1e-6f);
    EXPECT_NEAR(geometry::sampleAlpha(image, {-3.0f, 7.25f}), 0.1f, 1e-5f);
    // Huge or non-finite UVs do not overflow; an empty image is opaque.
    EXPECT_TRUE(std::isfinite(geometry::sampleAlpha(image, {1e30f, -1e30f})));
    EXPECT_EQ(geometry::sampleAlpha(image, {NAN, 0.0f}), 1.0f);
    EXPECT_EQ(geometry::sampleAlpha(geometry::TextureImage{}, {0.3f, 0.3f}), 1.0f);
}

geometry::MeshData maskedTriangle(geometry::AlphaMode mode, float cutoff, float factor) {
    geometry::MeshData mesh;
    mesh.positions = {{0, 0, 0}, {1, 0, 0}, {0, 0, 1}};
    mesh.texcoords = {{0.125f, 0.5f}, {0.375f, 0.5f}, {0.125f, 0.5f}};
    mesh.triangles = {{0, 1, 2}};
    mesh.triangleMaterial = {0};
    geometry::Material m;
    m.alphaMode = mode;
    m.alphaCutoff = cutoff;
    m.baseColor.a = factor;
    m.baseColorTexture = 0;
    mesh.materials = {m};
    mesh.textures = {alphaRow({0, 255, 255, 51})};
    return mesh;
}

TEST(AlphaMaskTest, CutoffFactorAndModes) {
    using geometry::AlphaMode;
    // Barycentric (u, v): uv = texcoord interpolation; u = 0.6 -> uv.x = 0.125 + 0.6 * 0.25 = 0.275:
    // texture alpha 0.6.
    const glm::vec2 at06(0.6f, 0.0f);
    EXPECT_NEAR(geometry::surfaceAlpha(maskedTriangle(AlphaMode::Mask, 0.5f, 1.0f), 0, at06), 0.6f,
                1e-5f);
    EXPECT_TRUE(geometry::surfaceOccludes(maskedTriangle(AlphaMode::Mask, 0.5f, 1.0f), 0, at06));
    EXPECT_FALSE(geometry::surfaceOccludes(maskedTriangle(AlphaMode::Mask, 0.7f, 1.0f), 0, at06));
    // The factor multiplies: 0.6 * 0.5 = 0.3 < 0.5.
    EXPECT_FALSE(geometry::surfaceOccludes(maskedTriangle(AlphaMode::Mask, 0.5f, 0.5f), 0, at06));
    // BLEND is MASK at 0.5 whatever its cutoff says; OPAQUE always occludes.
    EXPECT_TRUE(geometry::surfaceOccludes(maskedTriangle(AlphaMode::Blend, 0.9f, 1.0f), 0, at06));
    EXPECT_FALSE(geometry::surfaceOccludes(maskedTriangle(AlphaMode::Blend, 0.1f, 1.0f), 0,
                                           glm::vec2(0.2f, 0.0f)));
    EXPECT_TRUE(geometry::surfaceOccludes(maskedTriangle(AlphaMode::Opaque, 0.5f, 0.0f), 0,
                                          glm::vec2(0.0f)));
    EXPECT_TRUE(geometry::hasAlphaMask(maskedTriangle(AlphaMode::Blend, 0.5f, 1.0f)));
    EXPECT_FALSE(geometry::hasAlphaMask(maskedTriangle(AlphaMode::Opaque, 0.5f, 1.0f)));
}

// A card at y = 2 over x, z in [-1, 1] whose texture is transparent on its half x < 0 (u < 0.5)
// and opaque on x > 0, under a square light: ray traced, it must shadow exactly like an opaque
// card covering x in [0, 1] only.
geometry::Scene cardScene(bool masked) {
    geometry::Scene scene;
    scene.light.center = {0.0f, 6.0f, 0.0f};
    scene.light.u = {0.5f, 0.0f, 0.0f};
    scene.light.v = {0.0f, 0.0f, 0.5f};
    geometry::MeshData floor;
    floor.positions = {{-10, 0, -10}, {10, 0, -10}, {10, 0, 10}, {-10, 0, 10}};
    floor.triangles = {{0, 1, 2}, {0, 2, 3}};
    scene.objects.push_back({"floor", geometry::ShadowMethod::Auto, floor});
    geometry::MeshData card;
    const float x0 = masked ? -1.0f : 0.0f;
    card.positions = {{x0, 2, -1}, {1, 2, -1}, {1, 2, 1}, {x0, 2, 1}};
    card.triangles = {{0, 1, 2}, {0, 2, 3}};
    if (masked) {
        card.texcoords = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
        card.triangleMaterial = {0, 0};
        geometry::Material m;
        m.alphaMode = geometry::AlphaMode::Mask;
        m.alphaCutoff = 0.5f;
        m.baseColorTexture = 0;
        card.materials = {m};
        // 16 texels: alpha 0 then 255; at u = 0.5 the bilinear alpha is exactly 0.5 (occludes),
        // the card's repeat seam at u = 0 blends texel 15 (255) with texel 0 (0) over 1/32.
        std::vector<int> alphas(16, 0);
        std::fill(alphas.begin() + 8, alphas.end(), 255);
        card.textures = {alphaRow(alphas)};
    }
    scene.objects.push_back({"card", geometry::ShadowMethod::Auto, card});
    return scene;
}

TEST(AlphaMaskTest, RaytraceSeesThroughTheMaskedHalfOfACard) {
    const geometry::RayTracer masked(cardScene(true)), half(cardScene(false));
    std::vector<glm::vec3> points, normals;
    for (int j = 0; j < 24; ++j)
        for (int i = 0; i < 24; ++i) {
            points.emplace_back(-3.0f + 6.0f * (i + 0.5f) / 24.0f, 0.0f,
                                -3.0f + 6.0f * (j + 0.5f) / 24.0f);
            normals.emplace_back(0.0f, 1.0f, 0.0f);
        }
    geometry::RayTraceSettings settings;
    settings.samples = 256;
    std::vector<float> vm(points.size()), vh(points.size());
    masked.visibility(cardScene(true).light, points, normals, settings, vm);
    half.visibility(cardScene(false).light, points, normals, settings, vh);
    float maxDiff = 0.0f, minV = 1.0f, maxV = 0.0f;
    for (std::size_t i = 0; i < points.size(); ++i) {
        maxDiff = std::max(maxDiff, std::abs(vm[i] - vh[i]));
        minV = std::min(minV, vm[i]);
        maxV = std::max(maxV, vm[i]);
    }
    // Same samples, same occluded region but for the seam sliver at x = -1 (u < 1/32, alpha
    // above the cutoff only at u = 0 itself): at most a couple of samples differ.
    EXPECT_LE(maxDiff, 2.0f / 256.0f);
    EXPECT_EQ(minV, 0.0f); // under the opaque half
    EXPECT_EQ(maxV, 1.0f);

    // Hard visibility from the centre, under each half (away from the edges).
    std::vector<glm::vec3> p = {{-0.75f, 0.0f, 0.0f}, {0.75f, 0.0f, 0.0f}};
    std::vector<glm::vec3> n(2, glm::vec3(0.0f, 1.0f, 0.0f));
    std::vector<float> hv(2);
    masked.hardVisibility(cardScene(true).light.center, p, n, settings, hv);
    EXPECT_EQ(hv[0], 1.0f); // through the transparent half
    EXPECT_EQ(hv[1], 0.0f);
    // And a primary ray through the hole misses the card, hitting the floor.
    float t = 0.0f;
    glm::vec3 normal;
    ASSERT_TRUE(masked.intersect({-0.5f, 5.0f, 0.0f}, {0.0f, -1.0f, 0.0f}, t, normal));
    EXPECT_NEAR(t, 5.0f, 1e-4f);
    ASSERT_TRUE(masked.intersect({0.5f, 5.0f, 0.0f}, {0.0f, -1.0f, 0.0f}, t, normal));
    EXPECT_NEAR(t, 3.0f, 1e-4f);
}

} // namespace

// A level with a grate: loading splits it into its opaque triangles and its alpha-tested ones
// (geometry::splitByAlphaTest), so that a shadow path is chosen per part. Together they are the
// file's triangles, each once, at the same positions and with the same materials.
TEST(AlphaMaskTest, TexturedLevelLoadsAsOpaqueAndAlphaTestedParts) {
    const std::filesystem::path file =
        std::filesystem::path(PENUMBRA_SHARED_DIR) / "levels" / "textured" / "kaos2.glb";
    const geometry::MeshData whole = geometry::loadGltf(file);
    const geometry::Scene scene = geometry::loadScene(file);
    ASSERT_EQ(scene.objects.size(), 2u);
    const geometry::SceneObject& opaque = scene.objects[0];
    const geometry::SceneObject& tested = scene.objects[1];
    EXPECT_EQ(opaque.name, "kaos2.glb");
    EXPECT_EQ(tested.name, std::string("kaos2.glb") + geometry::kAlphaTestedSuffix);
    EXPECT_FALSE(geometry::hasAlphaMask(opaque.mesh));
    EXPECT_TRUE(geometry::hasAlphaMask(tested.mesh));
    EXPECT_GT(tested.mesh.triangles.size(), 0u);
    EXPECT_EQ(opaque.mesh.triangles.size() + tested.mesh.triangles.size(), whole.triangles.size());
    EXPECT_EQ(opaque.mesh.texcoords.size(), opaque.mesh.positions.size());
    // Walk the file's triangles in order: each is the next of the part its material says.
    std::size_t next[2] = {0, 0};
    for (std::size_t t = 0; t < whole.triangles.size(); ++t) {
        const std::uint32_t m = whole.triangleMaterial[t];
        const int side = geometry::isAlphaMasked(whole.materials[m]) ? 1 : 0;
        const geometry::MeshData& part = scene.objects[side].mesh;
        const std::size_t u = next[side]++;
        ASSERT_LT(u, part.triangles.size());
        const geometry::Material& a = part.materials[part.triangleMaterial[u]];
        const geometry::Material& b = whole.materials[m];
        EXPECT_EQ(a.name, b.name);
        EXPECT_EQ(a.alphaMode, b.alphaMode);
        ASSERT_EQ(a.baseColorTexture >= 0, b.baseColorTexture >= 0);
        if (a.baseColorTexture >= 0) {
            EXPECT_EQ(part.textures[a.baseColorTexture].rgba8,
                      whole.textures[b.baseColorTexture].rgba8);
        }
        for (int k = 0; k < 3; ++k) {
            EXPECT_EQ(part.positions[part.triangles[u][k]], whole.positions[whole.triangles[t][k]]);
            EXPECT_EQ(part.texcoords[part.triangles[u][k]], whole.texcoords[whole.triangles[t][k]]);
        }
    }
    // Each part holds only its own materials: the grate's texture is not uploaded twice.
    EXPECT_EQ(opaque.mesh.materials.size() + tested.mesh.materials.size(), whole.materials.size());
    // The untextured file has no alpha-tested material: one object, as before.
    EXPECT_EQ(geometry::loadScene(file.parent_path().parent_path() / "kaos2.glb").objects.size(), 1u);
}

namespace {

// A floor under two untextured translucent cards (BLEND, alpha from the base-colour factor) at
// heights 2 and 3 that cover everything the light sees of the floor's middle, and an opaque
// material in the lower card's mesh beside it (its factor alpha must not count).
geometry::Scene translucentCards(float lowerAlpha, float upperAlpha) {
    geometry::Scene scene;
    scene.light.center = {0.0f, 6.0f, 0.0f};
    scene.light.u = {0.5f, 0.0f, 0.0f};
    scene.light.v = {0.0f, 0.0f, 0.5f};
    geometry::MeshData floor;
    floor.positions = {{-10, 0, -10}, {10, 0, -10}, {10, 0, 10}, {-10, 0, 10}};
    floor.triangles = {{0, 1, 2}, {0, 2, 3}};
    scene.objects.push_back({"floor", geometry::ShadowMethod::Auto, floor});
    const auto card = [](float y, float alpha, bool opaqueSide) {
        geometry::MeshData m;
        m.positions = {{-5, y, -5}, {5, y, -5}, {5, y, 5}, {-5, y, 5}};
        m.triangles = {{0, 1, 2}, {0, 2, 3}};
        geometry::Material blend;
        blend.alphaMode = geometry::AlphaMode::Blend;
        blend.baseColor.a = alpha;
        m.materials = {blend};
        m.triangleMaterial = {0, 0};
        if (opaqueSide) { // a card of an opaque material at x in [5.2, 6.2], factor alpha 0.3
            geometry::Material opaque;
            opaque.baseColor.a = 0.3f;
            m.materials.push_back(opaque);
            m.positions.insert(m.positions.end(),
                               {{5.2f, y, -1}, {6.2f, y, -1}, {6.2f, y, 1}, {5.2f, y, 1}});
            m.triangles.insert(m.triangles.end(), {{4, 5, 6}, {4, 6, 7}});
            m.triangleMaterial.insert(m.triangleMaterial.end(), {1, 1});
        }
        return m;
    };
    scene.objects.push_back({"lower", geometry::ShadowMethod::Auto, card(2.0f, lowerAlpha, true)});
    scene.objects.push_back({"upper", geometry::ShadowMethod::Auto, card(3.0f, upperAlpha, false)});
    return scene;
}

} // namespace

TEST(AlphaMaskTest, TransmittanceRuleMultipliesOneMinusAlphaAlongEachRay) {
    const geometry::Scene scene = translucentCards(0.5f, 0.25f);
    const geometry::RayTracer tracer(scene);
    const std::vector<glm::vec3> points = {{0.0f, 0.0f, 0.0f},  // under both cards
                                           {8.5f, 0.0f, 0.0f},  // the opaque part hides
                                           {0.0f, 2.5f, 0.0f}}; // between the cards
    const std::vector<glm::vec3> normals(points.size(), glm::vec3(0.0f, 1.0f, 0.0f));
    geometry::RayTraceSettings settings;
    settings.samples = 64;
    std::vector<float> tested(points.size()), transmitted(points.size());
    tracer.visibility(scene.light, points, normals, settings, tested);
    settings.transmittance = true;
    tracer.visibility(scene.light, points, normals, settings, transmitted);
    // The alpha test: BLEND cuts at 0.5, so the lower card (0.5) hides the light, the upper
    // (0.25) lets all of it through.
    EXPECT_EQ(tested[0], 0.0f);
    EXPECT_EQ(tested[2], 1.0f);
    // Transmittance: (1 - 0.5)(1 - 0.25) under both, 0.75 under the upper one only; an opaque
    // material hides whatever its factor alpha says.
    EXPECT_NEAR(transmitted[0], 0.375f, 1e-5f);
    EXPECT_EQ(transmitted[1], 0.0f);
    EXPECT_EQ(tested[1], 0.0f);
    EXPECT_NEAR(transmitted[2], 0.75f, 1e-5f);
}

TEST(AlphaMaskTest, SurfacesAlongARayInOrderToTheFirstOpaqueOne) {
    const geometry::Scene scene = translucentCards(0.5f, 0.25f);
    const geometry::RayTracer tracer(scene);
    std::vector<geometry::SurfaceHit> hits;
    // Down the cards' shared diagonal: both triangles of each card report the crossing, which
    // is one.
    tracer.surfacesAlong({0.0f, 6.0f, 0.0f}, {0.0f, -1.0f, 0.0f}, 0.0f, 100.0f, hits);
    ASSERT_EQ(hits.size(), 3u);
    EXPECT_NEAR(hits[0].t, 3.0f, 1e-4f);
    EXPECT_FLOAT_EQ(hits[0].alpha, 0.25f);
    EXPECT_NEAR(hits[1].t, 4.0f, 1e-4f);
    EXPECT_FLOAT_EQ(hits[1].alpha, 0.5f);
    EXPECT_NEAR(hits[2].t, 6.0f, 1e-4f); // the floor
    EXPECT_EQ(hits[2].alpha, 1.0f);
    EXPECT_GT(std::abs(hits[2].normal.y), 0.0f);
    // Within tfar only; a ray through the opaque part ends there.
    tracer.surfacesAlong({0.0f, 6.0f, 0.0f}, {0.0f, -1.0f, 0.0f}, 0.0f, 3.5f, hits);
    ASSERT_EQ(hits.size(), 1u);
    tracer.surfacesAlong({5.7f, 6.0f, 0.0f}, {0.0f, -1.0f, 0.0f}, 0.0f, 100.0f, hits);
    ASSERT_EQ(hits.size(), 1u);
    EXPECT_NEAR(hits[0].t, 4.0f, 1e-4f);
    EXPECT_EQ(hits[0].alpha, 1.0f);
    // The tracer of some objects only: without the floor the ray leaves after the cards.
    const std::size_t cards[] = {1, 2};
    const geometry::RayTracer cardsOnly(scene, cards);
    cardsOnly.surfacesAlong({0.0f, 6.0f, 0.0f}, {0.0f, -1.0f, 0.0f}, 0.0f, 100.0f, hits);
    EXPECT_EQ(hits.size(), 2u);
    const std::size_t bad[] = {7};
    EXPECT_THROW(geometry::RayTracer(scene, bad), std::invalid_argument);
}
