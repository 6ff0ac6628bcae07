// Scene JSON (DESIGN.md §3) → Scene, with strict validation: every problem is an InputError that
// names the file and the key path ("scene.json: objects[2].size: expected 3 numbers").
//
// Required / optional keys (anything else is an error):
//   camera   required: eye, target          optional: up = [0,1,0], fov_y_deg = 50
//   light    required: center, u, v
//   objects  required, non-empty array; each object has "type" and optionally "name",
//            "method" (auto | wedges | occlusion | none, default auto), "static" (true |
//            false, default true: false keeps it out of what a method precomputes for the
//            static casters, pdsm's deep map), plus per type:
//     gltf   required: file              optional: translate = [0,0,0], rotate_deg = [0,0,0],
//                                                  scale = 1 (number or [x,y,z], all > 0)
//     box    required: center, size (all > 0)   optional: rotate_deg = [0,0,0] (about center)
//     quad   required: center, u, v (non-zero area)
//     sphere required: center, radius (> 0)   optional: segments = 32 (integer in [3, 4096])
//     torus  required: center, major_radius, minor_radius (major > minor > 0)
//            optional: major_segments = 48, minor_segments = 24 (integers in [3, 4096]),
//                      rotate_deg = [0,0,0] (about center; unrotated, the axis is +y)
// Budgets (geometry/core/Limits.h), checked before an object is built: a sphere or torus has at most
// kMaxObjectTriangles triangles (segments <= 1449; major x minor <= 1,048,576), the scene at most
// kMaxSceneTriangles; every coordinate is within +-kMaxCoordinate.
// rotate_deg is always Euler angles in degrees about fixed X, then Y, then Z (world = Rz Ry Rx).
// Camera and light are required because a silently invented view or light would make renders and
// benchmark numbers meaningless; "up" and the field of view have obvious conventional defaults.
#include <geometry/scene/Scene.h>

#include <geometry/core/Error.h>
#include <geometry/scene/AlphaMask.h>
#include <geometry/scene/GltfLoader.h>
#include <geometry/scene/LightCheck.h>
#include <geometry/core/Limits.h>
#include <geometry/scene/Primitives.h>

#include "JsonDepth.h"

#include <nlohmann/json.hpp>

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <fstream>
#include <initializer_list>
#include <iterator>
#include <set>
#include <sstream>
#include <string_view>

