#include <geometry/shadow/ShadowCone.h>

#include <gtest/gtest.h>

#include <random>

namespace {

using geometry::Aabb;
using geometry::RectLight;

Aabb box(glm::vec3 lo, glm::vec3 hi) {
    Aabb b;
    b.extend(lo);
    b.extend(hi);
    return b;
}

// Points X = Y + t (Y - L) for random light points L and occluder points Y, t >= 0: all of them
// must be in the cone (as zero-radius spheres), for lights and occluders in many poses.
TEST(ShadowCone, HoldsEveryPointBehindTheOccluder) {
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> unit(-1.0f, 1.0f), pos(0.0f, 1.0f);
    int cones = 0;
    for (int trial = 0; trial < 200; ++trial) {
        RectLight light;
        light.center = glm::vec3(unit(rng), 6.0f + unit(rng), unit(rng)) * 2.0f;
        light.u = glm::vec3(pos(rng) + 0.01f, 0.3f * unit(rng), 0.0f);
        light.v = glm::vec3(0.0f, 0.3f * unit(rng), pos(rng) + 0.01f);
        const glm::vec3 c(3.0f * unit(rng), 2.0f * pos(rng), 3.0f * unit(rng));
        const glm::vec3 half(pos(rng) + 0.01f, pos(rng) + 0.01f, pos(rng) + 0.01f);
        const Aabb occluder = box(c - half, c + half);
        const geometry::ShadowCone cone = geometry::shadowCone(occluder, light);
        cones += !cone.whole;
        for (int k = 0; k < 200; ++k) {
            const glm::vec3 l = light.point(unit(rng), unit(rng));
            const glm::vec3 y = glm::mix(occluder.min, occluder.max,
                                         glm::vec3(pos(rng), pos(rng), pos(rng)));
            const float t = 20.0f * pos(rng) * pos(rng);
            const glm::vec3 x = y + t * (y - l);
            ASSERT_TRUE(geometry::sphereMayMeetCone(cone, x, 0.0f))
                << "trial " << trial << " t " << t;
        }
    }
    EXPECT_GT(cones, 100); // most poses do have a cone (the test is not vacuous)
}

TEST(ShadowCone, RejectsWhatTheOccluderCannotShade) {
    RectLight light; // centre (0, 6, 0), 1 x 1, facing down
    const Aabb occluder = box({-0.5f, 2.0f, -0.5f}, {0.5f, 2.2f, 0.5f});
    const geometry::ShadowCone cone = geometry::shadowCone(occluder, light);
    ASSERT_FALSE(cone.whole);
    EXPECT_TRUE(geometry::sphereMayMeetCone(cone, {0.0f, 0.0f, 0.0f}, 0.1f)); // under it
    EXPECT_TRUE(geometry::sphereMayMeetCone(cone, {1.5f, 0.0f, 0.0f}, 0.1f)); // penumbra side
    EXPECT_FALSE(geometry::sphereMayMeetCone(cone, {6.0f, 0.0f, 0.0f}, 0.5f)); // far to the side
    EXPECT_FALSE(geometry::sphereMayMeetCone(cone, {0.0f, 8.0f, 0.0f}, 0.5f)); // above the light
    EXPECT_FALSE(geometry::sphereMayMeetCone(cone, {4.0f, 4.0f, 0.0f}, 0.5f)); // beside it
    // A sphere that reaches into the cone from outside it does meet it.
    EXPECT_TRUE(geometry::sphereMayMeetCone(cone, {6.0f, 0.0f, 0.0f}, 5.0f));
}

TEST(ShadowCone, NoConeWhenLightAndOccluderSpheresMeet) {
    RectLight light;
    light.u = {3.0f, 0.0f, 0.0f};
    light.v = {0.0f, 0.0f, 3.0f};
    const Aabb occluder = box({-0.5f, 2.0f, -0.5f}, {0.5f, 2.2f, 0.5f});
    EXPECT_TRUE(geometry::shadowCone(occluder, light).whole);
    EXPECT_TRUE(geometry::shadowCone(Aabb{}, RectLight{}).whole); // no occluder: no claim
    EXPECT_TRUE(geometry::sphereMayMeetCone(geometry::shadowCone(occluder, light),
                                            {100.0f, 100.0f, 100.0f}, 0.0f));
}

} // namespace
