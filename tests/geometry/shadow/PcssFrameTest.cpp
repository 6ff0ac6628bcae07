// The PCSS shadow maps' frame (geometry/shadow/PcssFrame.h):
// - every receiver vertex lands inside the map of its face (faceOf), and the shadow pass's
//   projection puts it where textureCoord says, at depth zNear / z;
// - casterNear is the least caster depth inside the frustum (the occluder's, not the floor's);
// - receivers beyond the light's plane get the second front face; receivers reaching the light's
//   plane clamp the front faces at maxTan (and say so) and go to the side faces;
// - the light's half extents along its axes are |u| and |v|; throughLight is the paper's
//   rectangle on the front faces and the light seen edge-on on the side faces.
#include <geometry/shadow/PcssFrame.h>
#include <geometry/scene/AlphaMask.h>
#include <geometry/scene/Primitives.h>
#include <geometry/scene/Scene.h>
#include <geometry/reference/Framing.h>

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

namespace {

geometry::Scene loadData(const char* name) {
    return geometry::loadScene(std::filesystem::path(PENUMBRA_SOURCE_DIR) / "data" / name);
}

std::vector<std::size_t> allObjects(const geometry::Scene& scene) {
    std::vector<std::size_t> all(scene.objects.size());
    for (std::size_t i = 0; i < all.size(); ++i)
        all[i] = i;
    return all;
}

// Every vertex in a face (all but those within zNear of the centre): inside that face's map,
// and the projection agrees.
void expectReceiversInside(const geometry::Scene& scene, const geometry::PcssFrame& f) {
    for (const auto& o : scene.objects)
        for (const glm::vec3& q : o.mesh.positions) {
            const int face = f.faceOf(q);
            if (face < 0) continue;
            const float z = f.depth(q, face);
            ASSERT_GT(z, f.zNear);
            ASSERT_TRUE(f.faces[face].present) << o.name << " face " << face;
            const glm::vec2 uv = f.textureCoord(q, face);
            EXPECT_GE(uv.x, 0.0f) << o.name << " face " << face;
            EXPECT_LE(uv.x, 1.0f) << o.name << " face " << face;
            EXPECT_GE(uv.y, 0.0f) << o.name << " face " << face;
            EXPECT_LE(uv.y, 1.0f) << o.name << " face " << face;
            const glm::vec4 clip = f.projection(face) * glm::vec4(q, 1.0f);
            EXPECT_NEAR(clip.w, z, 1e-4f * (1.0f + z));
            EXPECT_NEAR(0.5f * clip.x / clip.w + 0.5f, uv.x, 1e-5f);
            EXPECT_NEAR(0.5f * clip.y / clip.w + 0.5f, uv.y, 1e-5f);
            EXPECT_NEAR(clip.z / clip.w, f.zNear / z, 1e-6f);
        }
}

} // namespace

TEST(PcssFrame, ParallelSquare) {
    const geometry::Scene scene = loadData("parallel-square.json");
    const geometry::PcssFrame f = geometry::fitPcssFrame(scene, allObjects(scene));
    EXPECT_TRUE(f.faces[0].present); // the light faces down (u × v = -y)
    EXPECT_FALSE(f.faces[1].present);
    EXPECT_FALSE(f.faces[0].clamped);
    for (int face = 2; face < geometry::kPcssFaces; ++face)
        EXPECT_FALSE(f.faces[face].present) << face; // nothing reaches the light's plane
    EXPECT_NEAR(f.normal.y, -1.0f, 1e-6f);
    EXPECT_NEAR(f.halfSize.x, 0.5f, 1e-6f);
    EXPECT_NEAR(f.halfSize.y, 0.5f, 1e-6f);
    // The floor (3 m half-width at depth 3) spans m in [-1, 1], plus the small margin.
    EXPECT_NEAR(f.faces[0].lo.x, -1.0f, 0.01f);
    EXPECT_NEAR(f.faces[0].hi.y, 1.0f, 0.01f);
    // The occluder at y = 1, depth 2; the floor is deeper.
    EXPECT_NEAR(f.faces[0].casterNear, 2.0f, 1e-5f);
    expectReceiversInside(scene, f);
    // Only the floor casting: its depth.
    const std::size_t floorOnly[] = {0};
    EXPECT_NEAR(geometry::fitPcssFrame(scene, floorOnly).faces[0].casterNear, 3.0f, 1e-5f);
}