namespace geometry {
namespace {

using Json = nlohmann::json;

// Nesting a scene JSON may have. Its own structure is 4 levels deep ({"objects": [{"center":
// [...]}]}); the bound keeps recursive code (nlohmann's dump() in messages, which echo the
// offending value) from exhausting the stack on hostile input.
constexpr std::size_t kMaxSceneJsonDepth = 64;

std::string fmt(const glm::vec3& v) {
    std::ostringstream s;
    s << "[" << v.x << ", " << v.y << ", " << v.z << "]";
    return s.str();
}

bool finite(const glm::vec3& v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

std::string fmtNumber(double x) {
    std::ostringstream s;
    s << x;
    return s.str();
}

// "" when every component is within +-kMaxCoordinate (geometry/core/Limits.h), else what is wrong.
std::string outOfRange(const glm::vec3& v) {
    for (int axis = 0; axis < 3; ++axis) {
        if (std::abs(v[axis]) > kMaxCoordinate)
            return fmt(v) + " is outside [-" + fmtNumber(kMaxCoordinate) + ", " +
                   fmtNumber(kMaxCoordinate) +
                   "] (coordinates that large cannot be rendered in single precision)";
    }
    return {};
}

// Camera and light checks shared by the parser, validateScene() and validateLight(); `fail` gets
// the key path.
template <class Fail>
void checkCamera(const Camera& cam, Fail&& fail) {
    if (!finite(cam.eye)) fail("camera.eye", "must be finite");
    if (!finite(cam.target)) fail("camera.target", "must be finite");
    if (!finite(cam.up)) fail("camera.up", "must be finite");
    if (const std::string e = outOfRange(cam.eye); !e.empty()) fail("camera.eye", e);
    if (const std::string e = outOfRange(cam.target); !e.empty()) fail("camera.target", e);
    if (!std::isfinite(cam.fovYDeg) || !(cam.fovYDeg > 0.0f && cam.fovYDeg < 180.0f)) {
        fail("camera.fov_y_deg", "must be in (0, 180), got " + std::to_string(cam.fovYDeg));
    }
    const glm::vec3 view = cam.target - cam.eye;
    const float scale = std::max({glm::length(cam.eye), glm::length(cam.target), 1.0f});
    if (!(glm::length(view) > 1e-6f * scale)) {
        fail("camera.target", "must differ from camera.eye (both " + fmt(cam.eye) + ")");
    }
    const float upLen = glm::length(cam.up);
    if (!(upLen > 0.0f)) fail("camera.up", "must not be zero");
    // sin of the angle between up and the view direction; tiny means the basis is undefined.
    if (!(glm::length(glm::cross(view / glm::length(view), cam.up / upLen)) > 1e-4f)) {
        fail("camera.up", fmt(cam.up) + " is parallel to the view direction");
    }
}

template <class Fail>
void checkLight(const RectLight& light, Fail&& fail) {
    if (!finite(light.center)) fail("light.center", "must be finite");
    if (!finite(light.u)) fail("light.u", "must be finite");
    if (!finite(light.v)) fail("light.v", "must be finite");
    if (const std::string e = outOfRange(light.center); !e.empty()) fail("light.center", e);
    if (const std::string e = outOfRange(light.u); !e.empty()) fail("light.u", e);
    if (const std::string e = outOfRange(light.v); !e.empty()) fail("light.v", e);
    // In double: squared lengths of float vectors overflow float long before the vectors do.
    const glm::dvec3 u(light.u), v(light.v);
    const double lu = glm::length(u);
    const double lv = glm::length(v);
    if (!(lu > 0.0)) fail("light.u", "must have non-zero length");
    if (!(lv > 0.0)) fail("light.v", "must have non-zero length");
    // Relative: |u x v| = |u||v| sin(angle), so this rejects (nearly) parallel axes at any scale.
    if (!(glm::length(glm::cross(u, v)) > 1e-6 * lu * lv)) {
        fail("light", "u " + fmt(light.u) + " and v " + fmt(light.v) +
                          " are parallel: the light has zero area");
    }
}

// Every vertex within +-kMaxCoordinate; `fail` gets the object's name and what is wrong.
template <class Fail>
void checkObjectCoordinates(const SceneObject& object, Fail&& fail) {
    const std::vector<glm::vec3>& positions = object.mesh.positions;
    for (std::size_t i = 0; i < positions.size(); ++i) {
        if (const std::string e = outOfRange(positions[i]); !e.empty())
            fail(object.name, "vertex " + std::to_string(i) + " at " + e);
    }
}

template <class Fail>
void checkCameraAndLight(const Camera& cam, const RectLight& light, Fail&& fail) {
    checkCamera(cam, fail);
    checkLight(light, fail);
}

// Euler rotation in degrees about fixed axes: X first, then Y, then Z (the usual reading of
// "XYZ" in DCC tools), as a 4x4 so it composes with translation and scale.
glm::mat4 rotationXyzDeg(const glm::vec3& deg) {
    glm::mat4 m(1.0f);
    m = glm::rotate(m, glm::radians(deg.z), glm::vec3(0, 0, 1));
    m = glm::rotate(m, glm::radians(deg.y), glm::vec3(0, 1, 0));
    m = glm::rotate(m, glm::radians(deg.x), glm::vec3(1, 0, 0));
    return m;
}

// Rotates a mesh about `center`. A rotation keeps the winding outward (determinant +1).
void rotateAbout(MeshData& mesh, const glm::vec3& center, const glm::vec3& deg) {
    if (deg == glm::vec3(0.0f)) return; // keep unrotated shapes bit-exact
    const glm::mat3 r(rotationXyzDeg(deg));
    for (glm::vec3& p : mesh.positions)
        p = center + r * (p - center);
    for (glm::vec3& n : mesh.normals)
        n = r * n; // a rotation: its own inverse transpose
}

class SceneParser {
public:
    SceneParser(std::string origin, std::filesystem::path baseDir)
        : mOrigin(std::move(origin)), mBaseDir(std::move(baseDir)) {}

    Scene parse(const std::string& text);

private:
    [[noreturn]] void fail(const std::string& keyPath, const std::string& what) const {
        throw InputError(mOrigin + ": " + (keyPath.empty() ? "" : keyPath + ": ") + what);
    }

    Json parseJson(const std::string& text) const;
    void requireObject(const Json& j, const std::string& path) const;
    void checkKeys(const Json& j, const std::string& path,
                   std::initializer_list<std::string_view> allowed) const;
    const Json& require(const Json& j, const std::string& path, const char* key) const;
    double number(const Json& j, const std::string& path) const;
    glm::vec3 vec3(const Json& j, const std::string& path) const;
    std::string string(const Json& j, const std::string& path) const;
    // Optional integer key in [lo, hi]; `fallback` when absent.
    int optionalInt(const Json& j, const std::string& path, const char* key, int fallback, int lo,
                    int hi) const;
    // Optional rotate_deg (finite Euler angles); zero when absent.
    glm::vec3 optionalRotation(const Json& j, const std::string& path) const;

    // Refuses an object of `triangles` (described by `what`) over the per-object budget or
    // the scene's (with the objects parsed so far), before it is built; `hint` says what fits.
    void checkBudget(const std::string& keyPath, std::size_t triangles, const std::string& what,
                     const std::string& hint) const;

    Camera parseCamera(const Json& j) const;
    RectLight parseLight(const Json& j) const;
    SceneObject parseObject(const Json& j, std::size_t index) const;

    std::string mOrigin;
    std::filesystem::path mBaseDir;
    std::size_t mTriangles = 0; // of the objects parsed so far
};

// 16760832 -> "16,760,832".
std::string grouped(std::size_t n) {
    std::string digits = std::to_string(n), out;
    for (std::size_t i = 0; i < digits.size(); ++i) {
        if (i > 0 && (digits.size() - i) % 3 == 0) out += ',';
        out += digits[i];
    }
    return out;
}

void SceneParser::checkBudget(const std::string& keyPath, std::size_t triangles,
                              const std::string& what, const std::string& hint) const {
    if (triangles > kMaxObjectTriangles) {
        fail(keyPath, what + " would have " + grouped(triangles) + " triangles, more than the " +
                          grouped(kMaxObjectTriangles) + " one object may have (" + hint + ")");
    }
    if (mTriangles + triangles > kMaxSceneTriangles) {
        fail(keyPath, what + " would bring the scene to " + grouped(mTriangles + triangles) +
                          " triangles, more than the " + grouped(kMaxSceneTriangles) +
                          " a scene may have");
    }
}

Json SceneParser::parseJson(const std::string& text) const {
    if (const detail::JsonDepth d = detail::jsonNestingDepth(text, kMaxSceneJsonDepth);
        d.depth > kMaxSceneJsonDepth) {
        throw InputError(mOrigin + ": JSON nested deeper than " +
                         std::to_string(kMaxSceneJsonDepth) + " levels (at byte " +
                         std::to_string(d.offset) + "); a scene is 4 levels deep");
    }
    // The parser callback follows the key path of the value being parsed, so that errors raised
    // inside the JSON parser (a number like 1e999 that overflows) can still name their key, and
    // catches duplicated keys, which nlohmann would silently resolve to the last one.
    struct Frame {
        bool array = false;
        std::string key;            // object: key of the member being parsed
        std::size_t index = 0;      // array: index of the element being parsed
        std::set<std::string> keys; // object: keys seen so far
    };
    std::vector<Frame> stack;
    auto currentPath = [&stack] {
        std::string path;
        for (const Frame& f : stack) {
            // Appended piecewise: GCC 12 warns (-Wrestrict, falsely) on "[" + to_string() here.
            if (f.array) {
                path += '[';
                path += std::to_string(f.index);
                path += ']';
            } else if (!f.key.empty()) {
                if (!path.empty()) path += '.';
                path += f.key;
            }
        }
        return path;
    };
    auto elementDone = [&stack] {
        if (!stack.empty() && stack.back().array) ++stack.back().index;
    };
    auto callback = [&](int, Json::parse_event_t event, Json& parsed) {
        switch (event) {
        case Json::parse_event_t::object_start:
            stack.push_back({});
            break;
        case Json::parse_event_t::array_start:
            stack.push_back({.array = true});
            break;
        case Json::parse_event_t::object_end:
        case Json::parse_event_t::array_end:
            stack.pop_back();
            elementDone();
            break;
        case Json::parse_event_t::key: {
            const std::string key = parsed.get<std::string>();
            stack.back().key = key;
            if (!stack.back().keys.insert(key).second) {
                fail(currentPath(), "duplicate key \"" + key + "\"");
            }
            break;
        }
        case Json::parse_event_t::value:
            elementDone();
            break;
        }
        return true;
    };
    try {
        return Json::parse(text, callback);
    } catch (const Json::parse_error& e) {
        // e.what() already says "parse error at line L, column C: ..."; drop the library prefix.
        std::string msg = e.what();
        if (auto p = msg.find("] "); msg.rfind("[json.exception", 0) == 0 && p != msg.npos) {
            msg = msg.substr(p + 2);
        }
        const std::string where = currentPath();
        throw InputError(mOrigin + ": JSON syntax error at byte " + std::to_string(e.byte) +
                         (where.empty() ? "" : " (in " + where + ")") + ": " + msg);
    } catch (const Json::out_of_range& e) {
        // The only out_of_range the parser raises is a number too large for a double.
        std::string msg = e.what();
        if (auto p = msg.find("] "); p != msg.npos) msg = msg.substr(p + 2);
        fail(currentPath(), "expected a finite number (" + msg + ")");
    } catch (const Json::exception& e) {
        fail(currentPath(), std::string("invalid JSON: ") + e.what());
    }
}

void SceneParser::requireObject(const Json& j, const std::string& path) const {
    if (!j.is_object()) fail(path, std::string("expected an object, got ") + j.type_name());
}

void SceneParser::checkKeys(const Json& j, const std::string& path,
                            std::initializer_list<std::string_view> allowed) const {
    for (const auto& [key, value] : j.items()) {
        if (std::find(allowed.begin(), allowed.end(), key) == allowed.end()) {
            std::string list;
            for (auto a : allowed)
                list += (list.empty() ? "" : ", ") + std::string(a);
            fail(path.empty() ? key : path + "." + key, "unknown key (allowed here: " + list + ")");
        }
    }
}

const Json& SceneParser::require(const Json& j, const std::string& path, const char* key) const {
    auto it = j.find(key);
    if (it == j.end()) fail(path.empty() ? key : path + "." + key, "required key is missing");
    return *it;
}

double SceneParser::number(const Json& j, const std::string& path) const {
    if (!j.is_number()) fail(path, std::string("expected a number, got ") + j.dump());
    const double v = j.get<double>();
    if (!std::isfinite(v) || !std::isfinite(float(v))) {
        fail(path, "expected a finite number, got " + j.dump());
    }
    return v;
}

glm::vec3 SceneParser::vec3(const Json& j, const std::string& path) const {
    if (!j.is_array() || j.size() != 3 ||
        !std::all_of(j.begin(), j.end(), [](const Json& e) { return e.is_number(); })) {
        fail(path, "expected 3 numbers, got " + j.dump());
    }
    return glm::vec3(float(number(j[0], path + "[0]")), float(number(j[1], path + "[1]")),
                     float(number(j[2], path + "[2]")));
}

std::string SceneParser::string(const Json& j, const std::string& path) const {
    if (!j.is_string()) fail(path, std::string("expected a string, got ") + j.dump());
    return j.get<std::string>();
}

int SceneParser::optionalInt(const Json& j, const std::string& path, const char* key, int fallback,
                             int lo, int hi) const {
    auto it = j.find(key);
    if (it == j.end()) return fallback;
    const std::string keyPath = path + "." + key;
    const double v = number(*it, keyPath);
    if (v != std::floor(v) || v < lo || v > hi) {
        fail(keyPath, "expected an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) +
                          "], got " + it->dump());
    }
    return int(v);
}

glm::vec3 SceneParser::optionalRotation(const Json& j, const std::string& path) const {
    auto it = j.find("rotate_deg");
    return it == j.end() ? glm::vec3(0.0f) : vec3(*it, path + ".rotate_deg");
}

Camera SceneParser::parseCamera(const Json& j) const {
    requireObject(j, "camera");
    checkKeys(j, "camera", {"eye", "target", "up", "fov_y_deg"});
    Camera cam;
    cam.eye = vec3(require(j, "camera", "eye"), "camera.eye");
    cam.target = vec3(require(j, "camera", "target"), "camera.target");
    cam.up = j.contains("up") ? vec3(j["up"], "camera.up") : glm::vec3(0.0f, 1.0f, 0.0f);
    cam.fovYDeg =
        j.contains("fov_y_deg") ? float(number(j["fov_y_deg"], "camera.fov_y_deg")) : 50.0f;
    return cam;
}

RectLight SceneParser::parseLight(const Json& j) const {
    requireObject(j, "light");
    checkKeys(j, "light", {"center", "u", "v"});
    RectLight light;
    light.center = vec3(require(j, "light", "center"), "light.center");
    light.u = vec3(require(j, "light", "u"), "light.u");
    light.v = vec3(require(j, "light", "v"), "light.v");
    return light;
}

SceneObject SceneParser::parseObject(const Json& j, std::size_t index) const {
    const std::string path = "objects[" + std::to_string(index) + "]";
    requireObject(j, path);
    const std::string type = string(require(j, path, "type"), path + ".type");
    auto key = [&](const char* k) { return path + "." + k; };

    SceneObject obj;
    if (auto it = j.find("method"); it != j.end()) {
        const std::string m = string(*it, key("method"));
        if (m == "auto") {
            obj.method = ShadowMethod::Auto;
        } else if (m == "wedges") {
            obj.method = ShadowMethod::Wedges;
        } else if (m == "occlusion") {
            obj.method = ShadowMethod::Occlusion;
        } else if (m == "none") {
            obj.method = ShadowMethod::None;
        } else {
            fail(key("method"),
                 "unknown method \"" + m + "\" (expected auto, wedges, occlusion or none)");
        }
    }
    if (auto it = j.find("name"); it != j.end()) obj.name = string(*it, key("name"));
    if (auto it = j.find("static"); it != j.end()) {
        if (!it->is_boolean()) fail(key("static"), "expected true or false, got " + it->dump());
        obj.isStatic = it->get<bool>();
    }

    // Shape constructors validate too; their errors get this object's key path in front.
    auto build = [&](auto&& make) {
        try {
            return make();
        } catch (const InputError& e) {
            fail(path, e.what());
        }
    };

    if (type == "gltf") {
        checkKeys(j, path, {"type", "name", "method", "static", "file", "translate", "rotate_deg", "scale"});
        const std::string file = string(require(j, path, "file"), key("file"));
        if (file.empty()) fail(key("file"), "must not be empty");
        std::filesystem::path resolved(file);
        if (resolved.is_relative()) resolved = mBaseDir / resolved;
        std::error_code ec;
        if (!std::filesystem::is_regular_file(resolved, ec)) {
            fail(key("file"), "file not found: " + resolved.string());
        }
        const glm::vec3 t =
            j.contains("translate") ? vec3(j["translate"], key("translate")) : glm::vec3(0.0f);
        const glm::vec3 r = optionalRotation(j, path);
        glm::vec3 s(1.0f);
        if (auto it = j.find("scale"); it != j.end()) {
            if (it->is_array()) {
                s = vec3(*it, key("scale"));
            } else if (it->is_number()) {
                s = glm::vec3(float(number(*it, key("scale"))));
            } else {
                fail(key("scale"), "expected a number or 3 numbers, got " + it->dump());
            }
            if (!(s.x > 0.0f && s.y > 0.0f && s.z > 0.0f)) {
                fail(key("scale"), "must be > 0, got " + it->dump());
            }
        }
        // World = T * Rz * Ry * Rx * S.
        const glm::mat4 m = glm::scale(glm::translate(glm::mat4(1.0f), t) * rotationXyzDeg(r), s);
        try {
            obj.mesh = loadGltf(resolved, m);
        } catch (const InputError& e) {
            fail(key("file"), e.what());
        }

        if (obj.name.empty()) obj.name = resolved.filename().string();
    } else if (type == "box") {
        checkKeys(j, path, {"type", "name", "method", "static", "center", "size", "rotate_deg"});
        const glm::vec3 c = vec3(require(j, path, "center"), key("center"));
        const glm::vec3 size = vec3(require(j, path, "size"), key("size"));
        if (!(size.x > 0.0f && size.y > 0.0f && size.z > 0.0f)) {
            fail(key("size"), "every component must be > 0, got " + fmt(size));
        }
        const glm::vec3 r = optionalRotation(j, path);
        obj.mesh = build([&] { return makeBox(c, size); });
        rotateAbout(obj.mesh, c, r);
    } else if (type == "quad") {
        checkKeys(j, path, {"type", "name", "method", "static", "center", "u", "v"});
        const glm::vec3 c = vec3(require(j, path, "center"), key("center"));
        const glm::vec3 u = vec3(require(j, path, "u"), key("u"));
        const glm::vec3 v = vec3(require(j, path, "v"), key("v"));
        obj.mesh = build([&] { return makeQuad(c, u, v); });
    } else if (type == "sphere") {
        checkKeys(j, path, {"type", "name", "method", "static", "center", "radius", "segments"});
        const glm::vec3 c = vec3(require(j, path, "center"), key("center"));
        const double radius = number(require(j, path, "radius"), key("radius"));
        if (!(radius > 0.0)) fail(key("radius"), "must be > 0, got " + std::to_string(radius));
        const int segments = optionalInt(j, path, "segments", 32, 3, 4096);
        int fits = 4096;
        while (fits > 3 && sphereTriangleCount(fits) > kMaxObjectTriangles)
            --fits;
        checkBudget(key("segments"), sphereTriangleCount(segments),
                    "a sphere of " + std::to_string(segments) + " segments",
                    "segments at most " + std::to_string(fits));
        obj.mesh = build([&] { return makeSphere(c, float(radius), segments); });
    } else if (type == "torus") {
        checkKeys(j, path,
                  {"type", "name", "method", "static", "center", "major_radius", "minor_radius",
                   "major_segments", "minor_segments", "rotate_deg"});
        const glm::vec3 c = vec3(require(j, path, "center"), key("center"));
        const double major = number(require(j, path, "major_radius"), key("major_radius"));
        const double minor = number(require(j, path, "minor_radius"), key("minor_radius"));
        if (!(major > 0.0)) {
            fail(key("major_radius"), "must be > 0, got " + std::to_string(major));
        }
        if (!(minor > 0.0)) {
            fail(key("minor_radius"), "must be > 0, got " + std::to_string(minor));
        }
        // minor >= major is a horn or spindle torus through its own axis: not a closed manifold.
        if (!(float(minor) < float(major))) {
            fail(key("minor_radius"), "must be < major_radius (" + std::to_string(major) +
                                          "), got " + std::to_string(minor));
        }
        const int majorSegments = optionalInt(j, path, "major_segments", 48, 3, 4096);
        const int minorSegments = optionalInt(j, path, "minor_segments", 24, 3, 4096);
        checkBudget(key("major_segments"), torusTriangleCount(majorSegments, minorSegments),
                    "a torus of " + std::to_string(majorSegments) + " x " +
                        std::to_string(minorSegments) + " segments",
                    "major_segments x minor_segments at most " +
                        grouped(kMaxObjectTriangles / 2));
        const glm::vec3 r = optionalRotation(j, path);
        obj.mesh = build(
            [&] { return makeTorus(c, float(major), float(minor), majorSegments, minorSegments); });
        rotateAbout(obj.mesh, c, r);
    } else {
        fail(key("type"),
             "unknown type \"" + type + "\" (expected gltf, box, quad, sphere or torus)");
    }
    if (obj.name.empty()) obj.name = path + " (" + type + ")";
    return obj;
}

Scene SceneParser::parse(const std::string& text) {
    const Json root = parseJson(text);
    requireObject(root, "");
    checkKeys(root, "", {"camera", "light", "objects"});

    Scene scene;
    scene.camera = parseCamera(require(root, "", "camera"));
    scene.light = parseLight(require(root, "", "light"));
    checkCameraAndLight(scene.camera, scene.light,
                        [this](const std::string& k, const std::string& w) { fail(k, w); });

    const Json& objects = require(root, "", "objects");
    if (!objects.is_array()) {
        fail("objects", std::string("expected an array, got ") + objects.type_name());
    }
    if (objects.empty()) fail("objects", "must contain at least one object");
    for (std::size_t i = 0; i < objects.size(); ++i) {
        SceneObject parsed = parseObject(objects[i], i);
        // Spheres and tori were checked before they were built, a glTF file is bounded by its
        // loader; the sum is bounded here.
        const std::size_t n = parsed.mesh.triangles.size();
        if (mTriangles + n > kMaxSceneTriangles) {
            fail("objects[" + std::to_string(i) + "]",
                 "its " + grouped(n) + " triangles would bring the scene to " +
                     grouped(mTriangles + n) + " triangles, more than the " +
                     grouped(kMaxSceneTriangles) + " a scene may have");
        }
        mTriangles += n;
        checkObjectCoordinates(parsed, [&](const std::string&, const std::string& w) {
            fail("objects[" + std::to_string(i) + "]", w);
        });
        for (SceneObject& part : splitByAlphaTest(std::move(parsed)))
            scene.objects.push_back(std::move(part));
    }
    return scene;
}

} // namespace

std::vector<SceneObject> splitByAlphaTest(SceneObject object) {
    const MeshData& mesh = object.mesh;
    std::vector<SceneObject> out;
    if (!hasAlphaMask(mesh)) {
        out.push_back(std::move(object));
        return out;
    }
    auto tested = [&](std::size_t t) {
        const std::uint32_t m = mesh.triangleMaterial[t];
        return m < mesh.materials.size() && isAlphaMasked(mesh.materials[m]);
    };
    std::size_t alphaTriangles = 0;
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) alphaTriangles += tested(t);
    if (alphaTriangles == mesh.triangles.size()) {
        out.push_back(std::move(object));
        return out;
    }
    // One part: the triangles whose test is `alpha`, their vertices renumbered in first use.
    auto part = [&](bool alpha) {
        SceneObject o;
        o.name = alpha ? object.name + kAlphaTestedSuffix : object.name;
        o.method = object.method;
        o.isStatic = object.isStatic;
        o.mesh.name = mesh.name;
        // The materials its triangles use, and their textures, renumbered in first use.
        std::vector<std::uint32_t> materialIndex(mesh.materials.size(), UINT32_MAX);
        std::vector<int> textureIndex(mesh.textures.size(), -1);
        auto material = [&](std::uint32_t m) {
            if (materialIndex[m] == UINT32_MAX) {
                materialIndex[m] = static_cast<std::uint32_t>(o.mesh.materials.size());
                Material copy = mesh.materials[m];
                const int t = copy.baseColorTexture;
                if (t >= 0 && std::size_t(t) < mesh.textures.size()) {
                    if (textureIndex[std::size_t(t)] < 0) {
                        textureIndex[std::size_t(t)] = static_cast<int>(o.mesh.textures.size());
                        o.mesh.textures.push_back(mesh.textures[std::size_t(t)]);
                    }
                    copy.baseColorTexture = textureIndex[std::size_t(t)];
                }
                o.mesh.materials.push_back(std::move(copy));
            }
            return materialIndex[m];
        };
        std::vector<std::uint32_t> index(mesh.positions.size(), UINT32_MAX);
        for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
            if (tested(t) != alpha) continue;
            glm::uvec3 tri;
            for (int k = 0; k < 3; ++k) {
                std::uint32_t& v = index[mesh.triangles[t][k]];
                if (v == UINT32_MAX) {
                    v = static_cast<std::uint32_t>(o.mesh.positions.size());
                    o.mesh.positions.push_back(mesh.positions[mesh.triangles[t][k]]);
                    if (!mesh.texcoords.empty())
                        o.mesh.texcoords.push_back(mesh.texcoords[mesh.triangles[t][k]]);
                    if (!mesh.normals.empty())
                        o.mesh.normals.push_back(mesh.normals[mesh.triangles[t][k]]);
                }
                tri[k] = v;
            }
            o.mesh.triangles.push_back(tri);
            o.mesh.triangleMaterial.push_back(material(mesh.triangleMaterial[t]));
        }
        return o;
    };
    out.push_back(part(false));
    out.push_back(part(true));
    return out;
}

