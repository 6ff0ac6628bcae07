// The `auto` method's per-object rule (geometry/shadow/AutoChoice.h), one case per clause.
#include <geometry/shadow/AutoChoice.h>

#include <gtest/gtest.h>

namespace {

using geometry::ShadowPath;

geometry::CasterFacts facts(std::size_t triangles, std::size_t edges, std::size_t nonManifold,
                            std::size_t silhouetteEdges) {
    geometry::CasterFacts f;
    f.topology.triangles = triangles;
    f.topology.edges = edges;
    f.topology.nonManifoldEdges = nonManifold;
    f.silhouetteEdges = silhouetteEdges;
    return f;
}

TEST(AutoChoiceTest, EachClauseInOrder) {
    // A closed box: 12 triangles, 18 edges, 6 silhouette edges: wedges.
    EXPECT_EQ(geometry::chooseShadowPath(facts(12, 18, 0, 6)).path, ShadowPath::Wedges);
    // kaos2 as measured: 27831 triangles, 42829 edges, 269 non-manifold, 10620 silhouette
    // edges: a level stays with wedges.
    EXPECT_EQ(geometry::chooseShadowPath(facts(27831, 42829, 269, 10620)).path,
              ShadowPath::Wedges);
    // A triangle soup of crossed cards (10 % non-manifold edges) and a silhouette-dense mesh
    // (0.8 edges per triangle) stay with wedges: the two-sided counts serve any topology, and
    // the reason gives the counts.
    const auto soup = geometry::chooseShadowPath(facts(2000, 3000, 300, 100));
    EXPECT_EQ(soup.path, ShadowPath::Wedges);
    EXPECT_NE(soup.reason.find("10.0 % non-manifold"), std::string::npos) << soup.reason;
    const auto dense = geometry::chooseShadowPath(facts(500, 800, 0, 400));
    EXPECT_EQ(dense.path, ShadowPath::Wedges);
    EXPECT_NE(dense.reason.find("0.80 per triangle"), std::string::npos) << dense.reason;
    // Alpha masks win over everything the topology says.
    auto masked = facts(12, 18, 0, 6);
    masked.alphaMasked = true;
    masked.alphaMaterials = "grate (MASK 0.50)";
    // They take the alpha path: sample maps where every light point sees the object in front
    // of it, pcss where not (a grate around a lamp); pcss or occlusion when auto's alpha
    // parameter says so.
    const auto tree = geometry::chooseShadowPath(masked);
    EXPECT_EQ(tree.path, ShadowPath::SampleMaps);
    EXPECT_NE(tree.reason.find("grate (MASK 0.50)"), std::string::npos) << tree.reason;
    masked.sampleMapsHold = false;
    const auto grate = geometry::chooseShadowPath(masked);
    EXPECT_EQ(grate.path, ShadowPath::Pcss);
    EXPECT_NE(grate.reason.find("not wholly in front of every light point"), std::string::npos)
        << grate.reason;
    masked.alphaPath = ShadowPath::Pcss;
    masked.sampleMapsHold = true;
    EXPECT_EQ(geometry::chooseShadowPath(masked).path, ShadowPath::Pcss);
    masked.alphaPath = ShadowPath::Occlusion;
    EXPECT_EQ(geometry::chooseShadowPath(masked).path, ShadowPath::Occlusion);
    // The scene JSON wins over everything.
    masked.requested = geometry::ShadowMethod::Wedges;
    EXPECT_EQ(geometry::chooseShadowPath(masked).path, ShadowPath::Wedges);
    auto box = facts(12, 18, 0, 6);
    box.requested = geometry::ShadowMethod::Occlusion;
    const auto asked = geometry::chooseShadowPath(box);
    EXPECT_EQ(asked.path, ShadowPath::Occlusion);
    EXPECT_NE(asked.reason.find("scene JSON"), std::string::npos);
    // Empty meshes do not divide by zero.
    EXPECT_EQ(geometry::chooseShadowPath(facts(0, 0, 0, 0)).path, ShadowPath::Wedges);
}

} // namespace
