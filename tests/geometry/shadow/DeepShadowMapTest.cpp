// The deep-sm method's map (geometry/shadow/DeepShadowMap.h), built by tracing the casters
// (geometry::RayTracer::surfacesAlong) in pcss's frame:
// - each texel's function is the transmittance along its ray (the product of 1 - alpha of the
//   surfaces in front), within the compression's bound, the 8-bit values included;
// - texels an edge crosses hold the share of their S x S rays the caster covers;
// - a surface is stored at its plane's depth along the texel's centre ray, so a tilted
//   receiver does not lie partly in front of itself;
// - bad settings are refused.
#include <geometry/reference/RayTracer.h>
#include <geometry/shadow/DeepShadowMap.h>
#include <geometry/shadow/PcssFrame.h>

#include "shared/Pdsm.h"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <vector>

namespace {

geometry::MeshData quad(glm::vec3 a, glm::vec3 b, glm::vec3 c, glm::vec3 d,
                        geometry::AlphaMode mode = geometry::AlphaMode::Opaque,
                        float alpha = 1.0f) {
    geometry::MeshData m;
    m.positions = {a, b, c, d};
    m.triangles = {{0, 1, 2}, {0, 2, 3}};
    geometry::Material material;
    material.alphaMode = mode;
    material.baseColor.a = alpha;
    m.materials = {material};
    m.triangleMaterial = {0, 0};
    return m;
}

// A floor (y = 0) under a light at y = 6 looking down, and casters above it.
geometry::Scene floorScene() {
    geometry::Scene scene;
    scene.light.center = {0.0f, 6.0f, 0.0f};
    scene.light.u = {0.5f, 0.0f, 0.0f};
    scene.light.v = {0.0f, 0.0f, 0.5f};
    scene.objects.push_back({"floor", geometry::ShadowMethod::Auto,
                             quad({-8, 0, -8}, {8, 0, -8}, {8, 0, 8}, {-8, 0, 8})});
    return scene;
}

struct Built {
    geometry::PcssFrame frame;
    geometry::DeepShadowMap map;
};

Built build(const geometry::Scene& scene, int resolution, int supersample) {
    std::vector<std::size_t> objects;
    geometry::Aabb bounds;
    for (std::size_t i = 0; i < scene.objects.size(); ++i) {
        objects.push_back(i);
        bounds.extend(scene.objects[i].mesh.bounds());
    }
    Built b;
    b.frame = geometry::fitPcssFrame(scene, objects);
    const geometry::RayTracer tracer(scene, objects);
    geometry::DeepShadowSettings settings;
    settings.resolution = resolution;
    settings.supersample = supersample;
    settings.threads = 2;
    b.map = geometry::buildDeepShadowMap(
        b.frame, bounds,
        [&](const glm::vec3& o, const glm::vec3& d, float tfar,
            std::vector<geometry::SurfaceHit>& out) {
            tracer.surfacesAlong(o, d, 0.0f, tfar, out);
        },
        settings);
    return b;
}

// T of the texel holding q's ray (face 0, along the light's normal) at depth z.
float transmittanceAt(const Built& b, const glm::vec3& q, float z) {
    const glm::vec2 uv = b.frame.textureCoord(q, 0);
    const int R = b.map.resolution;
    const int i = std::clamp(static_cast<int>(uv.x * R), 0, R - 1);
    const int j = std::clamp(static_cast<int>(uv.y * R), 0, R - 1);
    const geometry::DeepShadowFace& f = b.map.faces[0];
    return geometry::evaluateDeepShadowMap(b.map, 0, i, j, shader::pdsmDepthCode(z, f.zc, f.sFar));
}

TEST(DeepShadowMapTest, TexelsHoldTheTransmittanceAlongTheirRays) {
    geometry::Scene scene = floorScene();
    scene.objects.push_back(
        {"upper", geometry::ShadowMethod::Auto,
         quad({-2, 3, -2}, {2, 3, -2}, {2, 3, 2}, {-2, 3, 2}, geometry::AlphaMode::Blend, 0.25f)});
    scene.objects.push_back(
        {"lower", geometry::ShadowMethod::Auto,
         quad({-2, 2, -2}, {2, 2, -2}, {2, 2, 2}, {-2, 2, 2}, geometry::AlphaMode::Blend, 0.5f)});
    const Built b = build(scene, 64, 3);
    ASSERT_TRUE(b.map.faces[0].built);
    EXPECT_NEAR(b.map.faces[0].zc, 3.0f, 1e-3f); // the upper card's depth
    const float bound = 0.004f + 1e-5f;
    EXPECT_LE(b.map.stats.maxDeviation, 0.004f);
    for (const glm::vec3 q : {glm::vec3(0.3f, 0.0f, -0.7f), glm::vec3(-1.2f, 0.0f, 1.1f)}) {
        // Depth along the light's normal from y = 6: the cards at 3 and 4, the floor at 6.
        EXPECT_NEAR(transmittanceAt(b, q, 2.9f), 1.0f, bound);
        EXPECT_NEAR(transmittanceAt(b, q, 3.5f), 0.75f, bound);
        EXPECT_NEAR(transmittanceAt(b, q, 5.0f), 0.375f, bound);
        EXPECT_NEAR(transmittanceAt(b, q, 5.99f), 0.375f, bound);
        EXPECT_NEAR(transmittanceAt(b, q, 6.5f), 0.0f, bound); // past the floor
    }
    // Beside the cards, only the floor.
    EXPECT_NEAR(transmittanceAt(b, {6.0f, 0.0f, 6.0f}, 5.0f), 1.0f, bound);
    EXPECT_NEAR(transmittanceAt(b, {6.0f, 0.0f, 6.0f}, 6.5f), 0.0f, bound);
    EXPECT_GT(b.map.stats.rays, 0u);
    EXPECT_GT(b.map.stats.texelsStored, 0u);
}

TEST(DeepShadowMapTest, EdgeTexelsHoldTheShareOfTheirRaysTheCasterCovers) {
    // An opaque card at depth 3 whose edge crosses a column of texels 0.4 of a texel from its
    // side (the map's extent is the floor's, the receivers').
    geometry::Scene scene = floorScene();
    const geometry::PcssFrame floorOnly =
        geometry::fitPcssFrame(scene, std::vector<std::size_t>{0});
    const geometry::PcssFace& face = floorOnly.faces[0];
    const float edge = 3.0f * (face.lo.x + 32.4f * (face.hi.x - face.lo.x) / 64.0f);
    scene.objects.push_back({"card", geometry::ShadowMethod::Auto,
                             quad({edge, 3, -2}, {2, 3, -2}, {2, 3, 2}, {edge, 3, 2})});
    for (const int S : {1, 4}) {
        SCOPED_TRACE(S);
        const Built b = build(scene, 64, S);
        ASSERT_EQ(b.frame.faces[0].lo, face.lo);
        ASSERT_EQ(b.frame.faces[0].hi, face.hi);
        int partial = 0;
        float last = 1.0f;
        for (float x = -0.5f; x <= 0.5f; x += 0.01f) {
            const float t = transmittanceAt(b, {x, 0.0f, 0.4f}, 4.0f);
            EXPECT_LE(t, last + 0.005f) << x; // darker across the edge, never lighter
            last = t;
            if (t > 0.01f && t < 0.99f) {
                ++partial;
                // A share of S^2 rays, within the bound.
                const float rays = t * S * S;
                EXPECT_NEAR(rays, std::round(rays), 0.005f * S * S) << x;
            }
        }
        EXPECT_EQ(last, 0.0f);
        if (S == 1)
            EXPECT_EQ(partial, 0); // one ray per texel: all or nothing
        else
            EXPECT_GT(partial, 0);
    }
}

TEST(DeepShadowMapTest, ASurfaceLiesAtItsPlanesDepthAlongTheCentreRay) {
    // A tilted opaque floor, the light grazing it: with S x S rays spread over a texel, its
    // crossings span depths in front of and behind the centre ray's; each is stored at the
    // centre ray's, so T steps from 1 to 0 there and not over the span.
    geometry::Scene scene;
    scene.light.center = {0.0f, 6.0f, 0.0f};
    scene.light.u = {0.5f, 0.0f, 0.0f};
    scene.light.v = {0.0f, 0.0f, 0.5f};
    scene.objects.push_back({"slope", geometry::ShadowMethod::Auto,
                             quad({-4, 0, -4}, {4, 4, -4}, {4, 4, 4}, {-4, 0, 4})});
    const Built b = build(scene, 32, 4);
    const geometry::PcssFrame& f = b.frame;
    for (const glm::vec3 q : {glm::vec3(-2.0f, 1.0f, 0.3f), glm::vec3(2.5f, 3.25f, -1.0f)}) {
        // The texel's centre ray and where it meets the plane y = 2 + x / 2.
        const glm::vec2 uv = f.textureCoord(q, 0);
        const int R = b.map.resolution;
        const glm::vec2 ij = glm::floor(uv * static_cast<float>(R)) + 0.5f;
        const glm::vec2 m =
            f.faces[0].lo + ij / static_cast<float>(R) * (f.faces[0].hi - f.faces[0].lo);
        const glm::vec3 dir = m.x * f.faces[0].b1 + m.y * f.faces[0].b2 + f.faces[0].axis;
        // c + z dir on y = 2 + x / 2: 6 + z dir.y = 2 + z dir.x / 2.
        const float z = -4.0f / (dir.y - 0.5f * dir.x);
        EXPECT_NEAR(transmittanceAt(b, q, z * 0.999f), 1.0f, 0.005f);
        EXPECT_NEAR(transmittanceAt(b, q, z * 1.001f), 0.0f, 0.005f);
    }
}

TEST(DeepShadowMapTest, BadSettingsAreRefused) {
    const geometry::Scene scene = floorScene();
    const geometry::PcssFrame frame = geometry::fitPcssFrame(scene, std::vector<std::size_t>{0});
    const geometry::SurfaceQuery none = [](const glm::vec3&, const glm::vec3&, float,
                                           std::vector<geometry::SurfaceHit>& out) { out.clear(); };
    geometry::DeepShadowSettings s;
    s.resolution = 0;
    EXPECT_THROW(geometry::buildDeepShadowMap(frame, {}, none, s), std::invalid_argument);
    s.resolution = 16;
    s.supersample = 0;
    EXPECT_THROW(geometry::buildDeepShadowMap(frame, {}, none, s), std::invalid_argument);
    s.supersample = 2;
    s.tolerance = 0.001f; // below the 8-bit values' half step
    geometry::SurfaceQuery one = [](const glm::vec3&, const glm::vec3&, float,
                                    std::vector<geometry::SurfaceHit>& out) {
        out.assign(1, geometry::SurfaceHit{1.0f, 0.5f, glm::vec3(0.0f, 1.0f, 0.0f)});
    };
    EXPECT_THROW(geometry::buildDeepShadowMap(frame, {}, one, s), std::invalid_argument);
}

} // namespace