TEST(PcssFrame, RectangularLightHalfExtents) {
    geometry::Scene scene = loadData("demo.json"); // u = 0.6 x, v = 0.4 z
    const geometry::PcssFrame f = geometry::fitPcssFrame(scene, allObjects(scene));
    EXPECT_NEAR(f.halfSize.x, 0.6f, 1e-6f);
    EXPECT_NEAR(f.halfSize.y, 0.4f, 1e-6f);
    EXPECT_NEAR(glm::dot(f.eu, f.ev), 0.0f, 1e-6f);
    EXPECT_NEAR(glm::dot(f.eu, f.normal), 0.0f, 1e-6f);
    // The walls reach 0.2 m below the light, 4 m beside it: the front face is capped, and the
    // walls' upper parts go to the side faces (those that have a wall).
    EXPECT_TRUE(f.faces[0].clamped);
    EXPECT_NEAR(f.faces[0].lo.x, -geometry::PcssFitSettings{}.maxTan, 0.01f);
    EXPECT_FALSE(f.faces[1].present);
    int inSideFaces = 0;
    for (const auto& o : scene.objects)
        for (const glm::vec3& q : o.mesh.positions)
            inSideFaces += f.faceOf(q) >= 2 ? 1 : 0;
    EXPECT_GT(inSideFaces, 0);
    int sideFaces = 0;
    for (int face = 2; face < geometry::kPcssFaces; ++face)
        if (f.faces[face].present) {
            ++sideFaces;
            EXPECT_GT(f.faces[face].casterNear, 0.0f) << face; // the walls cast
        }
    EXPECT_GE(sideFaces, 1);
    expectReceiversInside(scene, f); // and every face a vertex lands in is present
}

TEST(PcssFrame, FacesCoverEveryDirectionOnce) {
    geometry::Scene scene = loadData("demo.json");
    const geometry::PcssFrame f = geometry::fitPcssFrame(scene, allObjects(scene));
    // The cube's faces are orthonormal frames, and a direction's face has it deepest among the
    // candidates: the front faces within the cap, a side face whose axis is the largest lateral
    // component beyond it.
    for (int face = 0; face < geometry::kPcssFaces; ++face) {
        const geometry::PcssFace& s = f.faces[face];
        EXPECT_NEAR(glm::dot(s.b1, s.b2), 0.0f, 1e-6f);
        EXPECT_NEAR(glm::dot(s.b1, s.axis), 0.0f, 1e-6f);
        EXPECT_NEAR(glm::length(s.axis), 1.0f, 1e-6f);
    }
    const float T = f.maxTan;
    const glm::vec3 c = f.center;
    EXPECT_EQ(f.faceOf(c + 0.99f * T * f.eu + f.normal), 0); // inside the cap: the front face
    EXPECT_EQ(f.faceOf(c + 1.01f * T * f.eu + f.normal), 2); // beyond it: the side face
    EXPECT_EQ(f.faceOf(c - 1.01f * T * f.ev - f.normal), 5);
    EXPECT_EQ(f.faceOf(c - f.eu), 3);                        // in the light's plane
    EXPECT_EQ(f.faceOf(c + 0.1f * f.zNear * f.normal), -1);  // at the centre
    // Beyond the cap a point's side-face coordinates lie within the fixed extent.
    for (const glm::vec3& d : {1.01f * T * f.eu + f.normal, -f.ev + 0.2f * f.normal,
                                f.eu - 0.999f * f.ev - 0.33f * f.normal}) {
        const int face = f.faceOf(c + d);
        ASSERT_GE(face, 2);
        const glm::vec2 uv = f.textureCoord(c + d, face);
        EXPECT_TRUE(uv.x > 0.0f && uv.x < 1.0f && uv.y > 0.0f && uv.y < 1.0f)
            << face << " " << uv.x << " " << uv.y;
    }
}

