#include <geometry/core/Error.h>
#include <geometry/reference/Framing.h>
#include <geometry/scene/GltfLoader.h>
#include <geometry/core/Limits.h>
#include <geometry/scene/Primitives.h>
#include <geometry/reference/RayTracer.h>
#include <geometry/scene/Scene.h>

#include "TestFiles.h"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <string>

namespace {

namespace fs = std::filesystem;

const fs::path kShared = PENUMBRA_SHARED_DIR;

// One triangle (0,0,0) (1,0,0) (0,1,0) as a .gltf with an embedded base64 buffer: 36 bytes of
// float positions followed by 3 uint16 indices (+2 padding).
std::string triangleGltf() {
    std::string bytes;
    for (float f : {0.f, 0.f, 0.f, 1.f, 0.f, 0.f, 0.f, 1.f, 0.f}) {
        bytes.append(reinterpret_cast<const char*>(&f), 4);
    }
    for (std::uint16_t i : {0, 1, 2, 0})
        bytes.append(reinterpret_cast<const char*>(&i), 2);
    static const char* table = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string b64;
    for (std::size_t i = 0; i < bytes.size(); i += 3) { // 44 bytes: last group has 2
        unsigned v = (unsigned char)bytes[i] << 16;
        if (i + 1 < bytes.size()) v |= (unsigned char)bytes[i + 1] << 8;
        if (i + 2 < bytes.size()) v |= (unsigned char)bytes[i + 2];
        b64 += table[v >> 18];
        b64 += table[(v >> 12) & 63];
        b64 += i + 1 < bytes.size() ? table[(v >> 6) & 63] : '=';
        b64 += i + 2 < bytes.size() ? table[v & 63] : '=';
    }
    return R"({"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[0]}],"nodes":[{"mesh":0}],
      "meshes":[{"primitives":[{"attributes":{"POSITION":0},"indices":1}]}],
      "buffers":[{"byteLength":44,"uri":"data:application/octet-stream;base64,)" +
           b64 + R"("}],
      "bufferViews":[{"buffer":0,"byteOffset":0,"byteLength":36},
                     {"buffer":0,"byteOffset":36,"byteLength":6}],
      "accessors":[{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3"},
                   {"bufferView":1,"componentType":5123,"count":3,"type":"SCALAR"}]})";
}

const char* kCamera = R"("camera": {"eye": [0, 4, 8], "target": [0, 0, 0]})";
const char* kLight = R"("light": {"center": [0, 6, 0], "u": [0.5, 0, 0], "v": [0, 0, 0.5]})";
const char* kBox = R"({"type": "box", "center": [0, 1, 0], "size": [1, 0.2, 1]})";

class SceneTest : public testutil::TempDirTest {
protected:
    SceneTest() : TempDirTest("scene") {}
    void SetUp() override {
        TempDirTest::SetUp();
        fs::create_directories(mDir / "models");
        write("models/tri.gltf", triangleGltf());
    }
    fs::path write(const std::string& name, const std::string& text) const {
        fs::create_directories((mDir / name).parent_path());
        std::ofstream(mDir / name, std::ios::binary) << text;
        return mDir / name;
    }
    // Scene JSON from the three top-level parts.
    static std::string scene(const std::string& objects, const std::string& camera = kCamera,
                             const std::string& light = kLight) {
        return "{" + camera + ",\n" + light + ",\n\"objects\": [" + objects + "]}";
    }
    // Writes `json` to scene.json, loads it and expects an InputError whose message contains the
    // file name and every one of `needles`.
    void expectError(const std::string& json, std::initializer_list<std::string> needles) const {
        const fs::path path = write("scene.json", json);
        try {
            geometry::loadScene(path);
            ADD_FAILURE() << "expected InputError for:\n" << json;
        } catch (const geometry::InputError& e) {
            const std::string msg = e.what();
            EXPECT_NE(msg.find("scene.json"), std::string::npos) << msg;
            for (const auto& n : needles)
                EXPECT_NE(msg.find(n), std::string::npos) << msg;
        }
    }
};

