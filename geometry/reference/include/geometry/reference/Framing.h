// Loading scene files, and the automatic camera and light for a model given without a scene
// file (a bare .gltf/.glb is framed by casting rays, hence here with the ray tracer rather than
// in geometry/scene).
#pragma once

#include <geometry/scene/Scene.h>

#include <optional>
#include <span>

namespace geometry {

// Load a scene JSON (.json) or a glTF/GLB file (.gltf/.glb). Throws InputError.
Scene loadScene(const std::filesystem::path& path);

// Makes the automatic framing the scene's camera (cameraSource "framed"): the view loadScene
// gives a .gltf/.glb without cameras (frameInterior's, else defaultCamera). The light is kept.
void selectFramedCamera(Scene& scene);

// For an enclosed model (a game level): finds the most open point of its interior by casting
// rays from a grid of candidate points, puts the camera there looking along its longest free
// horizontal view, and hangs the light under the ceiling above the viewed spot. Returns false,
// leaving the scene unchanged, when no candidate point is enclosed (an object seen from outside:
// then defaultCamera/defaultLight frame its bounds from outside).
bool frameInterior(Scene& scene);

class RayTracer;

// A small area light (a lamp, facing down) hung under the ceiling above the first of `bases` with
// a ceiling over it: 0.85, 0.7 or 0.5 of the way up, its half-width 0.1 × the ceiling height
// (clamped to 0.5–3% of the scene diagonal) and halved until it touches nothing. Nothing when
// every base sees open sky or no size fits. `tracer` is built on `scene`.
std::optional<RectLight> hangLight(const Scene& scene, const RayTracer& tracer,
                                   std::span<const glm::vec3> bases);

// The viewer's lamp for the view of `camera` (hangLight): under the ceiling above the point
// halfway to what the camera looks at, else above the camera. Nothing when neither has a ceiling
// over it or no lamp fits. `tracer` is built on `scene`.
std::optional<RectLight> lampAhead(const Scene& scene, const RayTracer& tracer,
                                   const Camera& camera);

// How a .gltf/.glb seen from one of its glTF cameras is lit, the same in penumbra-render,
// penumbra-bench and the viewer: the viewer's lamp for scene.camera (lampAhead) becomes
// scene.light. Returns what lights the view, for reports: "lamp at the view" when hung; else
// the reason the light was left as it was ("scene light (--scene-light)" with keepSceneLight,
// "scene JSON" for a scene JSON, "framed" for a model seen from its framing, "framed: no
// ceiling above the view to hang a lamp under" when lampAhead finds none). `tracer`, when given,
// is built on `scene` (several views of one scene share it); else one is built when needed.
std::string lightAtView(Scene& scene, bool keepSceneLight, const RayTracer* tracer = nullptr);

} // namespace geometry