bool hasAlphaTestedCasters(const Scene& scene) {
    return std::any_of(scene.objects.begin(), scene.objects.end(), [](const SceneObject& o) {
        return o.method != ShadowMethod::None && hasAlphaMask(o.mesh);
    });
}

Aabb Scene::bounds() const {
    Aabb b;
    for (const auto& o : objects)
        b.extend(o.mesh.bounds());
    return b;
}

std::size_t Scene::triangleCount() const {
    std::size_t n = 0;
    for (const auto& o : objects)
        n += o.mesh.triangles.size();
    return n;
}

Scene parseScene(const std::string& jsonText, const std::filesystem::path& baseDir,
                 const std::string& origin) {
    return SceneParser(origin, baseDir).parse(jsonText);
}

void validateScene(const Scene& scene) {
    const std::string origin = scene.source.empty() ? "scene" : scene.source.string();
    checkCameraAndLight(scene.camera, scene.light, [&](const std::string& k, const std::string& w) {
        throw InputError(origin + ": " + k + ": " + w);
    });
    if (scene.triangleCount() > kMaxSceneTriangles) {
        throw InputError(origin + ": " + grouped(scene.triangleCount()) +
                         " triangles, more than the " + grouped(kMaxSceneTriangles) +
                         " a scene may have");
    }
    for (const SceneObject& object : scene.objects) {
        checkObjectCoordinates(object, [&](const std::string& name, const std::string& w) {
            throw InputError(origin + ": object '" + name + "': " + w);
        });
    }
    // A light inside or touching geometry makes the visibility integral meaningless.
    validateLightClear(scene);
}