TEST(PcssFrame, ThroughLightIsThePapersRectangleOnTheFrontFaces) {
    geometry::Scene scene = loadData("demo.json"); // u = 0.6 x, v = 0.4 z
    const geometry::PcssFrame f = geometry::fitPcssFrame(scene, allObjects(scene));
    // On face 0 the light lies at depth 0: the segment from P to the light's point s crosses
    // depth z at m_P + s halfSize (1 / z - 1 / z_P).
    const glm::vec3 p(0.7f, -0.3f, 2.5f);
    for (const glm::vec2 s : {glm::vec2(1.0f, 1.0f), glm::vec2(-0.5f, 0.25f)})
        for (const float z : {0.5f, 1.2f, 2.4f}) {
            const glm::vec3 l = s.x * f.lightU(0) + s.y * f.lightV(0);
            EXPECT_NEAR(l.z, 0.0f, 1e-6f);
            const glm::vec2 expected =
                glm::vec2(p) / p.z + s * f.halfSize * (1.0f / z - 1.0f / p.z);
            const glm::vec2 m = geometry::throughLight(p, l, z);
            EXPECT_NEAR(m.x, expected.x, 1e-5f);
            EXPECT_NEAR(m.y, expected.y, 1e-5f);
        }
    // On the side face along eu the light is seen edge-on: its u half axis lies along the depth,
    // its v half axis across, and a point of the light's edge is its own map position.
    const glm::vec3 lu = f.lightU(2), lv = f.lightV(2);
    EXPECT_NEAR(lu.z, f.halfSize.x, 1e-6f);
    EXPECT_NEAR(glm::length(glm::vec2(lu)), 0.0f, 1e-6f);
    EXPECT_NEAR(std::abs(lv.x), f.halfSize.y, 1e-6f);
    EXPECT_NEAR(lv.z, 0.0f, 1e-6f);
    const glm::vec3 q(0.1f, 0.05f, 4.0f), edge = lu + lv;
    const glm::vec2 atEdge = geometry::throughLight(q, edge, edge.z);
    EXPECT_NEAR(atEdge.x, edge.x / edge.z, 1e-5f);
    EXPECT_NEAR(atEdge.y, edge.y / edge.z, 1e-5f);
}

TEST(PcssFrame, ReceiversAboveTheLightGetTheSecondSide) {
    geometry::Scene scene = loadData("parallel-square.json");
    // A ceiling 2 m above the light and a plate between them.
    scene.objects.push_back({"ceiling", geometry::ShadowMethod::Auto,
                             geometry::makeQuad({0, 5, 0}, {3, 0, 0}, {0, 0, 3})});
    scene.objects.push_back({"upper plate", geometry::ShadowMethod::Auto,
                             geometry::makeQuad({0.2f, 4, 0}, {0.4f, 0, 0}, {0, 0, 0.4f})});
    const geometry::PcssFrame f = geometry::fitPcssFrame(scene, allObjects(scene));
    EXPECT_TRUE(f.faces[0].present);
    EXPECT_TRUE(f.faces[1].present);
    EXPECT_NEAR(f.faces[0].casterNear, 2.0f, 1e-5f);
    EXPECT_NEAR(f.faces[1].casterNear, 1.0f, 1e-5f);
    EXPECT_NEAR(f.faces[1].hi.x, 1.5f, 0.01f); // the ceiling: 3 m half-width at depth 2
    expectReceiversInside(scene, f);
}