TEST_F(SceneTest, ValidSceneWithEveryObjectType) {
    const std::string json = R"({
      "camera": {"eye": [0, 4, 8], "target": [0, 0, 0], "up": [0, 1, 0], "fov_y_deg": 40},
      "light":  {"center": [0, 6, 0], "u": [0.5, 0, 0], "v": [0, 0, 0.5]},
      "objects": [
        {"type": "gltf", "file": "models/tri.gltf", "translate": [10, 0, 0],
         "rotate_deg": [0, 0, 90], "scale": 2, "method": "wedges"},
        {"type": "box", "center": [0, 1, 0], "size": [1, 0.2, 1], "name": "table",
         "static": false},
        {"type": "quad", "center": [0, 2, 0], "u": [0.5, 0, 0], "v": [0, 0, 0.5],
         "method": "none"},
        {"type": "sphere", "center": [2, 1, 0], "radius": 0.5, "segments": 16,
         "method": "occlusion"},
        {"type": "gltf", "file": "models/tri.gltf", "scale": [1, 2, 3]}
      ]})";
    const fs::path path = write("scene.json", json);
    const geometry::Scene s = geometry::loadScene(path);
    EXPECT_EQ(s.source, path);
    EXPECT_EQ(s.camera.eye, glm::vec3(0, 4, 8));
    EXPECT_FLOAT_EQ(s.camera.fovYDeg, 40.0f);
    EXPECT_EQ(s.light.center, glm::vec3(0, 6, 0));
    EXPECT_EQ(s.light.v, glm::vec3(0, 0, 0.5f));
    ASSERT_EQ(s.objects.size(), 5u);

    EXPECT_EQ(s.objects[0].method, geometry::ShadowMethod::Wedges);
    EXPECT_EQ(s.objects[0].name, "tri.gltf");
    // Scaled by 2, rotated 90° about z, translated: (1,0,0) -> (0,2,0) -> (10,2,0).
    const auto& tri = s.objects[0].mesh.positions;
    ASSERT_EQ(tri.size(), 3u);
    EXPECT_NEAR(tri[1].x, 10.0f, 1e-5f);
    EXPECT_NEAR(tri[1].y, 2.0f, 1e-5f);
    EXPECT_NEAR(tri[2].x, 8.0f, 1e-5f); // (0,1,0) -> (0,2,0) -> (-2,0,0) -> (8,0,0)

    EXPECT_EQ(s.objects[1].name, "table");
    EXPECT_EQ(s.objects[1].method, geometry::ShadowMethod::Auto);
    EXPECT_FALSE(s.objects[1].isStatic);
    EXPECT_TRUE(s.objects[0].isStatic); // the default
    EXPECT_TRUE(s.objects[2].isStatic);
    EXPECT_EQ(s.objects[1].mesh.triangles.size(), 12u);
    EXPECT_EQ(s.objects[2].method, geometry::ShadowMethod::None);
    EXPECT_EQ(s.objects[2].name, "objects[2] (quad)");
    EXPECT_EQ(s.objects[2].mesh.triangles.size(), 2u);
    EXPECT_EQ(s.objects[3].method, geometry::ShadowMethod::Occlusion);
    EXPECT_EQ(s.objects[3].mesh.triangles.size(), 2u * 16u * 7u);
    EXPECT_NEAR(s.objects[4].mesh.bounds().max.y, 2.0f, 1e-6f); // per-axis scale

    EXPECT_EQ(s.triangleCount(), 1u + 12u + 2u + 224u + 1u);
    const geometry::Aabb b = s.bounds();
    EXPECT_NEAR(b.max.x, 10.0f, 1e-5f);
    EXPECT_NEAR(b.min.x, -0.5f, 1e-5f);
    EXPECT_NO_THROW(geometry::validateScene(s));
}

TEST_F(SceneTest, OptionalCameraKeysDefault) {
    const geometry::Scene s = geometry::loadScene(write("scene.json", scene(kBox)));
    EXPECT_EQ(s.camera.up, glm::vec3(0, 1, 0));
    EXPECT_FLOAT_EQ(s.camera.fovYDeg, 50.0f);
    ASSERT_EQ(s.objects.size(), 1u);
    EXPECT_EQ(s.objects[0].method, geometry::ShadowMethod::Auto);
}

TEST_F(SceneTest, RelativeFileResolvesAgainstSceneDirectory) {
    // Scene in a sub-directory referring to a sibling directory with "..".
    const std::string json = scene(R"({"type": "gltf", "file": "../../models/tri.gltf"})");
    const fs::path nestedOk = write("scenes/nested/scene.json", json);
    EXPECT_EQ(geometry::loadScene(nestedOk).triangleCount(), 1u);
    // parseScene with an explicit base directory.
    const geometry::Scene p = geometry::parseScene(
        scene(R"({"type": "gltf", "file": "models/tri.gltf"})"), mDir, "inline");
    EXPECT_EQ(p.triangleCount(), 1u);
    // And an absolute path works from anywhere.
    const std::string abs = (mDir / "models" / "tri.gltf").string();
    EXPECT_EQ(
        geometry::parseScene(scene(R"({"type": "gltf", "file": ")" + abs + "\"}"), "/", "inline")
            .triangleCount(),
        1u);
}

TEST_F(SceneTest, JsonSyntaxErrorNamesFileAndPosition) {
    expectError("{\"camera\": {\"eye\": [0, 4, 8],,}}", {"syntax error", "line 1", "byte"});
    expectError("", {"syntax error"});
}

TEST_F(SceneTest, UnknownKeys) {
    expectError(R"({"camera": {"eye": [0,4,8], "target": [0,0,0]}, )" + std::string(kLight) +
                    R"(, "objects": [)" + kBox + R"(], "shadows": true})",
                {"shadows", "unknown key"});
    expectError(scene(R"({"type": "box", "center": [0,1,0], "size": [1,1,1], "colour": [1,0,0]})"),
                {"objects[0].colour", "unknown key"});
    expectError(scene(kBox, R"("camera": {"eye": [0,4,8], "target": [0,0,0], "fov": 60})"),
                {"camera.fov"});
    expectError(scene(kBox, kCamera, R"("light": {"center": [0,6,0], "u": [1,0,0],
                                                  "v": [0,0,1], "intensity": 2})"),
                {"light.intensity"});
    // A key valid for one type is unknown for another.
    expectError(scene(R"({"type": "box", "center": [0,1,0], "size": [1,1,1], "radius": 1})"),
                {"objects[0].radius"});
}

