// The occlusion-texture frame and lookup (geometry/shadow/OcclusionSlices.h):
// - eq. (4) through the fitted frustum: a square occluder parallel to the light, lying on a
//   slice's lookup plane, gives the closed-form visibility exactly when its texture footprint is
//   box-filtered with the kernel sliceLookup returns;
// - the fade is continuous in depth and never looks up the slice containing the point;
// - the fit keeps every receiver in the frustum (or caps the frustum's growth), and the depth
//   range holds exactly the casters inside it; the slicing projection lands where textureCoord
//   says.
#include <geometry/reference/Analytic.h>
#include <geometry/shadow/OcclusionSlices.h>
#include <geometry/scene/Primitives.h>
#include <geometry/scene/Scene.h>
#include <geometry/reference/Framing.h>
#include <shared/Horizon.h>

#include "TestRandom.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <vector>

namespace {

using geometry::OcclusionFrame;

geometry::Scene loadData(const char* name) {
    return geometry::loadScene(std::filesystem::path(PENUMBRA_SOURCE_DIR) / "data" / name);
}

std::vector<std::size_t> allObjects(const geometry::Scene& scene) {
    std::vector<std::size_t> all(scene.objects.size());
    for (std::size_t i = 0; i < all.size(); ++i) all[i] = i;
    return all;
}

// Area of [a0, a1] ∩ [b0, b1] in 2D.
double overlap(glm::dvec2 a0, glm::dvec2 a1, glm::dvec2 b0, glm::dvec2 b1) {
    const glm::dvec2 lo = glm::max(a0, b0), hi = glm::min(a1, b1);
    return std::max(0.0, hi.x - lo.x) * std::max(0.0, hi.y - lo.y);
}

TEST(OcclusionSlices, KernelOfAParallelSquareIsTheClosedForm) {
    geometry::Scene scene;
    scene.light = {.center = {0.0f, 3.0f, 0.0f}, .u = {0.5f, 0.0f, 0.0f}, .v = {0.0f, 0.0f, 0.5f}};
    OcclusionFrame f;
    f.center = scene.light.center;
    f.axis = {0.0f, -1.0f, 0.0f};
    f.uStar = {2.0f, 0.0f, 0.0f};
    f.vStar = {0.0f, 0.0f, 2.0f};
    f.copDistance = 0.7f;
    f.slices = 8;
    // Slice 2's lookup plane at depth 2 (y = 1), where the occluder lies.
    f.zNear = 2.0f - 2.5f * 0.125f;
    f.zFar = f.zNear + 8 * 0.125f;
    f.empty = false;
    ASSERT_NEAR(f.planeDepth(2), 2.0f, 1e-6f);
    const geometry::HorizontalRect occluder{-0.4f, 0.6f, -0.5f, 0.3f, 1.0f};
    const glm::dvec2 o0(f.textureCoord({occluder.x0, occluder.y, occluder.z0}));
    const glm::dvec2 o1(f.textureCoord({occluder.x1, occluder.y, occluder.z1}));
    auto boxMean = [&](int k, glm::vec2 c, float w) {
        if (k != 2) return 0.0;
        const glm::dvec2 h(0.5 * w);
        return overlap(glm::dvec2(c) - h, glm::dvec2(c) + h, o0, o1) / (double(w) * w);
    };
    testutil::Rng rng(7);
    double worst = 0.0;
    int penumbra = 0;
    for (int i = 0; i < 2000; ++i) {
        // Receivers at least two slices below the occluder: slice 2 fully weighted.
        const glm::vec3 p(rng.uniform(-1.5, 1.5), rng.uniform(-0.5, 0.7), rng.uniform(-1.5, 1.5));
        ASSERT_FLOAT_EQ(geometry::sliceLookup(f, p, 2).weight, 1.0f);
        const double v = geometry::occlusionVisibility(f, p, boxMean);
        const double exact = geometry::visibilityParallelRects(scene.light, {&occluder, 1}, p);
        worst = std::max(worst, std::abs(v - exact));
        penumbra += exact > 0.01 && exact < 0.99;
    }
    std::printf("  max |model - closed form| over 2000 points: %.2e (%d in penumbra)\n", worst,
                penumbra);
    EXPECT_GT(penumbra, 500);
    EXPECT_LT(worst, 2e-5); // float kernel arithmetic, nothing else
}

TEST(OcclusionSlices, FadeIsContinuousAndSkipsTheContainingSlice) {
    OcclusionFrame f;
    f.zNear = 1.0f;
    f.zFar = 3.0f;
    f.slices = 8;
    f.empty = false;
    const float dz = 1e-3f;
    std::vector<float> previous(f.slices, 0.0f);
    for (float z = 0.5f; z < 3.6f; z += dz) {
        const glm::vec3 p = f.center + z * f.axis;
        const float u = (z - f.zNear) / f.sliceDepth();
        for (int k = 0; k < f.slices; ++k) {
            const float w = geometry::sliceLookup(f, p, k).weight;
            // Continuous: a slice's weight moves by at most dz / sliceDepth per step.
            if (z > 0.5f) {
                EXPECT_LE(std::abs(w - previous[k]), 1.01f * dz / f.sliceDepth());
            }
            previous[k] = w;
            if (u >= 0.0f && u < f.slices && k == static_cast<int>(std::floor(u))) {
                EXPECT_EQ(w, 0.0f) << "the slice containing P, z " << z;
            }
            if (k + 2 <= std::floor(u)) {
                EXPECT_EQ(w, 1.0f) << "k " << k << " z " << z;
            }
        }
    }
}

TEST(OcclusionSlices, FitKeepsReceiversInsideAndSpansTheCasters) {
    const geometry::Scene scene = loadData("parallel-square.json");
    const auto all = allObjects(scene);
    const OcclusionFrame f = geometry::fitOcclusionFrame(scene, all, 8);
    ASSERT_FALSE(f.empty);
    EXPECT_NEAR(glm::dot(f.axis, glm::vec3(0, -1, 0)), 1.0f, 1e-6f); // towards the floor
    // The occluder at y = 1 and the floor at y = 0 under a light at y = 3.
    EXPECT_NEAR(f.zNear, 2.0f, 1e-5f);
    EXPECT_NEAR(f.zFar, 3.0f, 1e-5f);
    // The 6 m floor's corners need 1 + 3 / d >= 6 light sizes: d = 0.6, under the cap.
    EXPECT_NEAR(f.copDistance, 0.6f, 1e-4f);
    for (const auto& o : scene.objects)
        for (const glm::vec3& q : o.mesh.positions) {
            const glm::vec2 t = f.textureCoord(q);
            EXPECT_GE(t.x, -1e-5f);
            EXPECT_LE(t.x, 1.0f + 1e-5f);
            EXPECT_GE(t.y, -1e-5f);
            EXPECT_LE(t.y, 1.0f + 1e-5f);
        }
}

TEST(OcclusionSlices, FitCapsTheFrustumAndDropsCastersOutsideIt) {
    geometry::Scene scene = loadData("parallel-square.json");
    // A slab far to the side at shallow depth: containing it would need a frustum of ~100 light
    // sizes; under the cap of 16 it lies outside and must not widen the depth range.
    scene.objects.push_back({"far box", geometry::ShadowMethod::Auto,
                             geometry::makeBox({40.0f, 2.5f, 0.0f}, {1.0f, 0.2f, 1.0f})});
    const auto all = allObjects(scene);
    const OcclusionFrame f = geometry::fitOcclusionFrame(scene, all, 8);
    EXPECT_NEAR(f.magnification(3.0f), 16.0f, 1e-3f); // capped at the deepest receiver
    EXPECT_NEAR(f.zNear, 2.0f, 1e-5f);
    EXPECT_NEAR(f.zFar, 3.0f, 1e-5f);
    // Only the occluder as caster: its own depth, with a minimum thickness.
    const std::size_t occluder[] = {1};
    const OcclusionFrame g = geometry::fitOcclusionFrame(scene, occluder, 8);
    EXPECT_NEAR(g.zNear, 2.0f, 1e-5f);
    EXPECT_GT(g.zFar, g.zNear);
    EXPECT_LT(g.zFar, 2.01f);
    // No caster in front of the light: an empty frame (V = 1).
    const std::size_t none[] = {2};
    scene.objects[2].mesh = geometry::makeBox({0.0f, 4.0f, 0.0f}, {0.5f, 0.2f, 0.5f});
    EXPECT_TRUE(geometry::fitOcclusionFrame(scene, none, 8).empty);
}

// covers: in front of the light and inside the frustum, i.e. exactly where textureCoord lands
// in [0, 1]^2; the fit says whether any receiver is not covered (the method then shadows those
// from pcss's maps).
TEST(OcclusionSlices, CoversIsTheFrustumInFrontOfTheLight) {
    geometry::Scene scene = loadData("parallel-square.json");
    const OcclusionFrame f = geometry::fitOcclusionFrame(scene, allObjects(scene), 8);
    EXPECT_FALSE(f.receiversOutside); // the floor's corners fit the frustum (up to rounding)
    for (const auto& o : scene.objects)
        for (const glm::vec3& q : o.mesh.positions) EXPECT_TRUE(f.covers(q)) << o.name;
    const glm::vec3 c = f.center;
    EXPECT_FALSE(f.covers(c - 0.5f * f.axis)); // behind the light
    EXPECT_FALSE(f.covers(c));                 // in its plane
    testutil::Rng rng(17);
    int inside = 0, outside = 0;
    for (int i = 0; i < 2000; ++i) {
        const float x = rng.uniform(-6.0, 6.0); // one draw per statement: the same points
        const float y = rng.uniform(-1.0, 3.5); // whatever order a compiler evaluates
        const float z = rng.uniform(-6.0, 6.0); // arguments in
        const glm::vec3 q(x, y, z);
        if (f.depth(q) <= 1e-3f) {
            EXPECT_FALSE(f.covers(q));
            continue;
        }
        const glm::vec2 t = f.textureCoord(q);
        const float edge = std::min(std::min(t.x, t.y), 1.0f - std::max(t.x, t.y));
        if (std::abs(edge) < 1e-3f) continue; // within rounding of the side planes
        EXPECT_EQ(f.covers(q), edge > 0.0f) << q.x << " " << q.y << " " << q.z;
        (edge > 0.0f ? inside : outside) += 1;
    }
    EXPECT_GT(inside, 100);
    EXPECT_GT(outside, 100);
    // A ceiling above the light, and a wall reaching its plane: not covered.
    scene.objects.push_back({"ceiling", geometry::ShadowMethod::Auto,
                             geometry::makeQuad({0, 5, 0}, {3, 0, 0}, {0, 0, 3})});
    EXPECT_TRUE(geometry::fitOcclusionFrame(scene, allObjects(scene), 8).receiversOutside);
}

TEST(OcclusionSlices, SliceProjectionLandsOnTextureCoord) {
    const geometry::Scene scene = loadData("demo.json");
    const auto all = allObjects(scene);
    const OcclusionFrame f = geometry::fitOcclusionFrame(scene, all, 8);
    ASSERT_FALSE(f.empty);
    const glm::mat4 m = f.sliceProjection();
    testutil::Rng rng(3);
    for (int i = 0; i < 200; ++i) {
        const glm::vec3 q(rng.uniform(-4, 4), rng.uniform(0, 4), rng.uniform(-4, 4));
        const glm::vec4 c = m * glm::vec4(q, 1.0f);
        ASSERT_GT(c.w, 0.0f);
        const glm::vec2 t = 0.5f + 0.5f * glm::vec2(c) / c.w;
        const glm::vec2 e = f.textureCoord(q);
        EXPECT_NEAR(t.x, e.x, 1e-5f);
        EXPECT_NEAR(t.y, e.y, 1e-5f);
        EXPECT_NEAR(c.z / c.w, 0.5f, 1e-6f);
    }
}

TEST(OcclusionSlices, HorizonFractionIsTheLightInFrontOfThePlane) {
    const geometry::RectLight light{.center = {0.3f, 4.0f, -0.2f},
                                    .u = {0.6f, 0.0f, 0.1f},
                                    .v = {0.0f, 0.2f, 0.4f}};
    testutil::Rng rng(11);
    int partial = 0;
    for (int i = 0; i < 300; ++i) {
        const glm::vec3 p(rng.uniform(-2, 2), rng.uniform(2.5, 5.5), rng.uniform(-2, 2));
        const glm::vec3 n(rng.direction());
        const float f = geometry::horizonFraction(light, p, n);
        // Midpoint rule on a 200 x 200 grid of the light (the boundary line costs ~1/200).
        int inFront = 0;
        for (int a = 0; a < 200; ++a)
            for (int b = 0; b < 200; ++b) {
                const glm::vec3 y = light.point(-1.0f + (a + 0.5f) / 100.0f, -1.0f + (b + 0.5f) / 100.0f);
                inFront += glm::dot(n, y - p) >= 0.0f;
            }
        EXPECT_NEAR(f, inFront / 40000.0, 0.01) << i;
        partial += f > 0.05f && f < 0.95f;
    }
    EXPECT_GT(partial, 20); // the planes cut the light, not only miss it
}

// The closed form (shared/Horizon.h) against clipping the light's square to the plane's side
// and taking the clipped polygon's area, on planes through the light in every direction and on
// the cases the closed form treats apart: b or c zero (one axis along the plane), both zero
// (the plane parallel to the light), the plane through a corner.
TEST(OcclusionSlices, HorizonFractionEqualsTheClippedSquaresArea) {
    const auto clippedShare = [](double a, double b, double c) {
        const double square[4][2] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
        double poly[5][2];
        int count = 0;
        for (int i = 0; i < 4; ++i) {
            const double* p0 = square[i];
            const double* p1 = square[(i + 1) % 4];
            const double g0 = a + b * p0[0] + c * p0[1], g1 = a + b * p1[0] + c * p1[1];
            if (g0 >= 0.0) {
                poly[count][0] = p0[0];
                poly[count++][1] = p0[1];
            }
            if ((g0 >= 0.0) != (g1 >= 0.0)) {
                const double t = g0 / (g0 - g1);
                poly[count][0] = p0[0] + t * (p1[0] - p0[0]);
                poly[count++][1] = p0[1] + t * (p1[1] - p0[1]);
            }
        }
        double area2 = 0.0;
        for (int i = 0; i < count; ++i) {
            const double* p0 = poly[i];
            const double* p1 = poly[(i + 1) % count];
            area2 += p0[0] * p1[1] - p1[0] * p0[1];
        }
        return area2 / 8.0;
    };
    testutil::Rng rng(5);
    std::vector<glm::vec3> planes = {{0.3f, 0.0f, 0.5f},  {-0.3f, 0.5f, 0.0f}, {0.0f, 0.0f, 0.0f},
                                     {-1.0f, 0.0f, 0.0f}, {1.0f, 0.5f, 0.5f},  {-1.0f, 0.5f, 0.5f},
                                     {0.2f, 0.4f, 0.4f},  {2.0f, 1.0f, 0.5f},  {-0.2f, 1e-7f, 1.0f}};
    for (int i = 0; i < 2000; ++i) {
        const float b = rng.uniform(-1, 1), c = rng.uniform(-1, 1);
        planes.emplace_back(rng.uniform(-1.2f, 1.2f) * (std::abs(b) + std::abs(c)), b, c);
    }
    for (const glm::vec3& g : planes) {
        const float f = shader::horizonShare(g.x, g.y, g.z);
        EXPECT_NEAR(f, clippedShare(g.x, g.y, g.z), 2e-6) << g.x << " " << g.y << " " << g.z;
    }
    EXPECT_EQ(shader::horizonShare(0.0f, 0.0f, 0.0f), 1.0f); // in the plane: in front, as g >= 0
    EXPECT_EQ(shader::horizonShare(-1e-3f, 0.0f, 0.0f), 0.0f);
}

} // namespace