// The boxes of the reach test: at most the number asked for, and every triangle's occluding part
// inside one of them; one object spread over a level gets boxes far smaller than its bounds.
TEST(PcssFrame, CasterClustersHoldEveryOccludingPart) {
    const geometry::Scene level =
        geometry::loadScene(std::filesystem::path(PENUMBRA_SHARED_DIR) / "levels" / "textured" /
                            "kaos2.glb");
    std::vector<std::size_t> alpha;
    for (std::size_t i = 0; i < level.objects.size(); ++i)
        if (level.objects[i].name.find("(alpha-tested)") != std::string::npos) alpha.push_back(i);
    ASSERT_EQ(alpha.size(), 1u);
    double volumes[3] = {0.0, 0.0, 0.0};
    int slot = 0;
    for (const int n : {1, 4, 16}) {
        SCOPED_TRACE(n);
        const std::vector<geometry::Aabb> boxes = geometry::casterClusters(level, alpha, n);
        ASSERT_FALSE(boxes.empty());
        EXPECT_LE(boxes.size(), std::size_t(n));
        const geometry::MeshData& m = level.objects[alpha[0]].mesh;
        for (std::uint32_t t = 0; t < m.triangles.size(); ++t) {
            // Each triangle's occluding part (geometry::occlusionBounds, tested in
            // AlphaMaskTest) inside one box.
            const geometry::Aabb part = geometry::occlusionBounds(m, t);
            if (part.empty()) continue;
            bool inside = false;
            for (const geometry::Aabb& b : boxes)
                inside = inside || (glm::all(glm::greaterThanEqual(part.min, b.min)) &&
                                    glm::all(glm::lessThanEqual(part.max, b.max)));
            ASSERT_TRUE(inside) << t;
        }
        double volume = 0.0;
        for (const geometry::Aabb& b : boxes) {
            const glm::vec3 e = b.max - b.min;
            volume += double(e.x) * e.y * e.z;
        }
        volumes[slot++] = volume;
        std::printf("  kaos2's alpha-tested part, %d boxes: %zu, total volume %.1f m³\n", n,
                    boxes.size(), volume);
    }
    // Measured: 16570 m³ in one box (around the triangles' opaque parts; 57474 around whole
    // triangles), 4.3 in 4, 0.0 in 16 (flat boxes: a card's few opaque texels).
    EXPECT_GT(volumes[0], 1e4);
    EXPECT_LT(volumes[2], 1e-3 * volumes[0]);
    EXPECT_TRUE(geometry::casterClusters(level, {}, 16).empty());
}

// textured oa_dm1's third spawn view, lit by the viewer's lamp: the lamp hangs inside the bounds
// of the light-beam cards around it (BLEND, tested as MASK 0.5: 7 % of their texels reach it),
// so boxes around whole triangles sent every pixel of the view to pcss's search (57,600 of
// 57,600 at 320x180; none of them shadowed). Boxed around their opaque texels, no grown box holds
// the lamp's centre.
TEST(PcssFrame, CasterClustersAroundOpaqueTexelsLeaveTheLampOutsideTheBeams) {
    geometry::Scene level = geometry::loadScene(std::filesystem::path(PENUMBRA_SHARED_DIR) /
                                                "levels" / "textured" / "oa_dm1.glb");
    geometry::selectCamera(level, 2);
    ASSERT_EQ(geometry::lightAtView(level, false), "lamp at the view");
    std::vector<std::size_t> alpha;
    for (std::size_t i = 0; i < level.objects.size(); ++i)
        if (level.objects[i].name.find("(alpha-tested)") != std::string::npos) alpha.push_back(i);
    ASSERT_EQ(alpha.size(), 1u);
    const geometry::MeshData& m = level.objects[alpha[0]].mesh;
    const glm::vec3 c = level.light.center;
    const glm::vec3 half = glm::abs(level.light.u) + glm::abs(level.light.v);
    auto holds = [&](const geometry::Aabb& b) {
        return glm::all(glm::greaterThanEqual(c, b.min - half)) &&
               glm::all(glm::lessThanEqual(c, b.max + half));
    };
    int wholeHolding = 0;
    for (const glm::uvec3& t : m.triangles) {
        geometry::Aabb b;
        for (int k = 0; k < 3; ++k) b.extend(m.positions[t[k]]);
        wholeHolding += holds(b) ? 1 : 0;
    }
    const std::vector<geometry::Aabb> boxes = geometry::casterClusters(level, alpha, 16);
    int clustersHolding = 0;
    for (const geometry::Aabb& b : boxes) clustersHolding += holds(b) ? 1 : 0;
    std::printf("  textured oa_dm1 camera 2: the lamp inside %d of %zu triangles' grown boxes, "
                "inside %d of %zu boxes around their opaque texels\n",
                wholeHolding, m.triangles.size(), clustersHolding, boxes.size());
    EXPECT_GT(wholeHolding, 0);
    EXPECT_EQ(clustersHolding, 0);
}

