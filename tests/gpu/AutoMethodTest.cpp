// `auto`: the per-object path (geometry/AutoChoice.h) and the composition of the paths' V.
#include "GlTestEnv.h"
#include "RenderTestUtil.h"

#include <geometry/Error.h>

#include <gtest/gtest.h>

#include <cmath>

namespace {

using testutil::Rendered;

class AutoMethod : public GlTest {};

double maxDifference(const Rendered& a, const Rendered& b) {
    double d = 0.0;
    for (std::size_t i = 0; i < a.visibility.data.size(); ++i)
        if (std::isfinite(a.visibility.data[i]))
            d = std::max(d, double(std::abs(a.visibility.data[i] - b.visibility.data[i])));
    return d;
}

TEST_F(AutoMethod, AllWedgeObjectsRenderAsTheWedgeMethod) {
    // Every object of the demo is manifold, opaque and not silhouette-dense: auto gives each to
    // wedges and the frame is wedges-blend's (or the wedge method asked for), bit for bit.
    const auto scene = geometry::loadScene(testutil::dataPath("demo.json"));
    const Rendered autoBlend = testutil::render(scene, "auto", 96, 96, 1);
    const Rendered blend = testutil::render(scene, "wedges-blend", 96, 96, 1);
    EXPECT_EQ(maxDifference(autoBlend, blend), 0.0);
    ASSERT_EQ(autoBlend.stats.objectChoices.size(), scene.objects.size());
    for (const auto& choice : autoBlend.stats.objectChoices) {
        EXPECT_EQ(choice.path, "wedges") << scene.objects[choice.object].name;
        EXPECT_FALSE(choice.reason.empty());
    }
    const Rendered autoAdditive =
        testutil::render(scene, "auto", 96, 96, 1, {{"wedges", "additive"}});
    const Rendered additive = testutil::render(scene, "wedges-additive", 96, 96, 1);
    EXPECT_EQ(maxDifference(autoAdditive, additive), 0.0);
    EXPECT_GT(maxDifference(autoAdditive, autoBlend), 0.0); // the parameter does something
}

TEST_F(AutoMethod, ObjectsWithMethodNoneAreNotChosenFor) {
    // Only the floor casts: auto chooses for it alone, and the frame is still the wedge
    // method's (V = 0 remains only where the floor shadows or a surface faces away from the
    // light).
    auto scene = geometry::loadScene(testutil::dataPath("demo.json"));
    for (auto& object : scene.objects)
        if (object.name != "floor") object.method = geometry::ShadowMethod::None;
    const Rendered r = testutil::render(scene, "auto", 64, 64, 1);
    ASSERT_EQ(r.stats.objectChoices.size(), 1u);
    EXPECT_EQ(scene.objects[r.stats.objectChoices[0].object].name, "floor");
    EXPECT_EQ(maxDifference(r, testutil::render(scene, "wedges-blend", 64, 64, 1)), 0.0);
}

} // namespace