TEST_F(SceneTest, WrongTypesAndLengths) {
    expectError(scene(kBox, R"("camera": {"eye": "up there", "target": [0,0,0]})"),
                {"camera.eye", "expected 3 numbers"});
    expectError(
        scene(std::string(kBox) + R"(, {"type": "box", "center": [0,1,0], "size": [1, 2]})"),
        {"objects[1].size: expected 3 numbers"});
    expectError(scene(R"({"type": "box", "center": [0,1,0], "size": [1, true, 1]})"),
                {"objects[0].size"});
    expectError(scene(R"({"type": "sphere", "center": [0,1,0], "radius": "big"})"),
                {"objects[0].radius", "expected a number"});
    expectError(scene(R"({"type": 3, "center": [0,1,0]})"), {"objects[0].type", "string"});
    expectError(scene(R"({"type": "cone"})"), {"objects[0].type", "cone"});
    expectError(scene(R"(42)"), {"objects[0]", "expected an object"});
    expectError(R"({"camera": [0,4,8], )" + std::string(kLight) + R"(, "objects": []})",
                {"camera", "expected an object"});
    expectError(std::string("{") + kCamera + "," + kLight + R"(, "objects": {}})",
                {"objects", "expected an array"});
    expectError("[1, 2, 3]", {"expected an object"});
    expectError(scene(R"({"type": "sphere", "center": [0,1,0], "radius": 1, "segments": 2.5})"),
                {"objects[0].segments"});
    expectError(scene(R"({"type": "gltf", "file": "models/tri.gltf", "scale": "2"})"),
                {"objects[0].scale"});
}

TEST_F(SceneTest, MissingRequiredKeys) {
    expectError(std::string("{") + kLight + R"(, "objects": [)" + kBox + "]}",
                {"camera", "missing"});
    expectError(std::string("{") + kCamera + R"(, "objects": [)" + kBox + "]}",
                {"light", "missing"});
    expectError(std::string("{") + kCamera + "," + kLight + "}", {"objects", "missing"});
    expectError(scene(kBox, kCamera, R"("light": {"center": [0,6,0], "v": [0,0,1]})"),
                {"light.u", "missing"});
    expectError(scene(kBox, R"("camera": {"eye": [0,4,8]})"), {"camera.target", "missing"});
    expectError(scene(R"({"type": "box", "center": [0,1,0]})"), {"objects[0].size", "missing"});
    expectError(scene(R"({"center": [0,1,0]})"), {"objects[0].type", "missing"});
    expectError(scene(R"({"type": "gltf"})"), {"objects[0].file", "missing"});
}

TEST_F(SceneTest, MissingAndBrokenGltfFiles) {
    expectError(scene(R"({"type": "gltf", "file": "models/nothere.glb"})"),
                {"objects[0].file", "nothere.glb", "not found"});
    write("models/broken.gltf", "{ definitely not gltf");
    expectError(scene(R"({"type": "gltf", "file": "models/broken.gltf"})"),
                {"objects[0].file", "broken.gltf", "parse error"});
    // Missing scene file itself.
    try {
        geometry::loadScene(mDir / "absent.json");
        ADD_FAILURE() << "expected InputError";
    } catch (const geometry::InputError& e) {
        EXPECT_NE(std::string(e.what()).find("absent.json"), std::string::npos) << e.what();
    }
}

TEST_F(SceneTest, ZeroAreaLight) {
    expectError(scene(kBox, kCamera, R"("light": {"center": [0,6,0], "u": [1,0,0], "v": [2,0,0]})"),
                {"light", "zero area"});
    expectError(scene(kBox, kCamera, R"("light": {"center": [0,6,0], "u": [0,0,0], "v": [0,0,1]})"),
                {"light.u"});
    // Nearly parallel at a large scale is still zero area relative to |u||v|.
    expectError(scene(kBox, kCamera,
                      R"("light": {"center": [0,6,0], "u": [1000,0,0], "v": [1000,0,1e-7]})"),
                {"light", "zero area"});
}

TEST_F(SceneTest, NonFiniteValues) {
    expectError(scene(kBox, R"("camera": {"eye": [0,4,8], "target": [0,0,0], "fov_y_deg": "NaN"})"),
                {"camera.fov_y_deg", "expected a number"});
    // nlohmann parses 1e999 as infinity.
    expectError(scene(R"({"type": "box", "center": [0,1e999,0], "size": [1,1,1]})"),
                {"objects[0].center[1]", "finite"});
    // Finite as a double but not as a float.
    expectError(scene(R"({"type": "sphere", "center": [0,1,0], "radius": 1e300})"),
                {"objects[0].radius", "finite"});
}

