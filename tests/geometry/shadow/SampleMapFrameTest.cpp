// The sample-maps method's frame (geometry/shadow/SampleMapFrame.h):
// - each sample's projection puts every corner of the casters' box inside its map, at depth
//   zNear / z in (0, 1];
// - the reach (from the light's centre) holds every receiver that some sample's map could
//   shadow: random receivers and samples;
// - sampleMapsHold: true for a tree under the light, false for a box around or beside it, and
//   the fit says `clipped` exactly then.
#include <geometry/core/Sampling.h>
#include <geometry/shadow/SampleMapFrame.h>


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

RectLight light(glm::vec3 c, float half) { return RectLight{c, {half, 0, 0}, {0, 0, half}}; }

TEST(SampleMapFrame, EveryCornerLiesInsideEveryMap) {
    const RectLight l = light({1.5f, 9.0f, 1.0f}, 0.6f);
    const Aabb b = box({-3, 0, -2}, {3, 6, 2.5f});
    const auto samples = geometry::stratifiedSquare(64, 1);
    const geometry::SampleMapFrame f = geometry::fitSampleMapFrame(l, samples, b);
    ASSERT_FALSE(f.empty);
    EXPECT_FALSE(f.clipped);
    ASSERT_EQ(f.views.size(), 64u);
    EXPECT_LT(f.n.y, -0.99f); // towards the box, below the light
    for (std::size_t i = 0; i < f.views.size(); ++i) {
        EXPECT_NEAR(glm::distance(f.views[i].origin, l.point(samples[i].x, samples[i].y)), 0.0f,
                    1e-5f);
        const glm::mat4 m = f.projection(i);
        for (int k = 0; k < 8; ++k) {
            const glm::vec3 q((k & 1) ? b.max.x : b.min.x, (k & 2) ? b.max.y : b.min.y,
                              (k & 4) ? b.max.z : b.min.z);
            const glm::vec4 c = m * glm::vec4(q, 1.0f);
            ASSERT_GT(c.w, 0.0f);
            const glm::vec3 ndc = glm::vec3(c) / c.w;
            EXPECT_LE(std::abs(ndc.x), 1.0f) << i << " " << k;
            EXPECT_LE(std::abs(ndc.y), 1.0f) << i << " " << k;
            EXPECT_GT(ndc.z, 0.0f);
            EXPECT_LE(ndc.z, 1.0f);
            // depth zNear / z, z along n from the sample
            const float z = glm::dot(q - f.views[i].origin, f.n);
            EXPECT_NEAR(ndc.z, f.zNear / z, 1e-5f);
        }
    }
}

TEST(SampleMapFrame, ReachHoldsEveryReceiverAMapCouldShadow) {
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    std::size_t inside = 0, outside = 0;
    for (int trial = 0; trial < 40; ++trial) {
        const RectLight l = {glm::vec3(u(rng), 8.0f + u(rng), u(rng)),
                             glm::vec3(0.2f + 1.5f * (u(rng) + 1.0f), 0, 0),
                             glm::vec3(0, 0, 0.2f + 1.5f * (u(rng) + 1.0f))};
        const glm::vec3 lo(2.0f * u(rng), 1.0f + u(rng), 2.0f * u(rng));
        const Aabb b = box(lo, lo + glm::vec3(1.0f + u(rng) + 1.0f, 2.0f + u(rng), 1.5f));
        const auto samples = geometry::stratifiedSquare(16, 3);
        const geometry::SampleMapFrame f = geometry::fitSampleMapFrame(l, samples, b);
        ASSERT_FALSE(f.clipped) << trial;
        for (int k = 0; k < 2000; ++k) {
            const glm::vec3 p(10.0f * u(rng), 4.0f * u(rng) - 1.0f, 10.0f * u(rng));
            const bool inReach = geometry::inReach(f, l.center, p);
            for (const geometry::SampleMapView& v : f.views) {
                const glm::vec3 d = p - v.origin;
                const float z = glm::dot(d, f.n);
                if (z <= f.zNear) continue;
                const glm::vec2 m = glm::vec2(glm::dot(d, f.eu), glm::dot(d, f.ev)) / z;
                const bool inMap = m.x >= v.lo.x && m.y >= v.lo.y && m.x <= v.hi.x && m.y <= v.hi.y;
                if (inMap) {
                    ASSERT_TRUE(inReach) << trial << " " << k;
                }
            }
            (inReach ? inside : outside) += 1;
        }
    }
    // The reach is a real cut: many receivers skip the loop.
    EXPECT_GT(outside, inside / 4);
}

TEST(SampleMapFrame, HoldsOnlyWhatLiesInFrontOfEveryLightPoint) {
    const auto samples = geometry::stratifiedSquare(16, 1);
    const RectLight l = light({0, 9, 0}, 0.6f);
    struct Case {
        const char* what;
        Aabb b;
        bool holds;
    };
    for (const Case& c : {Case{"a tree under the light", box({-3, 0, -3}, {3, 6, 3}), true},
                          Case{"a level around the lamp", box({-20, -2, -20}, {20, 12, 20}), false},
                          Case{"a grate level with the light", box({4, 8.9f, -1}, {6, 9.1f, 1}),
                               false},
                          Case{"far beside it, beyond the cap", box({40, 7, -1}, {42, 8, 1}), false},
                          Case{"above the light", box({-1, 11, -1}, {1, 12, 1}), true}}) {
        SCOPED_TRACE(c.what);
        EXPECT_EQ(geometry::sampleMapsHold(l, c.b), c.holds);
        EXPECT_EQ(geometry::fitSampleMapFrame(l, samples, c.b).clipped, !c.holds);
    }
    EXPECT_TRUE(geometry::fitSampleMapFrame(l, samples, Aabb{}).empty);
}

} // namespace
