// Alpha-masked materials (geometry/scene/AlphaMask.h) and the ray tracer's alpha filter.
#include <geometry/scene/AlphaMask.h>
#include <geometry/reference/Framing.h>
#include <geometry/reference/RayTracer.h>
#include <geometry/scene/GltfLoader.h>
#include <geometry/scene/Scene.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
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

namespace {

// A card (two triangles) over x, z in [0, 4] at y = 1 with texcoords (0, 0) .. `uvMax` and a
// size x size texture transparent but for the texels `opaque` (x, y).
geometry::MeshData texturedCard(int size, const std::vector<glm::ivec2>& opaque, glm::vec2 uvMax,
                                geometry::TextureWrap wrap = geometry::TextureWrap::Repeat) {
    geometry::MeshData mesh;
    mesh.positions = {{0, 1, 0}, {4, 1, 0}, {4, 1, 4}, {0, 1, 4}};
    mesh.texcoords = {{0, 0}, {uvMax.x, 0}, {uvMax.x, uvMax.y}, {0, uvMax.y}};
    mesh.triangles = {{0, 1, 2}, {0, 2, 3}};
    mesh.triangleMaterial = {0, 0};
    geometry::Material m;
    m.alphaMode = geometry::AlphaMode::Mask;
    m.alphaCutoff = 0.5f;
    m.baseColorTexture = 0;
    mesh.materials = {m};
    geometry::TextureImage image;
    image.width = image.height = size;
    image.rgba8.assign(static_cast<std::size_t>(size) * size * 4, 255);
    for (std::size_t i = 3; i < image.rgba8.size(); i += 4) image.rgba8[i] = 20;
    for (const glm::ivec2 t : opaque)
        image.rgba8[(static_cast<std::size_t>(t.y) * size + t.x) * 4 + 3] = 240;
    image.wrapS = image.wrapT = wrap;
    mesh.textures = {image};
    return mesh;
}

// Every point of a fine barycentric grid over each triangle that occludes lies in its
// occlusionBounds; returns how many did.
std::size_t expectOccludersInsideBounds(const geometry::MeshData& mesh) {
    std::size_t occluding = 0;
    constexpr int n = 300;
    for (std::uint32_t t = 0; t < mesh.triangles.size(); ++t) {
        const geometry::Aabb box = geometry::occlusionBounds(mesh, t);
        const glm::uvec3 tri = mesh.triangles[t];
        for (int i = 0; i <= n; ++i)
            for (int j = 0; i + j <= n; ++j) {
                const glm::vec2 b(float(i) / n, float(j) / n);
                if (!geometry::surfaceOccludes(mesh, t, b)) continue;
                ++occluding;
                const glm::vec3 p = (1.0f - b.x - b.y) * mesh.positions[tri.x] +
                                    b.x * mesh.positions[tri.y] + b.y * mesh.positions[tri.z];
                EXPECT_FALSE(box.empty()) << "triangle " << t;
                EXPECT_TRUE(glm::all(glm::greaterThanEqual(p, box.min)) &&
                            glm::all(glm::lessThanEqual(p, box.max)))
                    << "triangle " << t << " point " << p.x << " " << p.y << " " << p.z;
            }
    }
    return occluding;
}

} // namespace

