// RenderSettings::camera (the viewer's fly camera): a frame rendered with a replaced camera equals
// a frame of the scene whose camera was edited to match, a replaced camera is validated like the
// scene's, and frames that do not wait for the GPU still report pass times from an earlier frame.
#include "GlTestEnv.h"
#include "RenderTestUtil.h"
#include "TestErrors.h"

#include <geometry/core/Error.h>
#include <geometry/reference/Framing.h>

#include <chrono>
#include <cmath>
#include <optional>
#include <string>
#include <thread>

namespace {

class CameraOverride : public GlTest {};

TEST_F(CameraOverride, EqualsTheEditedScene) {
    const geometry::Scene scene = geometry::loadScene(testutil::dataPath("plates-three.json"));
    geometry::Camera moved = scene.camera;
    moved.eye = moved.target + glm::vec3(0.8f, 0.9f, 1.1f) * (moved.eye - moved.target);
    moved.fovYDeg *= 0.8f;
    geometry::Scene edited = scene;
    edited.camera = moved;
    for (const char* method : {"hard", "wedges-blend", "occlusion", "pcss"}) {
        const geometry::FloatImage a = testutil::renderOverridden(scene, method, {.camera = moved});
        const geometry::FloatImage b = testutil::renderOverridden(edited, method, {});
        EXPECT_EQ(testutil::countDiffering(a, b, 0.0f), 0u) << method;
        const geometry::FloatImage c = testutil::renderOverridden(scene, method, {});
        EXPECT_GT(testutil::countDiffering(a, c, 0.02f), 500u) << method << ": the camera override was ignored";
    }
}

TEST_F(CameraOverride, RefusesABadCamera) {
    const geometry::Scene scene = geometry::loadScene(testutil::dataPath("plates-three.json"));
    testutil::SceneRenderer sr(scene);
    gpu::RenderSettings s;
    s.width = s.height = 32;
    geometry::Camera c = scene.camera;
    c.target = c.eye;
    s.camera = c;
    const std::optional<std::string> error =
        testutil::errorOf<geometry::InputError>([&] { sr.renderer.renderFrame(s); });
    ASSERT_TRUE(error) << "a camera looking nowhere was accepted";
    EXPECT_NE(error->find("RenderSettings::camera.target"), std::string::npos) << *error;
    c = scene.camera;
    c.eye.x = std::nanf("");
    s.camera = c;
    EXPECT_THROW(sr.renderer.renderFrame(s), geometry::InputError);
}

TEST_F(CameraOverride, FramesThatDoNotWaitReportEarlierPassTimes) {
    const geometry::Scene scene = geometry::loadScene(testutil::dataPath("plates-three.json"));
    testutil::SceneRenderer sr(scene);
    // hard: no method counters read back, so nothing else waits for the GPU.
    gpu::RenderSettings s = testutil::frameSettings("hard", 64, 64);
    s.waitForGpu = false;
    int measured = 0;
    for (int f = 0; f < 12; ++f) {
        // Paced like a viewer's frames (100 ms apart), so that a loaded machine or an
        // instrumented build still completes each frame's queries within the ring's depth; the
        // count of frames with times below depends on that, not on the renderer's speed.
        if (f > 0) std::this_thread::sleep_for(std::chrono::milliseconds(100));
        const gpu::FrameStats stats = sr.renderer.renderFrame(s);
        // The ring holds at most a few frames in flight: times are never older than that.
        EXPECT_LE(stats.gpuTimesLag, 3) << "frame " << f;
        EXPECT_GE(stats.gpuTimesLag, -1) << "frame " << f;
        if (stats.gpuTimesLag < 0) {
            EXPECT_TRUE(stats.gpu.empty());
            continue;
        }
        ++measured;
        ASSERT_FALSE(stats.gpu.empty());
        EXPECT_EQ(stats.gpu.front().name, "gbuffer");
        EXPECT_GT(stats.gpuFrameMs, 0.0);
        // Passes and frame span from one frame: no pass outlasts its frame.
        for (const gpu::PassTime& p : stats.gpu)
            EXPECT_LE(p.ms, stats.gpuFrameMs + 1e-3) << p.name << ", frame " << f;
    }
    // Past the ring's depth every frame has times.
    EXPECT_GE(measured, 8);
    // A waiting frame afterwards measures itself.
    s.waitForGpu = true;
    const gpu::FrameStats stats = sr.renderer.renderFrame(s);
    EXPECT_EQ(stats.gpuTimesLag, 0);
    EXPECT_FALSE(stats.gpu.empty());
}

} // namespace
