// The stability suite (data/stability/, see the README there):
// - every scene keeps its light clear of all geometry over the flicker sweep (the light centre
//   from c - u to c + u), so no frame of the sweep is refused;
// - the camera scenes keep their camera where their names say, over the whole sweep;
// - the generated glTF casters (scripts/make-stability-meshes.py) have the topology the generator
//   promises, so a regenerated file that lost its defect fails here.
#include <geometry/core/Error.h>
#include <geometry/scene/GltfLoader.h>
#include <geometry/reference/RayTracer.h>
#include <geometry/scene/Scene.h>
#include <geometry/reference/Framing.h>
#include <geometry/shadow/Topology.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;

const fs::path kDir = fs::path(PENUMBRA_SOURCE_DIR) / "data" / "stability";

// Light positions checked, in units of the light's u half-axis. Contact needs only the two ends
// (the swept rectangle is their union); the camera checks also look between them.
constexpr float kSweep[] = {-1.0f, -0.75f, -0.5f, -0.25f, 0.0f, 0.25f, 0.5f, 0.75f, 1.0f};

geometry::Scene withLightAt(geometry::Scene s, float t) {
    s.light.center += t * s.light.u;
    return s;
}

// Fraction of the light seen from `p` (a point in free space: offset towards the light).
float visibilityAt(const geometry::RayTracer& tracer, const geometry::RectLight& light,
                   const glm::vec3& p) {
    const std::vector<glm::vec3> points{p};
    const std::vector<glm::vec3> normals{-light.normal()};
    float v = -1.0f;
    geometry::RayTraceSettings settings;
    settings.samples = 1024;
    tracer.visibility(light, points, normals, settings, std::span<float>(&v, 1));
    return v;
}

// 1 if the light centre is visible from `p`, else 0.
float hardVisibilityAt(const geometry::RayTracer& tracer, const geometry::RectLight& light,
                       const glm::vec3& p) {
    const std::vector<glm::vec3> points{p};
    const std::vector<glm::vec3> normals{glm::normalize(light.center - p)};
    float v = -1.0f;
    tracer.hardVisibility(light.center, points, normals, {}, std::span<float>(&v, 1));
    return v;
}

TEST(StabilityScenes, LightStaysClearOfGeometryDuringTheSweep) {
    int count = 0;
    for (const auto& entry : fs::directory_iterator(kDir)) {
        if (entry.path().extension() != ".json") continue;
        SCOPED_TRACE(entry.path().filename().string());
        const geometry::Scene scene = geometry::loadScene(entry.path());
        for (float t : kSweep) {
            SCOPED_TRACE("light centre at c + " + std::to_string(t) + " u");
            EXPECT_NO_THROW(geometry::validateScene(withLightAt(scene, t)));
        }
        ++count;
    }
    EXPECT_GE(count, 10);
}

// light-grazing is only a test of grazing if the contact is millimetres away: half a centimetre
// further (down onto the shelf, or back into the wall) must touch.
TEST(StabilityScenes, GrazingLightIsMillimetresFromContact) {
    const geometry::Scene scene = geometry::loadScene(kDir / "light-grazing.json");
    for (const glm::vec3 step : {glm::vec3(0.0f, -0.005f, 0.0f), glm::vec3(0.0f, 0.0f, -0.005f)}) {
        geometry::Scene moved = scene;
        moved.light.center += step;
        EXPECT_THROW(geometry::validateScene(moved), geometry::InputError);
    }
}

TEST(StabilityScenes, CameraInVolumeStaysInTheUmbra) {
    const geometry::Scene scene = geometry::loadScene(kDir / "camera-in-volume.json");
    const geometry::RayTracer tracer(scene);
    for (float t : kSweep) {
        const geometry::RectLight light = withLightAt(scene, t).light;
        EXPECT_EQ(visibilityAt(tracer, light, scene.camera.eye), 0.0f) << "t = " << t;
    }
}

