// Scene description (DESIGN.md §3): camera, one rectangular light, objects in world space.
// loadScene() (geometry/reference/Framing.h) accepts the scene JSON or a .gltf/.glb directly
// (then the light, and the camera when the file has no perspective glTF camera, are framed on
// the model's bounds). Every problem with
// the input throws geometry::InputError naming the key or file; nothing is ever silently defaulted
// except the documented optional keys.
#pragma once

#include <geometry/core/Types.h>

#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace geometry {

struct SceneObject {
    std::string name;                          // "objects[3] (box)" or the glTF file name
    ShadowMethod method = ShadowMethod::Auto;  // "method" key
    MeshData mesh;                             // world space, all transforms applied
    // "static" key (default true; glTF levels are static): false keeps the object out of what a
    // method precomputes for the static casters (pdsm's deep map), which then shadows it each
    // frame by another path and composes the two.
    bool isStatic = true;
};

// A camera the scene file offers (a glTF camera node: its name, or "camera N").
struct NamedCamera {
    std::string name;
    Camera camera;
};

struct Scene {
    Camera camera;
    RectLight light;
    std::vector<SceneObject> objects;
    std::filesystem::path source; // the file it was loaded from (empty if built in code)
    // The perspective cameras of a .gltf/.glb loaded directly, in file order (empty for a scene
    // JSON), and how many orthographic ones were skipped (not supported).
    std::vector<NamedCamera> cameras;
    int skippedCameras = 0;
    // Where `camera` comes from: "scene" (the scene JSON), "gltf camera N: NAME" (cameras[N]),
    // "framed" (automatic framing: a .gltf/.glb without a perspective camera); empty when built
    // in code.
    std::string cameraSource;

    Aabb bounds() const;
    std::size_t triangleCount() const;
};

// Parse a scene from JSON text; relative "file" paths resolve against baseDir. Throws InputError.
// `origin` names the source in error messages.
Scene parseScene(const std::string& jsonText, const std::filesystem::path& baseDir,
                 const std::string& origin = "<scene>");

// Checks that the light has finite values and non-zero area and touches no geometry
// (geometry/scene/LightCheck.h), and that the camera is usable. Throws InputError. Called by
// parseScene and loadScene (geometry/reference/Framing.h); public for code that edits a scene.
void validateScene(const Scene& scene);

// The light checks of validateScene for another light than the scene's (moved or scaled: bench
// sweeps, the viewer). `what` names it in messages ("light" when empty). Throws InputError.
void validateLight(const Scene& scene, const RectLight& light, std::string_view what = {});

// The camera checks of validateScene for another camera than the scene's (the viewer's fly
// camera). `what` names it in messages ("camera" when empty). Throws InputError.
void validateCamera(const Camera& camera, std::string_view what = {});

// Makes cameras[index] the scene's camera and names it in cameraSource. Throws InputError when
// the scene has no cameras, index is out of range, or the camera fails validateScene's checks.
void selectCamera(Scene& scene, int index);

// Camera and light framed on bounds: used when a glTF is given directly.
Camera defaultCamera(const Aabb& bounds);
RectLight defaultLight(const Aabb& bounds);

const char* toString(ShadowMethod m);

// An object whose mesh mixes opaque and alpha-tested materials (a game level with a grate, a
// tree with its bark and leaf cards) as two: the opaque triangles under the object's name, and
// the alpha-tested ones under kAlphaTestedSuffix appended to it, each with the vertices,
// materials and textures it uses (renumbered in first use), both with the object's "method".
// Shadow paths are chosen per object (`auto`), and a method that occludes with whole triangles
// can then serve the opaque part while one that honours alpha serves the other. An object of one
// kind comes back alone, unchanged. parseScene and loadScene split every object this way.
inline constexpr const char* kAlphaTestedSuffix = " (alpha-tested)";
std::vector<SceneObject> splitByAlphaTest(SceneObject object);
// Whether some casting object (method not None) has alpha-tested triangles: what a method that
// occludes with whole triangles cannot shadow alone.
bool hasAlphaTestedCasters(const Scene& scene);

} // namespace geometry