// Coordinates beyond geometry::kMaxCoordinate (1e7) cannot be rendered in float; each is refused
// naming its key or accessor, never as a light contact with some other object.
TEST_F(SceneTest, CoordinatesBeyondTheRenderableRange) {
    const std::string floor =
        R"({"type": "quad", "center": [0, 0, 0], "u": [3, 0, 0], "v": [0, 0, -3]})";
    const std::string hugeGltf =
        floor + R"(, {"type": "gltf", "file": "models/tri.gltf", "scale": [1, 1e19, 1]})";
    expectError(scene(hugeGltf), {"objects[1].file", "POSITION (accessor 0) vertex 2 has y = 1e+19",
                                  "after the node transforms", "outside [-1e+07, 1e+07]"});
    try {
        geometry::loadScene(write("scene.json", scene(hugeGltf)));
    } catch (const geometry::InputError& e) {
        // Once blamed on the floor: "light intersects object 'objects[0] (quad)'".
        EXPECT_EQ(std::string(e.what()).find("intersects"), std::string::npos) << e.what();
    }
    expectError(scene(floor + R"(, {"type": "box", "center": [0, 1e19, 0], "size": [1, 1, 1]})"),
                {"objects[1]: vertex 0 at", "is outside [-1e+07, 1e+07]"});
    expectError(scene(floor, R"("camera": {"eye": [0, 4, 2e7], "target": [0, 0, 0]})"),
                {"camera.eye", "outside"});
    expectError(
        scene(floor, kCamera,
              R"("light": {"center": [0, 6, 0], "u": [1e38, 0, 0], "v": [0, 0, 0.5]})"),
        {"light.u", "[1e+38, 0, 0] is outside [-1e+07, 1e+07]"});
}

// Procedural objects are bounded before they are built (geometry/core/Limits.h): "segments": 4096
// once took a minute and 8 GB of memory. The refusal must come at once.
TEST_F(SceneTest, TriangleBudgets) {
    const auto t0 = std::chrono::steady_clock::now();
    expectError(scene(R"({"type": "sphere", "center": [0,1,0], "radius": 0.5, "segments": 4096})"),
                {"objects[0].segments", "a sphere of 4096 segments would have 16,769,024 triangles",
                 "more than the 2,097,152 one object may have", "segments at most 1449"});
    expectError(scene(R"({"type": "torus", "center": [0,1,0], "major_radius": 0.5,
                          "minor_radius": 0.1, "major_segments": 2048, "minor_segments": 1024})"),
                {"objects[0].major_segments", "4,194,304 triangles",
                 "major_segments x minor_segments at most 1,048,576"});
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    EXPECT_LT(seconds, 5.0) << "refused only after building the mesh?";
    // The largest sphere that fits is accepted: the hint is right.
    EXPECT_EQ(geometry::sphereTriangleCount(1449), 2'095'254u);
    EXPECT_GT(geometry::sphereTriangleCount(1450), geometry::kMaxObjectTriangles);

    // Each object within its budget, the scene over its own: two 1024 x 1024 tori fill it.
    const std::string torus = R"({"type": "torus", "center": [0,1,0], "major_radius": 0.5,
        "minor_radius": 0.1, "major_segments": 1024, "minor_segments": 1024})";
    expectError(scene(torus + ", " + torus + ", " + kBox),
                {"objects[2]", "would bring the scene to 4,194,316 triangles",
                 "more than the 4,194,304 a scene may have"});
}

TEST_F(SceneTest, EmptyObjects) {
    expectError(scene(""), {"objects", "at least one"});
}

TEST_F(SceneTest, BadMethodName) {
    expectError(scene(R"({"type": "box", "center": [0,1,0], "size": [1,1,1], "method": "magic"})"),
                {"objects[0].method", "magic"});
    expectError(scene(R"({"type": "box", "center": [0,1,0], "size": [1,1,1], "method": 1})"),
                {"objects[0].method"});
}

TEST_F(SceneTest, BadStaticFlag) {
    expectError(scene(R"({"type": "box", "center": [0,1,0], "size": [1,1,1], "static": "no"})"),
                {"objects[0].static", "expected true or false", "\"no\""});
    expectError(scene(R"({"type": "sphere", "center": [0,1,0], "radius": 1, "static": 0})"),
                {"objects[0].static"});
}

TEST_F(SceneTest, InvalidCameraAndSizes) {
    expectError(scene(kBox, R"("camera": {"eye": [0,4,8], "target": [0,0,0], "fov_y_deg": 180})"),
                {"camera.fov_y_deg"});
    expectError(scene(kBox, R"("camera": {"eye": [0,4,8], "target": [0,0,0], "fov_y_deg": 0})"),
                {"camera.fov_y_deg"});
    expectError(scene(kBox, R"("camera": {"eye": [1,2,3], "target": [1,2,3]})"), {"camera.target"});
    expectError(scene(kBox, R"("camera": {"eye": [0,4,0], "target": [0,0,0]})"),
                {"camera.up", "parallel"});
    expectError(scene(R"({"type": "box", "center": [0,1,0], "size": [1,0,1]})"),
                {"objects[0].size"});
    expectError(scene(R"({"type": "sphere", "center": [0,1,0], "radius": -1})"),
                {"objects[0].radius"});
    expectError(scene(R"({"type": "gltf", "file": "models/tri.gltf", "scale": 0})"),
                {"objects[0].scale"});
    expectError(scene(R"({"type": "gltf", "file": "models/tri.gltf", "scale": [1,-1,1]})"),
                {"objects[0].scale"});
    expectError(scene(R"({"type": "quad", "center": [0,1,0], "u": [1,0,0], "v": [1,0,0]})"),
                {"objects[0]", "zero area"});
    expectError(scene(R"({"type": "sphere", "center": [0,1,0], "radius": 1, "segments": 2})"),
                {"objects[0].segments"});
}