// Inside the wedge: part of the light visible (not near either end of the penumbra), and on the
// hard-shadow side of the light centre's volume face.
TEST(StabilityScenes, CameraInWedgeStaysInThePenumbra) {
    const geometry::Scene scene = geometry::loadScene(kDir / "camera-in-wedge.json");
    const geometry::RayTracer tracer(scene);
    for (float t : kSweep) {
        const geometry::RectLight light = withLightAt(scene, t).light;
        const float v = visibilityAt(tracer, light, scene.camera.eye);
        EXPECT_GT(v, 0.15f) << "t = " << t;
        EXPECT_LT(v, 0.85f) << "t = " << t;
        EXPECT_EQ(hardVisibilityAt(tracer, light, scene.camera.eye), 0.0f) << "t = " << t;
    }
}

// The near plane (at the distance gpu/src/engine/Renderer.cpp uses: 1e-4 of the scene diagonal, at least
// 1e-4) is cut by the light centre's shadow volume: its corners are not all on one side.
TEST(StabilityScenes, NearPlaneCutsAShadowVolume) {
    const geometry::Scene scene = geometry::loadScene(kDir / "near-clip.json");
    const geometry::Aabb b = scene.bounds();
    const float zNear = std::max(1e-4f * glm::length(b.max - b.min), 1e-4f);
    const geometry::Camera& cam = scene.camera;
    const glm::vec3 forward = glm::normalize(cam.target - cam.eye);
    const glm::vec3 right = glm::normalize(glm::cross(forward, cam.up));
    const glm::vec3 up = glm::cross(right, forward);
    const float half = zNear * std::tan(glm::radians(cam.fovYDeg) / 2.0f); // square views
    const geometry::RayTracer tracer(scene);
    for (float t : kSweep) {
        const geometry::RectLight light = withLightAt(scene, t).light;
        int lit = 0;
        int shadowed = 0;
        for (float sx : {-1.0f, 1.0f}) {
            for (float sy : {-1.0f, 1.0f}) {
                const glm::vec3 corner = cam.eye + zNear * forward + half * (sx * right + sy * up);
                (hardVisibilityAt(tracer, light, corner) > 0.5f ? lit : shadowed)++;
            }
        }
        EXPECT_GT(lit, 0) << "t = " << t;
        EXPECT_GT(shadowed, 0) << "t = " << t;
    }
}

struct MeshFacts {
    const char* file;
    geometry::Manifoldness manifoldness;
    std::size_t triangles;           // after dropping degenerate ones
    std::size_t degenerateTriangles; // dropped by the topology (the loader drops strip restarts)
    std::size_t boundaryEdges;
    std::size_t nonManifoldEdges;
    std::size_t maxEdgeUses;
};

TEST(StabilityMeshes, GeneratedCastersHaveTheirDefects) {
    using M = geometry::Manifoldness;
    const MeshFacts facts[] = {
        // 142 of 146 triangles left once the collinear, repeated-index, zero-length-edge and 0.4 um-edge
        // triangles are gone; the 0.3 um-off side copies weld, so it closes.
        {"sliver-slab.gltf", M::Closed, 142, 4, 0, 0, 2},
        {"sliver-strip.gltf", M::Open, 200, 0, 202, 0, 2},
        {"open-box.gltf", M::Open, 8, 0, 6, 0, 2},
        {"fan.gltf", M::Open, 12, 0, 12, 0, 2},
        {"fins.gltf", M::NonManifold, 8, 0, 12, 1, 4},
        {"tee.gltf", M::NonManifold, 6, 0, 9, 1, 3},
        {"cubes-edge.gltf", M::NonManifold, 24, 0, 0, 1, 4},
    };
    for (const MeshFacts& f : facts) {
        SCOPED_TRACE(f.file);
        const geometry::Topology topo(geometry::loadGltf(kDir / f.file));
        const geometry::TopologyStats& s = topo.stats();
        EXPECT_EQ(topo.manifoldness(), f.manifoldness) << geometry::toString(topo.manifoldness());
        EXPECT_EQ(s.triangles, f.triangles);
        EXPECT_EQ(s.degenerateTriangles, f.degenerateTriangles);
        EXPECT_EQ(s.boundaryEdges, f.boundaryEdges);
        EXPECT_EQ(s.nonManifoldEdges, f.nonManifoldEdges);
        std::size_t maxUses = 0;
        const auto offsets = topo.edgeUseOffsets();
        for (std::size_t e = 0; e + 1 < offsets.size(); ++e)
            maxUses = std::max<std::size_t>(maxUses, offsets[e + 1] - offsets[e]);
        EXPECT_EQ(maxUses, f.maxEdgeUses);
    }
}

} // namespace
