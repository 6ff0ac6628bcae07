// Interior framing for game levels: a camera outside a roofed level sees only its roof, and a
// light above the bounds leaves the whole interior in shadow. Levels are not closed meshes, so
// "inside" is judged by rays: a point is in the open interior when rays in all 26 grid
// directions hit geometry, almost all of them on the side the faces point to (level brushes
// face into the playable space), and none very close.
#include <geometry/reference/Framing.h>

#include <geometry/core/Error.h>
#include <geometry/scene/GltfLoader.h>
#include <geometry/scene/LightCheck.h>
#include <geometry/reference/RayTracer.h>

#include <algorithm>
#include <cctype>
#include <array>
#include <cmath>
#include <fstream>
#include <iterator>
#include <optional>

namespace geometry {

namespace {

std::array<glm::vec3, 26> gridDirections() {
    std::array<glm::vec3, 26> dirs{};
    int n = 0;
    for (int x = -1; x <= 1; ++x)
        for (int y = -1; y <= 1; ++y)
            for (int z = -1; z <= 1; ++z)
                if (x || y || z) dirs[n++] = glm::normalize(glm::vec3(x, y, z));
    return dirs;
}

struct Candidate {
    glm::vec3 point{0.0f};
    float score = -1.0f;
};

std::string lowerExtension(const std::filesystem::path& p) {
    std::string e = p.extension().string();
    std::transform(e.begin(), e.end(), e.begin(),
                   [](unsigned char c) { return char(std::tolower(c)); });
    return e;
}

} // namespace

std::optional<RectLight> hangLight(const Scene& scene, const RayTracer& tracer,
                                   std::span<const glm::vec3> bases) {
    const Aabb bounds = scene.bounds();
    const float diag = bounds.empty() ? 0.0f : glm::length(bounds.extent());
    if (!(diag > 0.0f)) return std::nullopt;
    // Lowered and shrunk until it touches nothing: a light inside geometry is invalid input.
    const glm::vec3 up(0.0f, 1.0f, 0.0f);
    const float tolerance = 1e-5f * diag;
    for (const glm::vec3& base : bases) {
        float t = 0.0f;
        glm::vec3 n;
        if (!tracer.intersect(base, up, t, n)) continue; // open sky above
        for (float height : {0.85f, 0.7f, 0.5f}) {
            // A small area light (a lamp, not a skylight) that grows with the room.
            for (float half = std::clamp(0.1f * t, 0.005f * diag, 0.03f * diag);
                 half > 0.002f * diag; half *= 0.5f) {
                RectLight light;
                light.center = base + height * t * up;
                light.u = glm::vec3(half, 0.0f, 0.0f);
                light.v = glm::vec3(0.0f, 0.0f, half);
                if (!findLightContact(scene, light, tolerance)) return light;
            }
        }
    }
    return std::nullopt;
}

bool frameInterior(Scene& scene) {
    const Aabb bounds = scene.bounds();
    if (bounds.empty()) return false;
    const glm::vec3 extent = bounds.extent();
    const float diag = glm::length(extent);
    if (!(diag > 0.0f)) return false;

    const RayTracer tracer(scene);
    const auto dirs = gridDirections();
    constexpr int kGrid[3] = {9, 5, 9};
    constexpr int kMinFrontHits = 23; // of 26: tolerate a few back faces seen through cracks
    const float minClearance = 0.02f * diag;

    Candidate best;
    for (int i = 0; i < kGrid[0]; ++i)
        for (int j = 0; j < kGrid[1]; ++j)
            for (int k = 0; k < kGrid[2]; ++k) {
                const glm::vec3 f((i + 0.5f) / kGrid[0], (j + 0.5f) / kGrid[1],
                                  (k + 0.5f) / kGrid[2]);
                const glm::vec3 p = bounds.min + f * extent;
                int front = 0;
                float sum = 0.0f, nearest = INFINITY;
                bool enclosed = true;
                for (const glm::vec3& d : dirs) {
                    float t = 0.0f;
                    glm::vec3 n;
                    if (!tracer.intersect(p, d, t, n)) {
                        enclosed = false;
                        break;
                    }
                    front += glm::dot(n, d) < 0.0f;
                    sum += t;
                    nearest = std::min(nearest, t);
                }
                if (!enclosed || front < kMinFrontHits || nearest < minClearance) continue;
                // Mean free distance, weighted by clearance so the camera stays off the walls.
                const float score = (sum / dirs.size()) * std::min(nearest / (0.1f * diag), 1.0f);
                if (score > best.score) best = {p, score};
            }
    if (best.score < 0.0f) return false;

    // Look along the longest free, slightly downward direction.
    glm::vec3 view(1.0f, 0.0f, 0.0f);
    float viewLength = 0.0f;
    for (int a = 0; a < 16; ++a) {
        const float phi = 2.0f * 3.14159265f * a / 16.0f;
        const glm::vec3 d = glm::normalize(glm::vec3(std::cos(phi), -0.25f, std::sin(phi)));
        float t = 0.0f;
        glm::vec3 n;
        if (tracer.intersect(best.point, d, t, n) && t > viewLength) {
            viewLength = t;
            view = d;
        }
    }
    if (viewLength <= 0.0f) return false;

    Camera camera;
    camera.eye = best.point;
    camera.target = best.point + 0.5f * viewLength * view;
    camera.up = glm::vec3(0.0f, 1.0f, 0.0f);
    camera.fovYDeg = 70.0f;

    // Light: under the ceiling above the middle of the view (or above the camera).
    const glm::vec3 bases[] = {camera.target, camera.eye};
    const std::optional<RectLight> light = hangLight(scene, tracer, bases);
    if (!light) return false;
    scene.light = *light;

    scene.camera = camera;
    return true;
}

void selectFramedCamera(Scene& scene) {
    const RectLight light = scene.light;
    if (!frameInterior(scene)) scene.camera = defaultCamera(scene.bounds());
    scene.light = light;
    scene.cameraSource = "framed";
}

Scene loadScene(const std::filesystem::path& path) {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec)) {
        throw InputError(path.string() + ": scene file not found");
    }
    const std::string ext = lowerExtension(path);
    Scene scene;
    if (ext == ".gltf" || ext == ".glb") {
        GltfContents gltf = loadGltfWithCameras(path);
        SceneObject obj;
        obj.mesh = std::move(gltf.mesh);
        obj.name = path.filename().string();
        scene.objects = splitByAlphaTest(std::move(obj));
        const Aabb b = scene.bounds();
        scene.camera = defaultCamera(b);
        scene.light = defaultLight(b);
        frameInterior(scene); // a game level: look from inside, light under the ceiling
        scene.cameraSource = "framed";
        // The file's own view wins over the framing; the light stays framed either way.
        for (GltfCamera& c : gltf.cameras)
            scene.cameras.push_back({std::move(c.name), c.camera});
        scene.skippedCameras = gltf.orthographicCameras;
        scene.source = path; // named in selectCamera's messages
        if (!scene.cameras.empty()) selectCamera(scene, 0);
    } else if (ext == ".json") {
        std::ifstream in(path, std::ios::binary);
        if (!in) throw InputError(path.string() + ": cannot open scene file");
        const std::string text((std::istreambuf_iterator<char>(in)),
                               std::istreambuf_iterator<char>());
        scene = parseScene(text, path.parent_path(), path.string());
        scene.cameraSource = "scene";
    } else {
        throw InputError(path.string() +
                         ": unsupported scene file type (expected .json, .gltf or .glb)");
    }
    scene.source = path;
    validateScene(scene);
    return scene;
}

std::optional<RectLight> lampAhead(const Scene& scene, const RayTracer& tracer,
                                   const Camera& camera) {
    const glm::vec3 forward = glm::normalize(camera.target - camera.eye);
    std::vector<glm::vec3> bases;
    float t = 0.0f;
    glm::vec3 n;
    if (tracer.intersect(camera.eye, forward, t, n))
        bases.push_back(camera.eye + 0.5f * t * forward);
    bases.push_back(camera.eye);
    return hangLight(scene, tracer, bases);
}

std::string lightAtView(Scene& scene, bool keepSceneLight, const RayTracer* tracer) {
    if (scene.cameras.empty()) return scene.cameraSource == "scene" ? "scene JSON" : "framed";
    if (keepSceneLight) return "scene light (--scene-light)";
    if (scene.cameraSource == "framed") return "framed";
    std::optional<RayTracer> own;
    if (!tracer) tracer = &own.emplace(scene);
    const std::optional<RectLight> lamp = lampAhead(scene, *tracer, scene.camera);
    if (!lamp) return "framed: no ceiling above the view to hang a lamp under";
    scene.light = *lamp;
    return "lamp at the view";
}

} // namespace geometry