TEST_F(SceneTest, DuplicateKey) {
    expectError(scene(R"({"type": "box", "center": [0,1,0], "size": [1,1,1], "size": [2,2,2]})"),
                {"duplicate", "size"});
}

// Positive for outward counter-clockwise winding of a closed mesh.
double signedVolume(const geometry::MeshData& m) {
    double v = 0.0;
    for (const glm::uvec3& t : m.triangles) {
        const glm::dvec3 a(m.positions[t.x]), b(m.positions[t.y]), c(m.positions[t.z]);
        v += glm::dot(a, glm::cross(b, c)) / 6.0;
    }
    return v;
}

TEST_F(SceneTest, TorusDefaultsAndRotation) {
    const std::string json = scene(R"(
        {"type": "torus", "center": [1, 2, 3], "major_radius": 0.6, "minor_radius": 0.2},
        {"type": "torus", "center": [0, 1, 0], "major_radius": 0.6, "minor_radius": 0.2,
         "major_segments": 12, "minor_segments": 5, "rotate_deg": [90, 0, 0], "name": "ring"})");
    const geometry::Scene s = geometry::loadScene(write("scene.json", json));
    ASSERT_EQ(s.objects.size(), 2u);

    const geometry::MeshData& plain = s.objects[0].mesh;
    EXPECT_EQ(s.objects[0].name, "objects[0] (torus)");
    EXPECT_EQ(plain.triangles.size(), 2u * 48u * 24u); // default segments 48 x 24
    EXPECT_EQ(plain.positions.size(), 48u * 24u);
    // Axis +y: the tube spans y = 2 ± 0.2, the ring x = 1 ± 0.8.
    const geometry::Aabb pb = plain.bounds();
    EXPECT_NEAR(pb.max.y, 2.2f, 1e-5f);
    EXPECT_NEAR(pb.min.y, 1.8f, 1e-5f);
    EXPECT_NEAR(pb.max.x, 1.8f, 1e-5f);
    EXPECT_NEAR(pb.min.x, 0.2f, 1e-5f);
    // Outward winding; a polyhedron inscribed in the torus is a little smaller than 2 pi^2 R r^2.
    const double exact = 2.0 * std::numbers::pi * std::numbers::pi * 0.6 * 0.2 * 0.2;
    EXPECT_LT(signedVolume(plain), exact);
    EXPECT_GT(signedVolume(plain), 0.98 * exact);

    // Rotated 90° about x about its centre: the axis is now z, so the ring stands up in xy.
    const geometry::MeshData& ring = s.objects[1].mesh;
    EXPECT_EQ(s.objects[1].name, "ring");
    EXPECT_EQ(ring.triangles.size(), 2u * 12u * 5u);
    const geometry::Aabb rb = ring.bounds();
    EXPECT_NEAR(rb.max.y, 1.8f, 1e-5f);
    EXPECT_NEAR(rb.min.y, 0.2f, 1e-5f);
    EXPECT_LT(rb.max.z, 0.2f + 1e-5f);
    EXPECT_GT(rb.min.z, -0.2f - 1e-5f);
    EXPECT_GT(signedVolume(ring), 0.0); // a rotation keeps the winding outward
}

TEST_F(SceneTest, RotatedBox) {
    const std::string json = scene(R"(
        {"type": "box", "center": [0, 1, 0], "size": [2, 0.2, 0.2], "rotate_deg": [0, 45, 0]},
        {"type": "box", "center": [0, 3, 0], "size": [2, 0.2, 0.2], "rotate_deg": [0, 0, 0]})");
    const geometry::Scene s = geometry::loadScene(write("scene.json", json));
    ASSERT_EQ(s.objects.size(), 2u);
    const geometry::MeshData& bar = s.objects[0].mesh;
    ASSERT_EQ(bar.triangles.size(), 12u);
    // A 2 x 0.2 bar turned 45° about y: its corners reach (1 + 0.1) / sqrt(2) in x and z.
    const geometry::Aabb b = bar.bounds();
    const float reach = 1.1f / std::sqrt(2.0f);
    EXPECT_NEAR(b.max.x, reach, 1e-5f);
    EXPECT_NEAR(b.min.z, -reach, 1e-5f);
    EXPECT_NEAR(b.max.y, 1.1f, 1e-5f); // height unchanged
    EXPECT_NEAR(signedVolume(bar), 2.0 * 0.2 * 0.2, 1e-5);
    // A zero rotation is the axis-aligned box exactly.
    EXPECT_EQ(s.objects[1].mesh.positions, geometry::makeBox({0, 3, 0}, {2, 0.2f, 0.2f}).positions);
}