void selectCamera(Scene& scene, int index) {
    const std::string origin = scene.source.empty() ? "scene" : scene.source.string();
    if (scene.cameras.empty()) {
        throw InputError(origin + ": has no glTF cameras to choose from (camera " +
                         std::to_string(index) + " asked for)");
    }
    if (index < 0 || std::size_t(index) >= scene.cameras.size()) {
        throw InputError(origin + ": camera " + std::to_string(index) + " does not exist (" +
                         std::to_string(scene.cameras.size()) + " glTF cameras: 0 to " +
                         std::to_string(scene.cameras.size() - 1) + ")");
    }
    const NamedCamera& c = scene.cameras[std::size_t(index)];
    checkCamera(c.camera, [&](const std::string& k, const std::string& w) {
        throw InputError(origin + ": glTF camera " + std::to_string(index) + " (" + c.name +
                         "): " + k + ": " + w);
    });
    scene.camera = c.camera;
    scene.cameraSource = "gltf camera " + std::to_string(index) + ": " + c.name;
}

void validateLight(const Scene& scene, const RectLight& light, std::string_view what) {
    const std::string name = what.empty() ? std::string("light") : std::string(what);
    checkLight(light, [&](const std::string& k, const std::string& w) {
        throw LightRefusedError(name + (k == "light" ? "" : k.substr(5)) + ": " + w);
    });
    validateLightClear(scene, light, name);
}

