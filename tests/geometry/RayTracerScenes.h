// Scenes for the ray-tracer tests (RayTracerTest) and benchmarks (geometry_bench's ray_tracer
// cases): horizontal quads over a floor under a square light, and grids of floor points.
#pragma once

#include <geometry/reference/Analytic.h>
#include <geometry/scene/Scene.h>

#include <glm/glm.hpp>

#include <cstddef>
#include <string>
#include <vector>

namespace raytracerscenes {

using geometry::HorizontalRect;

// A horizontal quad [x0,x1] x [z0,z1] at height y as two triangles. Built here rather than with
// geometry/Primitives so these tests depend only on the ray tracer.
inline geometry::MeshData horizontalQuad(const HorizontalRect& r, const std::string& name) {
    geometry::MeshData mesh;
    mesh.name = name;
    mesh.positions = {{r.x0, r.y, r.z0}, {r.x1, r.y, r.z0}, {r.x1, r.y, r.z1}, {r.x0, r.y, r.z1}};
    mesh.triangles = {{0, 1, 2}, {0, 2, 3}};
    return mesh;
}

inline geometry::RectLight squareLight() {
    geometry::RectLight light;
    light.center = {0.0f, 6.0f, 0.0f};
    light.u = {0.5f, 0.0f, 0.0f};
    light.v = {0.0f, 0.0f, 0.5f};
    return light;
}

inline constexpr HorizontalRect kFloor{-10.0f, 10.0f, -10.0f, 10.0f, 0.0f};

inline geometry::Scene
makeScene(const std::vector<HorizontalRect>& occluders,
          geometry::ShadowMethod occluderMethod = geometry::ShadowMethod::Auto) {
    geometry::Scene scene;
    scene.light = squareLight();
    scene.objects.push_back(
        {"floor", geometry::ShadowMethod::Auto, horizontalQuad(kFloor, "floor")});
    for (std::size_t i = 0; i < occluders.size(); ++i) {
        const std::string name = "occluder" + std::to_string(i);
        scene.objects.push_back({name, occluderMethod, horizontalQuad(occluders[i], name)});
    }
    return scene;
}

// n x n floor points over [-half, half]^2 (cell centres), normals up (towards viewer and light).
inline void floorGrid(int n, float half, std::vector<glm::vec3>& points,
                      std::vector<glm::vec3>& normals) {
    points.clear();
    normals.clear();
    for (int j = 0; j < n; ++j) {
        for (int i = 0; i < n; ++i) {
            const float x = -half + 2.0f * half * (static_cast<float>(i) + 0.5f) / n;
            const float z = -half + 2.0f * half * (static_cast<float>(j) + 0.5f) / n;
            points.emplace_back(x, 0.0f, z);
            normals.emplace_back(0.0f, 1.0f, 0.0f);
        }
    }
}

// A grate of 64 x 64 squares of side 0.035 at height 2 (8194 triangles with the floor): penumbra
// almost everywhere under it, so shadow rays really traverse the BVH.
inline std::vector<HorizontalRect> grate() {
    std::vector<HorizontalRect> squares;
    for (int j = 0; j < 64; ++j) {
        for (int i = 0; i < 64; ++i) {
            const float x = -1.6f + 0.05f * static_cast<float>(i);
            const float z = -1.6f + 0.05f * static_cast<float>(j);
            squares.push_back({x, x + 0.035f, z, z + 0.035f, 2.0f});
        }
    }
    return squares;
}

} // namespace raytracerscenes