TEST_F(SceneTest, BadTorusAndRotation) {
    const std::string t = R"({"type": "torus", "center": [0,1,0], )";
    expectError(scene(t + R"("major_radius": 0.5, "minor_radius": 0.1, "tube": 1})"),
                {"objects[0].tube", "unknown key"});
    expectError(scene(t + R"("minor_radius": 0.1})"), {"objects[0].major_radius", "missing"});
    expectError(scene(t + R"("major_radius": 0.5})"), {"objects[0].minor_radius", "missing"});
    expectError(scene(t + R"("major_radius": 0, "minor_radius": 0.1})"),
                {"objects[0].major_radius", "> 0"});
    expectError(scene(t + R"("major_radius": 0.5, "minor_radius": -0.1})"),
                {"objects[0].minor_radius", "> 0"});
    expectError(scene(t + R"("major_radius": 0.5, "minor_radius": 0.5})"),
                {"objects[0].minor_radius", "< major_radius"});
    expectError(scene(t + R"("major_radius": 0.5, "minor_radius": 0.7})"),
                {"objects[0].minor_radius", "< major_radius"});
    expectError(scene(t + R"("major_radius": "big", "minor_radius": 0.1})"),
                {"objects[0].major_radius", "expected a number"});
    expectError(scene(t + R"("major_radius": 0.5, "minor_radius": 0.1, "major_segments": 2})"),
                {"objects[0].major_segments", "[3, 4096]"});
    expectError(scene(t + R"("major_radius": 0.5, "minor_radius": 0.1, "minor_segments": 4097})"),
                {"objects[0].minor_segments", "[3, 4096]"});
    expectError(scene(t + R"("major_radius": 0.5, "minor_radius": 0.1, "minor_segments": 8.5})"),
                {"objects[0].minor_segments", "integer"});
    expectError(scene(t + R"("major_radius": 0.5, "minor_radius": 0.1, "rotate_deg": [0, 90]})"),
                {"objects[0].rotate_deg", "expected 3 numbers"});
    expectError(
        scene(t + R"("major_radius": 0.5, "minor_radius": 0.1, "rotate_deg": [0,1e999,0]})"),
        {"objects[0].rotate_deg[1]", "finite"});
    // rotate_deg is a box key now, but still not a quad or sphere key.
    expectError(scene(R"({"type": "box", "center": [0,1,0], "size": [1,1,1], "rotate_deg": 45})"),
                {"objects[0].rotate_deg", "expected 3 numbers"});
    expectError(scene(R"({"type": "quad", "center": [0,1,0], "u": [1,0,0], "v": [0,0,1],
                          "rotate_deg": [0,45,0]})"),
                {"objects[0].rotate_deg", "unknown key"});
    expectError(scene(R"({"type": "sphere", "center": [0,1,0], "radius": 1,
                          "rotate_deg": [0,45,0]})"),
                {"objects[0].rotate_deg", "unknown key"});
    // A torus key is unknown on a sphere.
    expectError(scene(R"({"type": "sphere", "center": [0,1,0], "radius": 1,
                          "major_segments": 8})"),
                {"objects[0].major_segments", "unknown key"});
    expectError(scene(R"({"type": "donut"})"), {"objects[0].type", "torus"});
}

// Every scene authored in data/ loads, keeps its light clear of all geometry and has a floor
// receiver: renders and benchmarks read them by name.
// Every scene under data/, subfolders included (data/stability/: the sweep and camera checks are
// in StabilitySceneTest.cpp).
TEST(DataScenes, EveryDataSceneLoads) {
    const fs::path dir = fs::path(PENUMBRA_SOURCE_DIR) / "data";
    int topLevel = 0;
    int stability = 0;
    for (const auto& entry : fs::recursive_directory_iterator(dir)) {
        if (entry.path().extension() != ".json") continue;
        SCOPED_TRACE(entry.path().string());
        geometry::Scene s;
        ASSERT_NO_THROW(s = geometry::loadScene(entry.path()));
        EXPECT_LT(s.light.normal().y, -0.99f) << "the light faces down onto the scene";
        if (entry.path().parent_path() == dir) {
            // Not for the stability suite: light-grazing hangs its light beside a taller wall.
            EXPECT_GT(s.light.center.y, s.bounds().max.y) << "the light is above every object";
            ++topLevel;
        } else if (entry.path().parent_path() == dir / "stability") {
            ++stability;
        }
    }
    EXPECT_GE(topLevel, 10);
    EXPECT_GE(stability, 10);
}

TEST_F(SceneTest, UnsupportedExtension) {
    const fs::path p = write("scene.yaml", "camera: {}");
    EXPECT_THROW(geometry::loadScene(p), geometry::InputError);
}

