// The viewer's camera and light rig (apps/viewer/ViewerCore.h): conversions that must round-trip
// (a glTF camera opens exactly as stored; a scene light is edited from exactly itself) and moves
// that go where the keys say.
#include "ViewerCore.h"

#include <geometry/scene/Scene.h>

#include <gtest/gtest.h>

#include <glm/gtc/constants.hpp>

#include <vector>

namespace {

void expectNear(const glm::vec3& a, const glm::vec3& b, float tol, const char* what) {
    EXPECT_NEAR(a.x, b.x, tol) << what;
    EXPECT_NEAR(a.y, b.y, tol) << what;
    EXPECT_NEAR(a.z, b.z, tol) << what;
}

glm::vec3 dir(const geometry::Camera& c) { return glm::normalize(c.target - c.eye); }

TEST(ViewerCore, FlyCameraKeepsAStoredView) {
    const glm::vec3 views[] = {{0, 0, -1}, {1, 0, 0}, {0.3f, -0.5f, 0.8f}, {-0.7f, 0.6f, -0.1f}};
    for (const glm::vec3& d : views) {
        geometry::Camera c;
        c.eye = {1.0f, 2.0f, 3.0f};
        c.target = c.eye + 4.0f * d;
        c.fovYDeg = 73.0f;
        const geometry::Camera back = viewer::FlyCamera::fromCamera(c).camera();
        expectNear(back.eye, c.eye, 1e-6f, "eye");
        expectNear(dir(back), glm::normalize(d), 1e-5f, "view direction");
        EXPECT_FLOAT_EQ(back.fovYDeg, 73.0f);
    }
}

TEST(ViewerCore, FlyCameraFarFromTheOriginStaysValid) {
    geometry::Camera c;
    c.eye = {3.0e6f, 10.0f, -2.0e6f};
    c.target = c.eye + glm::vec3(0.0f, 0.0f, -5000.0f);
    const geometry::Camera back = viewer::FlyCamera::fromCamera(c).camera();
    EXPECT_NO_THROW(geometry::validateCamera(back));
    EXPECT_NEAR(dir(back).z, -1.0f, 1e-6f);
}

TEST(ViewerCore, FlyCameraMovesInItsOwnFrame) {
    geometry::Camera c;
    c.eye = {0, 0, 0};
    c.target = {1, 0, 0}; // looking along +X: right = forward x up = +Z
    viewer::FlyCamera fly = viewer::FlyCamera::fromCamera(c);
    fly.speed = 2.0f;
    fly.move({0, 0, 1}, 0.5f); // W for half a second at 2 m/s
    expectNear(fly.eye, {1, 0, 0}, 1e-5f, "forward");
    fly.move({1, 0, 0}, 0.5f); // D
    expectNear(fly.eye, {1, 0, 1}, 1e-5f, "right");
    fly.move({0, 1, 0}, 1.0f); // E
    expectNear(fly.eye, {1, 2, 1}, 1e-5f, "up");
    fly.look(0.0f, 10.0f); // pitch clamps short of straight up: the camera stays valid
    EXPECT_LT(fly.pitch, glm::radians(89.5f));
    EXPECT_GT(glm::length(glm::cross(dir(fly.camera()), glm::vec3(0, 1, 0))), 1e-3f);
}

TEST(ViewerCore, OrbitStartsWhereTheFlyCameraIs) {
    geometry::Camera c;
    c.eye = {2, 1, 0};
    c.target = {0, 0, 0};
    const viewer::FlyCamera fly = viewer::FlyCamera::fromCamera(c);
    viewer::OrbitCamera orbit = viewer::OrbitCamera::around(fly, 3.0f);
    expectNear(orbit.camera().eye, c.eye, 1e-5f, "orbit eye");
    expectNear(dir(orbit.camera()), dir(c), 1e-5f, "orbit view");
    const glm::vec3 pivot = orbit.pivot;
    orbit.rotate(1.0f, 0.2f);
    EXPECT_NEAR(glm::length(orbit.camera().eye - pivot), 3.0f, 1e-4f) << "stays on its sphere";
    orbit.zoom(0.5f);
    EXPECT_NEAR(glm::length(orbit.camera().eye - pivot), 1.5f, 1e-4f);
    orbit.zoom(-1.0f); // ignored
    EXPECT_NEAR(orbit.distance, 1.5f, 1e-6f);
}

TEST(ViewerCore, LightRigRoundTripsRotatedLights) {
    std::vector<geometry::RectLight> lights(3);
    lights[0] = {{0, 6, 0}, {0.5f, 0, 0}, {0, 0, 0.25f}};
    lights[1] = {{1, 2, 3}, {0, 0.3f, 0.4f}, {0.2f, 0, 0}};     // facing sideways
    const glm::vec3 a = glm::normalize(glm::vec3(1, 2, 3));
    const glm::vec3 b = glm::normalize(glm::cross(a, glm::vec3(0.3f, -1, 0.2f)));
    lights[2] = {{-2, 1, 5}, 0.7f * a, 0.1f * b};
    for (const auto& l : lights) {
        const geometry::RectLight back = viewer::LightRig::fromLight(l).light();
        expectNear(back.center, l.center, 1e-6f, "centre");
        expectNear(back.u, l.u, 1e-5f, "u");
        expectNear(back.v, l.v, 1e-5f, "v");
    }
    viewer::LightRig rig; // zero angles: the documented default orientation, facing down
    const geometry::RectLight l = rig.light();
    expectNear(glm::normalize(glm::cross(l.u, l.v)), {0, -1, 0}, 1e-6f, "normal");
}

TEST(ViewerCore, AnimatedLightCirclesInItsPlane) {
    const geometry::RectLight l{{1, 2, 3}, {0, 0.3f, 0.4f}, {0.2f, 0, 0}};
    const viewer::LightRig rig = viewer::LightRig::fromLight(l);
    const glm::vec3 n = glm::normalize(glm::cross(l.u, l.v));
    for (float t = 0.0f; t < 6.0f; t += 0.7f) {
        const geometry::RectLight m = rig.animated(t, 0.5f);
        EXPECT_NEAR(glm::dot(m.center - l.center, n), 0.0f, 1e-5f) << t;
        EXPECT_NEAR(glm::length(m.center - l.center), 0.5f, 1e-5f) << t;
        expectNear(m.u, l.u, 1e-5f, "size and orientation unchanged");
    }
}

TEST(ViewerCore, FlyThroughVisitsEveryCamera) {
    std::vector<geometry::Camera> cams(3);
    cams[0] = {{0, 1, 0}, {0, 1, -1}, {0, 1, 0}, 60};
    cams[1] = {{5, 1, 0}, {6, 1, 0}, {0, 1, 0}, 70};
    cams[2] = {{5, 1, 5}, {5, 1, 6}, {0, 1, 0}, 80};
    for (int i = 0; i < 3; ++i) {
        const geometry::Camera c = viewer::flyThrough(cams, i * 10, 10);
        expectNear(c.eye, cams[i].eye, 1e-6f, "eye at a leg's start");
        expectNear(dir(c), dir(cams[i]), 1e-6f, "view at a leg's start");
    }
    const geometry::Camera wrap = viewer::flyThrough(cams, 30, 10);
    expectNear(wrap.eye, cams[0].eye, 1e-6f, "wraps to the first");
    const geometry::Camera mid = viewer::flyThrough(cams, 5, 10);
    expectNear(mid.eye, {2.5f, 1, 0}, 1e-5f, "halfway along the first leg");
}

} // namespace