// sweepMeetsBox against brute force: points of the source box (corners, faces, inside), each
// segment to the point sampled finely; a hit found by sampling must be reported, and a reported
// hit must lie within a small distance of some sampled segment point (it is exact).
TEST(PcssFrame, SweepMeetsBoxAgreesWithSampledSegments) {
    std::uint32_t state = 12345u;
    auto rnd = [&] {
        state = state * 1664525u + 1013904223u;
        return static_cast<float>(state >> 8) / static_cast<float>(1u << 24);
    };
    int hits = 0, misses = 0;
    for (int trial = 0; trial < 400; ++trial) {
        geometry::Aabb from, box;
        const glm::vec3 a(rnd() * 4 - 2, rnd() * 4 - 2, rnd() * 4 - 2);
        from.extend(a);
        from.extend(a + glm::vec3(rnd(), rnd(), rnd()) * (trial % 4 == 0 ? 0.0f : 1.5f));
        const glm::vec3 b(rnd() * 4 - 2, rnd() * 4 - 2, rnd() * 4 - 2);
        box.extend(b);
        box.extend(b + glm::vec3(rnd(), rnd(), rnd()) * 0.8f);
        const glm::vec3 to(rnd() * 4 - 2, rnd() * 4 - 2, rnd() * 4 - 2);
        // Whether a sampled segment (grid points of `from` to `to`) has a point in `b`.
        constexpr int n = 8, m = 120;
        auto sampledMeet = [&](const geometry::Aabb& b) {
            for (int i = 0; i <= n; ++i)
                for (int j = 0; j <= n; ++j)
                    for (int k = 0; k <= n; ++k) {
                        const glm::vec3 p =
                            from.min + (from.max - from.min) * glm::vec3(i, j, k) / float(n);
                        for (int s = 0; s <= m; ++s) {
                            const glm::vec3 q = p + (to - p) * (float(s) / m);
                            if (glm::all(glm::greaterThanEqual(q, b.min)) &&
                                glm::all(glm::lessThanEqual(q, b.max)))
                                return true;
                        }
                    }
            return false;
        };
        const bool sampled = sampledMeet(box);
        const bool swept = geometry::sweepMeetsBox(from, to, box);
        if (sampled) {
            EXPECT_TRUE(swept) << trial;
        }
        hits += swept ? 1 : 0;
        misses += swept ? 0 : 1;
        if (swept && !sampled) {
            // Exact: a box grown by the sampling's spacing is met by a sampled segment.
            geometry::Aabb wider = box;
            const float h = 0.07f * glm::length(from.max - from.min) + 0.05f;
            wider.extend(box.min - glm::vec3(h));
            wider.extend(box.max + glm::vec3(h));
            EXPECT_TRUE(sampledMeet(wider)) << trial;
        }
    }
    EXPECT_GT(hits, 10); // measured 19 of 400
    EXPECT_GT(misses, 40);
    geometry::Aabb none;
    EXPECT_FALSE(geometry::sweepMeetsBox(none, glm::vec3(0.0f), geometry::Aabb{}));
}