TEST_F(SceneTest, GltfLevelGivenDirectlyIsFramedFromInside) {
    const geometry::Scene s = geometry::loadScene(kShared / "levels" / "oa_dm1.glb");
    ASSERT_EQ(s.objects.size(), 1u);
    EXPECT_EQ(s.objects[0].name, "oa_dm1.glb");
    EXPECT_EQ(s.triangleCount(), 7502u);
    EXPECT_NO_THROW(geometry::validateScene(s));
    const geometry::Aabb b = s.bounds();
    auto inside = [&](const glm::vec3& p) {
        return glm::all(glm::greaterThan(p, b.min)) && glm::all(glm::lessThan(p, b.max));
    };
    // The level's spawn camera is the view; the light is the framing's, which would also give the
    // camera for a level without cameras.
    geometry::Scene framed = s;
    ASSERT_TRUE(geometry::frameInterior(framed));
    EXPECT_EQ(s.light.center, framed.light.center);
    EXPECT_EQ(s.light.u, framed.light.u);
    EXPECT_EQ(s.cameraSource.rfind("gltf camera 0: ", 0), 0u) << s.cameraSource;
    // A roofed level seen from outside shows only its roof: the camera must be inside, with
    // geometry in front of it, and the light under a ceiling (not above the level).
    EXPECT_TRUE(inside(framed.camera.eye));
    EXPECT_FLOAT_EQ(framed.camera.fovYDeg, 70.0f);
    const geometry::RayTracer tracer(s);
    float t = 0.0f;
    glm::vec3 n;
    const glm::vec3 view = glm::normalize(framed.camera.target - framed.camera.eye);
    ASSERT_TRUE(tracer.intersect(framed.camera.eye, view, t, n));
    EXPECT_GT(t, 0.5f); // not staring into a wall

    const geometry::RectLight& L = s.light;
    EXPECT_TRUE(inside(L.center));
    EXPECT_LT(L.normal().y, -0.99f);
    EXPECT_NEAR(glm::dot(L.u, L.v), 0.0f, 1e-6f);
    ASSERT_TRUE(tracer.intersect(L.center, {0, 1, 0}, t, n)) << "the light hangs under a ceiling";
    EXPECT_GT(t, 0.0f);
    const float diag = glm::length(b.extent());
    EXPECT_GT(glm::length(L.u), 0.002f * diag); // shrunk until clear of geometry, not to a point
    EXPECT_LT(glm::length(L.u), 0.031f * diag);
}

// Every shared level opens at its first spawn camera (levels/README.md: spawn counts), and that
// view passes validateScene with the framed light: eye in open space above a floor, looking at
// geometry some way off.
TEST_F(SceneTest, LevelsOpenAtTheirFirstSpawnCamera) {
    const std::pair<const char*, std::size_t> levels[] = {
        {"oa_dm1.glb", 8}, {"oa_dm4.glb", 7}, {"oa_dm5.glb", 7}, {"kaos2.glb", 12}};
    for (const auto& [file, spawns] : levels) {
        SCOPED_TRACE(file);
        const geometry::Scene s = geometry::loadScene(kShared / "levels" / file);
        ASSERT_EQ(s.cameras.size(), spawns);
        EXPECT_EQ(s.skippedCameras, 0);
        EXPECT_EQ(s.cameras[0].name.rfind("spawn 1 (", 0), 0u) << s.cameras[0].name;
        EXPECT_EQ(s.cameraSource, "gltf camera 0: " + s.cameras[0].name);
        EXPECT_EQ(s.camera.eye, s.cameras[0].camera.eye);
        EXPECT_EQ(s.camera.target, s.cameras[0].camera.target);
        EXPECT_EQ(s.camera.up, s.cameras[0].camera.up);
        EXPECT_EQ(s.camera.fovYDeg, s.cameras[0].camera.fovYDeg);
        EXPECT_NO_THROW(geometry::validateScene(s));
        const geometry::Aabb b = s.bounds();
        EXPECT_TRUE(glm::all(glm::greaterThan(s.camera.eye, b.min)) &&
                    glm::all(glm::lessThan(s.camera.eye, b.max)));
        const geometry::RayTracer tracer(s);
        float t = 0.0f;
        glm::vec3 n;
        // Floor below the eye (a player's eye height, seen from its front side).
        ASSERT_TRUE(tracer.intersect(s.camera.eye, {0, -1, 0}, t, n));
        EXPECT_GT(t, 0.3f);
        EXPECT_LT(t, 3.0f);
        EXPECT_GT(n.y, 0.5f);
        const glm::vec3 view = glm::normalize(s.camera.target - s.camera.eye);
        if (tracer.intersect(s.camera.eye, view, t, n)) {
            EXPECT_GT(t, 0.5f) << "staring into a wall";
            EXPECT_LT(glm::dot(n, view), 0.0f) << "looking at a back face (inside a wall?)";
        }
    }
}