void validateCamera(const Camera& camera, std::string_view what) {
    const std::string name = what.empty() ? std::string("camera") : std::string(what);
    checkCamera(camera, [&](const std::string& k, const std::string& w) {
        throw InputError(name + k.substr(6) + ": " + w); // "camera.eye" -> name + ".eye"
    });
}

Camera defaultCamera(const Aabb& bounds) {
    Camera cam;
    if (bounds.empty()) return cam;
    const glm::vec3 c = bounds.center();
    const float diag = std::max(glm::length(bounds.extent()), 1e-3f);
    // Diagonally above: far enough that the bounding sphere (radius diag/2) fits the default
    // 50° field of view (distance r / sin(25°) ≈ 1.18 diag), a little more for margin.
    const glm::vec3 dir = glm::normalize(glm::vec3(1.0f, 0.8f, 1.0f));
    cam.target = c;
    cam.eye = c + dir * (1.3f * diag);
    cam.up = glm::vec3(0.0f, 1.0f, 0.0f);
    cam.fovYDeg = 50.0f;
    return cam;
}

RectLight defaultLight(const Aabb& bounds) {
    RectLight light;
    if (bounds.empty()) return light;
    const glm::vec3 c = bounds.center();
    const glm::vec3 e = bounds.extent();
    const float diag = std::max(glm::length(e), 1e-3f);
    float half = 0.05f * diag;
    // Keep the light inside the horizontal extent (a light hanging past a level's walls would
    // light it from outside); only possible when the extent is not degenerate.
    const float horizontal = std::min(e.x, e.z);
    if (horizontal > 0.0f) half = std::min(half, 0.5f * horizontal);
    const float lift = std::max(0.3f * e.y, 0.05f * diag);
    light.center = glm::vec3(c.x, bounds.max.y + lift, c.z);
    // u along +x, v along +z: normal = normalize(u x v) = -y, facing down onto the model.
    light.u = glm::vec3(half, 0.0f, 0.0f);
    light.v = glm::vec3(0.0f, 0.0f, half);
    return light;
}

const char* toString(ShadowMethod m) {
    switch (m) {
    case ShadowMethod::Auto:
        return "auto";
    case ShadowMethod::Wedges:
        return "wedges";
    case ShadowMethod::Occlusion:
        return "occlusion";
    case ShadowMethod::None:
        return "none";
    }
    return "auto";
}

} // namespace geometry