// The reach test of pcss's alpha path boxes an alpha-tested triangle around its opaque texels
// only (a light beam or flame card around a lamp is mostly cut away): every occluding point is
// inside its box, which is far smaller than the triangle's where few texels are opaque.
TEST(AlphaMaskTest, OcclusionBoundsHoldEveryOccludingPointAndLittleElse) {
    // One opaque texel of 16 x 16 at (3, 12): u in [3/16, 4/16], v in [12/16, 13/16] (x = 4u,
    // z = 4v), grown by the bilinear footprint (half a texel each way, and the next texel's).
    const geometry::MeshData one = texturedCard(16, {{3, 12}}, {1, 1});
    EXPECT_GT(expectOccludersInsideBounds(one), 100u);
    geometry::Aabb both;
    for (std::uint32_t t = 0; t < 2; ++t)
        if (const geometry::Aabb b = geometry::occlusionBounds(one, t); !b.empty()) both.extend(b);
    ASSERT_FALSE(both.empty());
    const glm::vec3 e = both.max - both.min;
    std::printf("  one opaque texel of 16 x 16 on a 4 x 4 card: bounds %.3f x %.3f x %.3f\n", e.x,
                e.y, e.z);
    EXPECT_LE(e.x, 3.0f * 4.0f / 16.0f + 1e-3f); // at most 3 texels wide, not the card's 4
    EXPECT_LE(e.z, 3.0f * 4.0f / 16.0f + 1e-3f);
    EXPECT_LE(e.y, 1e-3f);
    EXPECT_LE(both.min.x, 3.0f / 4.0f); // and around the texel
    EXPECT_GE(both.max.x, 1.0f);

    // Nothing opaque: no box; an opaque material, or the factor alone: the triangle's.
    const geometry::MeshData none = texturedCard(16, {}, {1, 1});
    EXPECT_TRUE(geometry::occlusionBounds(none, 0).empty());
    EXPECT_TRUE(geometry::occlusionBounds(none, 1).empty());
    geometry::MeshData opaque = none;
    opaque.materials[0].alphaMode = geometry::AlphaMode::Opaque;
    EXPECT_EQ(geometry::occlusionBounds(opaque, 0).min, glm::vec3(0, 1, 0));
    EXPECT_EQ(geometry::occlusionBounds(opaque, 0).max, glm::vec3(4, 1, 4));
    geometry::MeshData untextured = none;
    untextured.materials[0].baseColorTexture = -1;
    EXPECT_FALSE(geometry::occlusionBounds(untextured, 0).empty()); // factor 1 >= 0.5
    untextured.materials[0].baseColor.a = 0.4f;
    EXPECT_TRUE(geometry::occlusionBounds(untextured, 0).empty());
    // The transmittance rule (deep-sm): every texel above 0 hides some light, so the cut-away
    // texels (alpha 20) count; a texture of zeros but one texel bounds that texel.
    using geometry::AlphaRule;
    const geometry::Aabb faint = geometry::occlusionBounds(none, 0, AlphaRule::Transmittance);
    EXPECT_LE(faint.min.x, 0.0f); // the whole triangle: x, z in [0, 4]
    EXPECT_GE(faint.max.x, 4.0f);
    EXPECT_GE(faint.max.z, 4.0f);
    geometry::MeshData zeros = one;
    for (std::size_t i = 3; i < zeros.textures[0].rgba8.size(); i += 4)
        if (zeros.textures[0].rgba8[i] == 20) zeros.textures[0].rgba8[i] = 0;
    for (std::uint32_t t = 0; t < 2; ++t) {
        const geometry::Aabb c = geometry::occlusionBounds(zeros, t);
        const geometry::Aabb r = geometry::occlusionBounds(zeros, t, AlphaRule::Transmittance);
        EXPECT_EQ(c.empty(), r.empty());
        if (!c.empty()) {
            EXPECT_EQ(c.min, r.min);
        }
    }
    // The factor scales the texels: 240 * 0.5 / 255 < 0.5 cuts the opaque texel too.
    geometry::MeshData faded = one;
    faded.materials[0].baseColor.a = 0.5f;
    EXPECT_TRUE(geometry::occlusionBounds(faded, 0).empty());
    EXPECT_TRUE(geometry::occlusionBounds(faded, 1).empty());
}

// Wrapped, transformed and huge texcoords: still every occluding point inside.
TEST(AlphaMaskTest, OcclusionBoundsFollowWrapModesTransformsAndLimits) {
    using geometry::TextureWrap;
    const std::vector<glm::ivec2> texels = {{0, 0}, {7, 3}, {2, 6}};
    for (const TextureWrap wrap :
         {TextureWrap::Repeat, TextureWrap::ClampToEdge, TextureWrap::MirroredRepeat}) {
        SCOPED_TRACE(static_cast<int>(wrap));
        // Three repeats across the card and a half below 0.
        geometry::MeshData mesh = texturedCard(8, texels, {3.0f, 2.5f}, wrap);
        mesh.texcoords[0] = {-0.5f, -0.5f};
        mesh.texcoords[1].y = -0.5f;
        mesh.texcoords[3].x = -0.5f;
        EXPECT_GT(expectOccludersInsideBounds(mesh), 100u);
        // KHR_texture_transform: rotated and offset.
        const float c = std::cos(0.7f), s = std::sin(0.7f);
        mesh.materials[0].baseColorUvTransform =
            glm::mat3(glm::vec3(c, s, 0), glm::vec3(-s, c, 0), glm::vec3(0.3f, -1.7f, 1));
        EXPECT_GT(expectOccludersInsideBounds(mesh), 100u);
    }
    // Past kOcclusionBoundsTexels texels (a texture repeated 1000 times): the triangle's box.
    const geometry::MeshData tiled = texturedCard(8, texels, {1000.0f, 1000.0f});
    EXPECT_EQ(geometry::occlusionBounds(tiled, 0).min, glm::vec3(0, 1, 0));
    EXPECT_EQ(geometry::occlusionBounds(tiled, 0).max, glm::vec3(4, 1, 4));
    // Every corner at one texcoord: the triangle's box where that texel is opaque, none where not.
    geometry::MeshData point = texturedCard(8, texels, {1, 1});
    point.texcoords = std::vector<glm::vec2>(4, glm::vec2(7.5f / 8.0f, 3.5f / 8.0f));
    EXPECT_EQ(geometry::occlusionBounds(point, 0).max, glm::vec3(4, 1, 4));
    point.texcoords = std::vector<glm::vec2>(4, glm::vec2(4.5f / 8.0f, 4.5f / 8.0f));
    EXPECT_TRUE(geometry::occlusionBounds(point, 0).empty());
    // Non-finite texcoords: the triangle's box (sampleAlpha reads them as opaque).
    point.texcoords[0].x = NAN;
    EXPECT_EQ(geometry::occlusionBounds(point, 0).max, glm::vec3(4, 1, 4));
}