TEST_F(SceneTest, OaDm4SpawnCameraIsPickedAndSelectable) {
    const fs::path level = kShared / "levels" / "oa_dm4.glb";
    geometry::Scene s = geometry::loadScene(level);
    const auto gltf = geometry::loadGltfCameras(level);
    ASSERT_EQ(gltf.size(), 7u);
    ASSERT_EQ(s.cameras.size(), 7u);
    for (std::size_t i = 0; i < gltf.size(); ++i) {
        EXPECT_EQ(s.cameras[i].name, gltf[i].name);
        EXPECT_EQ(s.cameras[i].camera.eye, gltf[i].camera.eye);
    }
    EXPECT_EQ(s.cameraSource, "gltf camera 0: spawn 1 (info_player_start)");
    EXPECT_EQ(s.camera.eye, gltf[0].camera.eye);

    geometry::selectCamera(s, 3);
    EXPECT_EQ(s.cameraSource, "gltf camera 3: " + gltf[3].name);
    EXPECT_EQ(s.camera.eye, gltf[3].camera.eye);
    EXPECT_EQ(s.camera.target, gltf[3].camera.target);
    EXPECT_NE(gltf[3].camera.eye, gltf[0].camera.eye);
    for (int bad : {7, -1, 99}) {
        try {
            geometry::selectCamera(s, bad);
            ADD_FAILURE() << bad;
        } catch (const geometry::InputError& e) {
            const std::string msg = e.what();
            EXPECT_NE(msg.find("oa_dm4.glb"), std::string::npos) << msg;
            EXPECT_NE(msg.find("camera " + std::to_string(bad)), std::string::npos) << msg;
            EXPECT_NE(msg.find("7 glTF cameras"), std::string::npos) << msg;
        }
    }
    EXPECT_EQ(s.cameraSource, "gltf camera 3: " + gltf[3].name); // unchanged by the failures

    // Back to the automatic framing (the view of a level without cameras); the light stays.
    const geometry::RectLight light = s.light;
    geometry::selectFramedCamera(s);
    EXPECT_EQ(s.cameraSource, "framed");
    EXPECT_FLOAT_EQ(s.camera.fovYDeg, 70.0f); // frameInterior's
    EXPECT_NE(s.camera.eye, gltf[3].camera.eye);
    EXPECT_EQ(s.light.center, light.center);
    EXPECT_EQ(s.light.u, light.u);
}

TEST_F(SceneTest, CameraSourceOfFilesWithoutGltfCameras) {
    const geometry::Scene json = geometry::loadScene(write("scene.json", scene(kBox)));
    EXPECT_EQ(json.cameraSource, "scene");
    EXPECT_TRUE(json.cameras.empty());
    geometry::Scene copy = json;
    EXPECT_THROW(geometry::selectCamera(copy, 0), geometry::InputError);

    const geometry::Scene tri = geometry::loadScene(mDir / "models" / "tri.gltf");
    EXPECT_EQ(tri.cameraSource, "framed");
    EXPECT_TRUE(tri.cameras.empty());

    // Only an orthographic camera: skipped (counted), the view is framed.
    std::string text = triangleGltf();
    const std::string nodes = R"("scenes":[{"nodes":[0]}],"nodes":[{"mesh":0}],)";
    ASSERT_NE(text.find(nodes), std::string::npos);
    text.replace(
        text.find(nodes), nodes.size(),
        R"("scenes":[{"nodes":[0,1]}],"nodes":[{"mesh":0},{"camera":0,"translation":[0,0,5]}],
                    "cameras":[{"type":"orthographic","orthographic":{"xmag":1,"ymag":1,"zfar":10,"znear":0.1}}],)");
    const geometry::Scene ortho = geometry::loadScene(write("ortho.gltf", text));
    EXPECT_EQ(ortho.cameraSource, "framed");
    EXPECT_TRUE(ortho.cameras.empty());
    EXPECT_EQ(ortho.skippedCameras, 1);
    EXPECT_EQ(ortho.camera.eye, tri.camera.eye);
}

TEST_F(SceneTest, OpenModelGivenDirectlyIsFramedFromOutside) {
    // A single box is not enclosing anything: the bounds are framed from outside, light above.
    geometry::Scene s;
    s.objects.push_back({"box", geometry::ShadowMethod::Auto,
                         geometry::makeBox({0, 0.5f, 0}, {1, 1, 1})});
    EXPECT_FALSE(geometry::frameInterior(s));
    const geometry::Aabb b = s.bounds();
    const geometry::Camera cam = geometry::defaultCamera(b);
    EXPECT_NEAR(glm::length(cam.target - b.center()), 0.0f, 1e-5f);
    EXPECT_GT(cam.eye.y, b.max.y);
    const geometry::RectLight L = geometry::defaultLight(b);
    EXPECT_GT(L.center.y, b.max.y);
    EXPECT_LT(L.normal().y, -0.99f);
}

TEST_F(SceneTest, DefaultFramingOfSmallModel) {
    // A glTF written to disk goes through the same path; the triangle lies in z = 0, so the
    // horizontal extent is degenerate in z and the light keeps its nominal size.
    const geometry::Scene s = geometry::loadScene(mDir / "models" / "tri.gltf");
    EXPECT_EQ(s.triangleCount(), 1u);
    EXPECT_GT(s.light.area(), 0.0f);
    EXPECT_NO_THROW(geometry::validateScene(s));
}

TEST_F(SceneTest, ValidateSceneRejectsEditedScene) {
    geometry::Scene s = geometry::loadScene(write("scene.json", scene(kBox)));
    s.light.v = s.light.u;
    EXPECT_THROW(geometry::validateScene(s), geometry::InputError);
    s = geometry::loadScene(mDir / "scene.json");
    s.camera.fovYDeg = std::nanf("");
    EXPECT_THROW(geometry::validateScene(s), geometry::InputError);
}

TEST(SceneToString, MethodNames) {
    EXPECT_STREQ(geometry::toString(geometry::ShadowMethod::Auto), "auto");
    EXPECT_STREQ(geometry::toString(geometry::ShadowMethod::Wedges), "wedges");
    EXPECT_STREQ(geometry::toString(geometry::ShadowMethod::Occlusion), "occlusion");
    EXPECT_STREQ(geometry::toString(geometry::ShadowMethod::None), "none");
}

} // namespace
