#include <geometry/core/Error.h>
#include <geometry/scene/GltfLoader.h>
#include <geometry/scene/Scene.h>
#include <geometry/scene/ImageIO.h>

#include "TestFiles.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <initializer_list>
#include <limits>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;

const fs::path kShared = PENUMBRA_SHARED_DIR;

std::string base64(const std::string& bytes) {
    static const char* table = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    std::size_t i = 0;
    for (; i + 2 < bytes.size(); i += 3) {
        const unsigned v = (unsigned char)bytes[i] << 16 | (unsigned char)bytes[i + 1] << 8 |
                           (unsigned char)bytes[i + 2];
        out += {table[v >> 18], table[(v >> 12) & 63], table[(v >> 6) & 63], table[v & 63]};
    }
    if (i + 1 == bytes.size()) {
        const unsigned v = (unsigned char)bytes[i] << 16;
        out += {table[v >> 18], table[(v >> 12) & 63], '=', '='};
    } else if (i + 2 == bytes.size()) {
        const unsigned v = (unsigned char)bytes[i] << 16 | (unsigned char)bytes[i + 1] << 8;
        out += {table[v >> 18], table[(v >> 12) & 63], table[(v >> 6) & 63], '='};
    }
    return out;
}

template <class T> std::string bytesOf(std::initializer_list<T> values) {
    std::string s;
    for (T v : values)
        s.append(reinterpret_cast<const char*>(&v), sizeof v);
    return s;
}

// Builds a small .gltf with one embedded base64 buffer: add views and accessors, then write with
// hand-written meshes/nodes JSON.
class GltfWriter {
public:
    int view(const std::string& bytes, int stride = 0) {
        while (mBuffer.size() % 4)
            mBuffer.push_back('\0');
        mViews.push_back(R"({"buffer":0,"byteOffset":)" + std::to_string(mBuffer.size()) +
                         R"(,"byteLength":)" + std::to_string(bytes.size()) +
                         (stride ? R"(,"byteStride":)" + std::to_string(stride) : "") + "}");
        mBuffer += bytes;
        return int(mViews.size()) - 1;
    }
    int accessor(int view, int componentType, int count, const std::string& type,
                 const std::string& extra = "") {
        mAccessors.push_back(R"({"bufferView":)" + std::to_string(view) + R"(,"componentType":)" +
                             std::to_string(componentType) + R"(,"count":)" +
                             std::to_string(count) + R"(,"type":")" + type + "\"" + extra + "}");
        return int(mAccessors.size()) - 1;
    }
    // Positions as float VEC3 in their own view.
    int positions(std::initializer_list<float> xyz) {
        return accessor(view(bytesOf(xyz)), 5126, int(xyz.size() / 3), "VEC3");
    }
    int indices32(std::initializer_list<std::uint32_t> idx) {
        return accessor(view(bytesOf(idx)), 5125, int(idx.size()), "SCALAR");
    }
    std::string json(const std::string& meshes, const std::string& nodes = R"([{"mesh":0}])",
                     const std::string& scenes = R"("scene":0,"scenes":[{"nodes":[0]}],)",
                     const std::string& extra = "") const {
        std::string s = R"({"asset":{"version":"2.0"},)" + scenes + extra;
        s += R"("buffers":[{"byteLength":)" + std::to_string(mBuffer.size()) +
             R"(,"uri":"data:application/octet-stream;base64,)" + base64(mBuffer) + "\"}],";
        s += R"("bufferViews":[)" + join(mViews) + "],";
        s += R"("accessors":[)" + join(mAccessors) + "],";
        s += R"("meshes":)" + meshes + R"(,"nodes":)" + nodes + "}";
        return s;
    }

private:
    static std::string join(const std::vector<std::string>& v) {
        std::string s;
        for (const auto& e : v)
            s += (s.empty() ? "" : ",") + e;
        return s;
    }
    std::string mBuffer;
    std::vector<std::string> mViews, mAccessors;
};

const char* kOneTriangleMesh = R"([{"primitives":[{"attributes":{"POSITION":0},"indices":1}]}])";

class GltfTest : public testutil::TempDirTest {
protected:
    GltfTest() : TempDirTest("gltf") {}
    fs::path write(const std::string& name, const std::string& text) const {
        std::ofstream(mDir / name, std::ios::binary) << text;
        return mDir / name;
    }
    // Loads and expects an InputError naming the file and containing `needle`.
    void expectError(const fs::path& path, const std::string& needle) const {
        try {
            geometry::loadGltf(path);
            ADD_FAILURE() << path << ": expected InputError containing \"" << needle << "\"";
        } catch (const geometry::InputError& e) {
            const std::string msg = e.what();
            EXPECT_NE(msg.find(path.filename().string()), std::string::npos) << msg;
            EXPECT_NE(msg.find(needle), std::string::npos) << msg;
        }
    }
};

glm::vec3 normalOf(const geometry::MeshData& m, std::size_t t) {
    const auto& tri = m.triangles[t];
    return glm::cross(m.positions[tri.y] - m.positions[tri.x],
                      m.positions[tri.z] - m.positions[tri.x]);
}

void expectVec(const glm::vec3& a, const glm::vec3& b) {
    EXPECT_NEAR(a.x, b.x, 1e-5f);
    EXPECT_NEAR(a.y, b.y, 1e-5f);
    EXPECT_NEAR(a.z, b.z, 1e-5f);
}

TEST_F(GltfTest, LoadsOpenArenaLevel) {
    const geometry::MeshData m = geometry::loadGltf(kShared / "levels" / "oa_dm1.glb");
    EXPECT_EQ(m.triangles.size(), 7502u); // levels/README.md
    EXPECT_EQ(m.triangleMaterial.size(), m.triangles.size());
    EXPECT_TRUE(m.texcoords.empty()); // the levels carry positions and indices only
    EXPECT_TRUE(m.textures.empty());
    EXPECT_FALSE(m.materials.empty());
    for (const auto& t : m.triangles) {
        ASSERT_LT(std::max({t.x, t.y, t.z}), m.positions.size());
    }
    for (std::uint32_t mat : m.triangleMaterial)
        ASSERT_LT(mat, m.materials.size());
    const geometry::Aabb b = m.bounds();
    ASSERT_FALSE(b.empty());
    for (int i = 0; i < 3; ++i) {
        EXPECT_TRUE(std::isfinite(b.min[i]) && std::isfinite(b.max[i]));
        EXPECT_GT(b.max[i] - b.min[i], 1.0f); // an arena is metres across in every axis
    }
}

TEST_F(GltfTest, LoadsFoliageMaterialAndTexture) {
    const geometry::MeshData m = geometry::loadGltf(kShared / "foliage" / "oak_hungarian_1.glb");
    EXPECT_EQ(m.triangles.size(), 394u); // foliage/README.md
    ASSERT_EQ(m.materials.size(), 1u);
    const geometry::Material& mat = m.materials[0];
    EXPECT_EQ(mat.alphaMode, geometry::AlphaMode::Mask);
    EXPECT_FLOAT_EQ(mat.alphaCutoff, 0.5f);
    EXPECT_TRUE(mat.doubleSided);
    ASSERT_EQ(mat.baseColorTexture, 0);
    ASSERT_EQ(m.textures.size(), 1u);
    const geometry::TextureImage& tex = m.textures[0];
    EXPECT_EQ(tex.width, 512);
    EXPECT_EQ(tex.height, 512);
    ASSERT_EQ(tex.rgba8.size(), 512u * 512u * 4u);
    // ~55% of the texels are transparent (README): the alpha channel must have survived.
    std::size_t transparent = 0;
    for (std::size_t i = 3; i < tex.rgba8.size(); i += 4)
        transparent += tex.rgba8[i] < 128;
    const double share = double(transparent) / (512.0 * 512.0);
    EXPECT_GT(share, 0.3);
    EXPECT_LT(share, 0.8);
    ASSERT_EQ(m.texcoords.size(), m.positions.size());
    EXPECT_EQ(m.triangleMaterial.size(), m.triangles.size());
}

TEST_F(GltfTest, MissingFile) {
    expectError(mDir / "nope.glb", "not found");
}

TEST_F(GltfTest, GarbageBytes) {
    expectError(write("garbage.gltf", "this is { not json"), "parse error");
    std::string glb = "glTF";
    for (int i = 0; i < 64; ++i)
        glb.push_back(char(i * 37));
    // The GLB header is checked before tinygltf sees it: the version field is the first thing
    // wrong here.
    expectError(write("garbage.glb", glb), "malformed GLB: version");
}

TEST_F(GltfTest, NoMeshes) {
    expectError(write("empty.gltf", R"({"asset":{"version":"2.0"}})"), "no meshes");
}

TEST_F(GltfTest, NaNPosition) {
    GltfWriter w;
    const float nan = std::numeric_limits<float>::quiet_NaN();
    w.positions({0, 0, 0, 1, 0, 0, 0, nan, 0});
    w.indices32({0, 1, 2});
    expectError(write("nan.gltf", w.json(kOneTriangleMesh)), "NaN");
}

// A finite float far beyond what single precision renders (Embree aborts on ray origins past
// 1.8e19): refused with the accessor, the vertex and the bound named.
TEST_F(GltfTest, CoordinateBeyondTheRenderableRange) {
    GltfWriter w;
    w.positions({-1, 0, -1, 1, 0, -1, 0, 0, 1, 0, 1, 1e19f});
    w.indices32({0, 1, 2, 0, 1, 3});
    const fs::path path = write("huge.gltf", w.json(kOneTriangleMesh));
    expectError(path, "POSITION (accessor 0) vertex 3 has z = 1e+19, outside [-1e+07, 1e+07]");
    try {
        geometry::loadGltf(path);
    } catch (const geometry::InputError& e) {
        EXPECT_NE(std::string(e.what()).find("single precision"), std::string::npos) << e.what();
    }
    // Within the bound on file, beyond it after a node scale: said so.
    GltfWriter scaled;
    scaled.positions({0, 0, 0, 1, 0, 0, 0, 1, 0});
    scaled.indices32({0, 1, 2});
    expectError(write("scaled.gltf",
                      scaled.json(kOneTriangleMesh, R"([{"mesh":0,"scale":[1,2e7,1]}])")),
                "vertex 2 has y = 2e+07 after the node transforms");
    // The bound itself is accepted.
    GltfWriter edge;
    edge.positions({0, 0, 0, 1e7f, 0, 0, 0, -1e7f, 0});
    edge.indices32({0, 1, 2});
    EXPECT_EQ(geometry::loadGltf(write("edge.gltf", edge.json(kOneTriangleMesh))).triangles.size(),
              1u);
}

// An index accessor claiming more triangles than a scene may have is refused before anything is
// read or allocated (its data would run past the buffer too: the budget speaks first).
TEST_F(GltfTest, TriangleBudget) {
    GltfWriter w;
    w.positions({0, 0, 0, 1, 0, 0, 0, 1, 0});
    w.accessor(w.view(bytesOf<std::uint32_t>({0, 1, 2})), 5125, 3 * (1 << 22) + 3, "SCALAR");
    expectError(write("many.gltf", w.json(kOneTriangleMesh)),
                "4194305 triangles bring the file to 4194305, more than the 4194304 a scene "
                "may have");
}

// Wrong index types are named as such, before their data is read (a FLOAT accessor over three
// uint16 indices once "ran past the end" of its view).
TEST_F(GltfTest, FloatIndicesAreNamedAsTheWrongType) {
    GltfWriter w;
    w.positions({0, 0, 0, 1, 0, 0, 0, 1, 0});
    w.accessor(w.view(bytesOf<std::uint16_t>({0, 1, 2})), 5126, 3, "SCALAR");
    expectError(write("float.gltf", w.json(kOneTriangleMesh)),
                "indices (accessor 1) are float SCALAR; indices must be SCALAR unsigned byte, "
                "short or int");
}

// The walk is bounded at 1000 levels: a deeper chain says so; a real cycle is still a cycle.
TEST_F(GltfTest, DeepNodeChainIsNotACycle) {
    auto chain = [](int levels) {
        std::string nodes = "[";
        for (int i = 0; i < levels; ++i) {
            nodes += i ? "," : "";
            nodes += i + 1 < levels ? R"({"children":[)" + std::to_string(i + 1) + "]}"
                                    : std::string(R"({"mesh":0})");
        }
        return nodes + "]";
    };
    GltfWriter w;
    w.positions({0, 0, 0, 1, 0, 0, 0, 1, 0});
    w.indices32({0, 1, 2});
    EXPECT_EQ(geometry::loadGltf(write("deep1000.gltf", w.json(kOneTriangleMesh, chain(1000))))
                  .triangles.size(),
              1u);
    const fs::path deep = write("deep1001.gltf", w.json(kOneTriangleMesh, chain(1001)));
    expectError(deep, "node hierarchy is deeper than 1000 levels (node 1000 is at level 1001)");
    try {
        geometry::loadGltf(deep);
    } catch (const geometry::InputError& e) {
        EXPECT_EQ(std::string(e.what()).find("has a cycle"), std::string::npos) << e.what();
    }
    expectError(write("cycle.gltf", w.json(kOneTriangleMesh,
                                           R"([{"mesh":0,"children":[1]},{"children":[0]}])")),
                "node hierarchy has a cycle through node 0");
}

// A .glb whose first bytes are not the GLB magic says so (it once got a JSON parse error); a
// .glb holding JSON text still loads, mislabelled.
TEST_F(GltfTest, GlbWithBadMagic) {
    std::string bytes = "glTX";
    for (int i = 0; i < 60; ++i)
        bytes.push_back(char(i));
    expectError(write("bad.glb", bytes),
                "not a binary glTF file: it begins with 'glTX' (67 6c 54 58) where a GLB begins "
                "with the magic 'glTF'");
    GltfWriter w;
    w.positions({0, 0, 0, 1, 0, 0, 0, 1, 0});
    w.indices32({0, 1, 2});
    EXPECT_EQ(geometry::loadGltf(write("text.glb", w.json(kOneTriangleMesh))).triangles.size(), 1u);
}

TEST_F(GltfTest, IndexOutOfRange) {
    GltfWriter w;
    w.positions({0, 0, 0, 1, 0, 0, 0, 1, 0});
    w.indices32({0, 1, 3});
    expectError(write("range.gltf", w.json(kOneTriangleMesh)), "out of range");
}

TEST_F(GltfTest, PointsModeRejected) {
    GltfWriter w;
    w.positions({0, 0, 0, 1, 0, 0, 0, 1, 0});
    expectError(write("points.gltf",
                      w.json(R"([{"primitives":[{"attributes":{"POSITION":0},"mode":0}]}])")),
                "POINTS");
}

TEST_F(GltfTest, NonFloatPositionsRejected) {
    GltfWriter w;
    w.accessor(w.view(bytesOf<std::uint16_t>({0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 0})), 5123, 3,
               "VEC3");
    w.indices32({0, 1, 2});
    expectError(write("ushort.gltf", w.json(kOneTriangleMesh)), "float");
}

TEST_F(GltfTest, NodeTranslationAndScale) {
    GltfWriter w;
    w.positions({0, 0, 0, 1, 0, 0, 0, 1, 0});
    w.indices32({0, 1, 2});
    const auto path =
        write("trs.gltf",
              w.json(kOneTriangleMesh, R"([{"mesh":0,"translation":[1,2,3],"scale":[2,2,2]}])"));
    const geometry::MeshData m = geometry::loadGltf(path);
    ASSERT_EQ(m.positions.size(), 3u);
    expectVec(m.positions[0], {1, 2, 3});
    expectVec(m.positions[1], {3, 2, 3}); // scaled first, then translated
    expectVec(m.positions[2], {1, 4, 3});
    EXPECT_GT(normalOf(m, 0).z, 0.0f);
}

TEST_F(GltfTest, NodeHierarchyRotationMatrixAndExtraTransform) {
    GltfWriter w;
    w.positions({0, 0, 0, 1, 0, 0, 0, 1, 0});
    w.indices32({0, 1, 2});
    // Parent: column-major matrix translating by (10, 0, 0). Child: 90° about +z
    // (quaternion x,y,z,w = 0,0,sin45,cos45), which maps (1,0,0) to (0,1,0).
    const std::string nodes =
        R"([{"matrix":[1,0,0,0, 0,1,0,0, 0,0,1,0, 10,0,0,1],"children":[1]},
            {"mesh":0,"rotation":[0,0,0.70710678,0.70710678]}])";
    const auto path = write("tree.gltf", w.json(kOneTriangleMesh, nodes));
    const geometry::MeshData m = geometry::loadGltf(path);
    ASSERT_EQ(m.positions.size(), 3u);
    expectVec(m.positions[1], {10, 1, 0});
    expectVec(m.positions[2], {9, 0, 0});
    // The loader's own transform applies on top of the scene (world = transform * scene).
    glm::mat4 lift(1.0f);
    lift[3] = glm::vec4(0, 5, 0, 1);
    const geometry::MeshData lifted = geometry::loadGltf(path, lift);
    expectVec(lifted.positions[1], {10, 6, 0});
}

TEST_F(GltfTest, MirroredNodeFlipsWinding) {
    GltfWriter w;
    w.positions({0, 0, 0, 1, 0, 0, 0, 1, 0}); // counter-clockwise seen from +z
    w.indices32({0, 1, 2});
    const auto plain = geometry::loadGltf(write("plain.gltf", w.json(kOneTriangleMesh)));
    const auto mirrored = geometry::loadGltf(
        write("mirror.gltf", w.json(kOneTriangleMesh, R"([{"mesh":0,"scale":[-1,1,1]}])")));
    EXPECT_GT(normalOf(plain, 0).z, 0.0f);
    // Mirroring in x keeps the front on +z; without the flip the normal would point to -z.
    EXPECT_GT(normalOf(mirrored, 0).z, 0.0f);
    expectVec(mirrored.positions[1], {-1, 0, 0});
}

TEST_F(GltfTest, StripsAndFansConverted) {
    GltfWriter w;
    // A unit square in z = 0 as a strip 0-1-2-3 and as a fan 0-1-2-3 (different vertex order).
    w.positions({0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0});
    w.positions({0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0});
    const auto m = geometry::loadGltf(
        write("strip.gltf", w.json(R"([{"primitives":[{"attributes":{"POSITION":0},"mode":5},
                                                 {"attributes":{"POSITION":1},"mode":6}]}])")));
    ASSERT_EQ(m.triangles.size(), 4u);
    double area = 0.0;
    for (std::size_t t = 0; t < 4; ++t) {
        EXPECT_GT(normalOf(m, t).z, 0.0f) << "triangle " << t; // one consistent winding
        area += 0.5 * glm::length(normalOf(m, t));
    }
    EXPECT_NEAR(area, 2.0, 1e-6);
}

TEST_F(GltfTest, IndexTypesStrideAndNonIndexed) {
    GltfWriter w;
    // Interleaved: position (12 bytes) + 4 padding bytes per vertex, byteStride 16.
    std::string inter;
    for (float v : {0.f, 0.f, 0.f, -1.f, 2.f, 0.f, 0.f, -1.f, 0.f, 2.f, 0.f, -1.f}) {
        inter += bytesOf({v});
    }
    w.accessor(w.view(inter, 16), 5126, 3, "VEC3");
    w.accessor(w.view(bytesOf<std::uint8_t>({0, 1, 2})), 5121, 3, "SCALAR");
    w.accessor(w.view(bytesOf<std::uint16_t>({2, 0, 1})), 5123, 3, "SCALAR");
    const auto m = geometry::loadGltf(
        write("types.gltf", w.json(R"([{"primitives":[{"attributes":{"POSITION":0},"indices":1},
                                                 {"attributes":{"POSITION":0},"indices":2},
                                                 {"attributes":{"POSITION":0}}]}])")));
    ASSERT_EQ(m.triangles.size(), 3u);
    ASSERT_EQ(m.positions.size(), 9u); // one vertex range per primitive
    expectVec(m.positions[1], {2, 0, 0});
    expectVec(m.positions[2], {0, 2, 0});
    EXPECT_EQ(m.triangles[1], glm::uvec3(5, 3, 4));
    EXPECT_EQ(m.triangles[2], glm::uvec3(6, 7, 8));
}

TEST_F(GltfTest, SparseAccessorApplied) {
    GltfWriter w;
    const int base = w.view(bytesOf<float>({0, 0, 0, 1, 0, 0, 9, 9, 9}));
    const int sIdx = w.view(bytesOf<std::uint16_t>({2}));
    const int sVal = w.view(bytesOf<float>({0, 1, 0}));
    w.accessor(base, 5126, 3, "VEC3",
               R"(,"sparse":{"count":1,"indices":{"bufferView":)" + std::to_string(sIdx) +
                   R"(,"componentType":5123},"values":{"bufferView":)" + std::to_string(sVal) +
                   "}}");
    w.indices32({0, 1, 2});
    const auto m = geometry::loadGltf(write("sparse.gltf", w.json(kOneTriangleMesh)));
    ASSERT_EQ(m.positions.size(), 3u);
    expectVec(m.positions[2], {0, 1, 0});
}

TEST_F(GltfTest, TexcoordsFilledWhenOnlySomePrimitivesHaveThem) {
    GltfWriter w;
    w.positions({0, 0, 0, 1, 0, 0, 0, 1, 0});
    w.indices32({0, 1, 2});
    w.accessor(w.view(bytesOf<std::uint8_t>({0, 0, 255, 0, 0, 255})), 5121, 3, "VEC2",
               R"(,"normalized":true)");
    const auto m = geometry::loadGltf(
        write("uv.gltf", w.json(R"([{"primitives":[{"attributes":{"POSITION":0},"indices":1},
                            {"attributes":{"POSITION":0,"TEXCOORD_0":2},"indices":1}]}])")));
    ASSERT_EQ(m.texcoords.size(), 6u);
    EXPECT_EQ(m.texcoords[1], glm::vec2(0.0f)); // first primitive had none
    EXPECT_EQ(m.texcoords[4], glm::vec2(1.0f, 0.0f));
    EXPECT_EQ(m.texcoords[5], glm::vec2(0.0f, 1.0f));
}

// NORMAL is for shading only: world space through the inverse transpose, unit length; a zero
// normal stays zero (the face's is used), primitives without NORMAL get zeros.
TEST_F(GltfTest, NormalsTransformByTheInverseTranspose) {
    GltfWriter w;
    w.positions({0, 0, 0, 1, 0, 0, 0, 1, 0});
    w.indices32({0, 1, 2});
    const float h = 0.70710678f;
    w.accessor(w.view(bytesOf<float>({h, h, 0, 0, 0, 0, 0, 0, 1})), 5126, 3, "VEC3");
    const auto m = geometry::loadGltf(
        write("normals.gltf",
              w.json(R"([{"primitives":[{"attributes":{"POSITION":0,"NORMAL":2},"indices":1},
                                        {"attributes":{"POSITION":0},"indices":1}]}])",
                     R"([{"mesh":0,"scale":[2,1,1]}])")));
    ASSERT_EQ(m.normals.size(), 6u);
    // diag(2, 1, 1) -> diag(1/2, 1, 1): (1, 1, 0) -> (1/2, 1, 0), renormalised.
    expectVec(m.normals[0], glm::normalize(glm::vec3(0.5f, 1.0f, 0.0f)));
    expectVec(m.normals[1], {0, 0, 0});
    expectVec(m.normals[2], {0, 0, 1});
    for (int i = 3; i < 6; ++i) expectVec(m.normals[i], {0, 0, 0}); // no NORMAL there
    // A file without any NORMAL has none at all.
    GltfWriter plain;
    plain.positions({0, 0, 0, 1, 0, 0, 0, 1, 0});
    plain.indices32({0, 1, 2});
    EXPECT_TRUE(geometry::loadGltf(write("plain.gltf", plain.json(kOneTriangleMesh))).normals.empty());
}

TEST_F(GltfTest, BadNormalsAreRefused) {
    const auto withNormals = [&](const std::string& name, std::initializer_list<float> normals,
                                 int count, const char* type) {
        GltfWriter w;
        w.positions({0, 0, 0, 1, 0, 0, 0, 1, 0});
        w.indices32({0, 1, 2});
        w.accessor(w.view(bytesOf<float>(normals)), 5126, count, type);
        return write(name, w.json(
            R"([{"primitives":[{"attributes":{"POSITION":0,"NORMAL":2},"indices":1}]}])"));
    };
    const float nan = std::numeric_limits<float>::quiet_NaN();
    const float inf = std::numeric_limits<float>::infinity();
    expectError(withNormals("nan.gltf", {0, 0, 1, nan, 0, 1, 0, 0, 1}, 3, "VEC3"),
                "NORMAL 1 is NaN or infinite");
    expectError(withNormals("inf.gltf", {0, 0, 1, 0, 0, 1, 0, inf, 1}, 3, "VEC3"),
                "NORMAL 2 is NaN or infinite");
    expectError(withNormals("count.gltf", {0, 0, 1, 0, 0, 1}, 2, "VEC3"),
                "NORMAL has 2 elements, POSITION 3");
    expectError(withNormals("type.gltf", {0, 0, 1, 0, 0, 1}, 3, "VEC2"),
                "NORMAL must be VEC3 of float");
}

TEST_F(GltfTest, NoDefaultSceneUsesRootNodes) {
    GltfWriter w;
    w.positions({0, 0, 0, 1, 0, 0, 0, 1, 0});
    w.indices32({0, 1, 2});
    // Node 1 is a child of node 0 and must be visited once, through its parent.
    const auto m = geometry::loadGltf(
        write("roots.gltf",
              w.json(kOneTriangleMesh,
                     R"([{"mesh":0,"children":[1]},{"mesh":0,"translation":[0,0,1]}])", "")));
    EXPECT_EQ(m.triangles.size(), 2u);
    EXPECT_FLOAT_EQ(m.bounds().max.z, 1.0f);
}

TEST_F(GltfTest, MeshWithoutTrianglesInScene) {
    GltfWriter w;
    w.positions({0, 0, 0, 1, 0, 0, 0, 1, 0});
    w.indices32({0, 1, 2});
    // The mesh exists but no node of the scene draws it.
    expectError(write("unused.gltf", w.json(kOneTriangleMesh, R"([{"name":"empty"}])")),
                "no triangles");
}

// Buffer and image URIs stay inside the model's folder (mDir/model): no "..", no absolute paths,
// no URLs, no symlinks out, no fallback to the working directory. A file outside is never read,
// so its size cannot leak into a message.
class ExternalUriTest : public GltfTest {
protected:
    void SetUp() override {
        GltfTest::SetUp();
        fs::create_directories(mDir / "model" / "sub");
        // One triangle: 36 bytes of positions, then 3 uint32 indices.
        mBytes = bytesOf<float>({0, 0, 0, 1, 0, 0, 0, 1, 0}) + bytesOf<std::uint32_t>({0, 1, 2});
        std::ofstream(mDir / "model" / "sub" / "tri.bin", std::ios::binary) << mBytes;
        std::ofstream(mDir / "secret.bin", std::ios::binary) << mBytes << "and more";
    }
    // model/NAME with its buffer at `uri` and, when given, an image at `imageUri`.
    fs::path model(const std::string& name, const std::string& uri,
                   const std::string& imageUri = "") const {
        const std::string text =
            R"({"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[0]}],"nodes":[{"mesh":0}],
            "meshes":[{"primitives":[{"attributes":{"POSITION":0},"indices":1}]}],
            "buffers":[{"byteLength":48,"uri":")" + uri + R"("}],
            "bufferViews":[{"buffer":0,"byteLength":36},
                           {"buffer":0,"byteOffset":36,"byteLength":12}],
            "accessors":[{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3"},
                         {"bufferView":1,"componentType":5125,"count":3,"type":"SCALAR"}])" +
            (imageUri.empty() ? "" : R"(,"images":[{"uri":")" + imageUri + R"("}])") + "}";
        std::ofstream(mDir / "model" / name, std::ios::binary) << text;
        return mDir / "model" / name;
    }
    void expectRefused(const fs::path& path, const std::string& needle) const {
        expectError(path, needle);
        try {
            geometry::loadGltf(path);
        } catch (const geometry::InputError& e) {
            const std::string msg = e.what();
            EXPECT_NE(msg.find("a glTF file may read only files in its own folder"),
                      std::string::npos) << msg;
            // The size must not show; the temporary folder's name (which holds digits, the
            // process id among them) is taken out before looking.
            std::string rest = msg;
            for (std::size_t at; (at = rest.find(mDir.string())) != std::string::npos;)
                rest.erase(at, mDir.string().size());
            EXPECT_EQ(rest.find("56"), std::string::npos) << "secret.bin's size leaked: " << msg;
        }
    }
    std::string mBytes;
};

TEST_F(ExternalUriTest, InsideTheFolderLoads) {
    EXPECT_EQ(geometry::loadGltf(model("ok.gltf", "sub/tri.bin")).triangles.size(), 1u);
    EXPECT_EQ(geometry::loadGltf(model("dots.gltf", "sub/../sub/./tri.bin")).triangles.size(), 1u);
    EXPECT_EQ(geometry::loadGltf(model("pct.gltf", "sub%2Ftri.bin")).triangles.size(), 1u);
    // A bare file name: its folder is the working directory.
    const fs::path path = model("here.gltf", "sub/tri.bin");
    const fs::path cwd = fs::current_path();
    fs::current_path(path.parent_path());
    std::size_t triangles = 0;
    try {
        triangles = geometry::loadGltf("here.gltf").triangles.size();
    } catch (const geometry::InputError& e) {
        ADD_FAILURE() << e.what();
    }
    fs::current_path(cwd);
    EXPECT_EQ(triangles, 1u);
}

TEST_F(ExternalUriTest, EscapesAreRefused) {
    expectRefused(model("up.gltf", "../secret.bin"),
                  "buffers[0].uri '../secret.bin' leads outside the model's folder");
    expectRefused(model("deep.gltf", "../../../../../../../../etc/passwd"), "leads outside");
    expectRefused(model("pct.gltf", "%2e%2e/secret.bin"), "leads outside");
    expectRefused(model("abs.gltf", (mDir / "secret.bin").string()), "is an absolute path");
    expectRefused(model("url.gltf", "file:///etc/passwd"), "is a URL");
    expectRefused(model("image.gltf", "sub/tri.bin", "../leaf.png"),
                  "images[0].uri '../leaf.png' leads outside");
    fs::create_symlink(mDir / "secret.bin", mDir / "model" / "link.bin");
    expectRefused(model("link.gltf", "link.bin"), "buffers[0].uri 'link.bin' leads outside");
}

// tinygltf looks for a file missing beside the model in the working directory too: refused when
// that is outside the model's folder.
TEST_F(ExternalUriTest, NoFallbackToTheWorkingDirectory) {
    fs::create_directories(mDir / "elsewhere");
    std::ofstream(mDir / "elsewhere" / "gone.bin", std::ios::binary) << mBytes;
    const fs::path path = model("gone.gltf", "gone.bin");
    const fs::path cwd = fs::current_path();
    fs::current_path(mDir / "elsewhere");
    std::string msg;
    try {
        geometry::loadGltf(path);
    } catch (const geometry::InputError& e) {
        msg = e.what();
    }
    fs::current_path(cwd);
    EXPECT_NE(msg.find("resolves to " + (mDir / "elsewhere" / "gone.bin").string() +
                       ", outside the model's folder"),
              std::string::npos)
        << msg;
    // Without the stray file it is simply not found.
    fs::remove(mDir / "elsewhere" / "gone.bin");
    expectError(path, "File not found : gone.bin");
}

// Cameras: node 1 (scale 2, 90° about +y, at (10, 0, 0)) has the camera node 2 "eye" as a child
// (at (0, 1, 0), rolled 90° about its z); node 3 is an unnamed root camera listed first in the
// scene, node 4 an orthographic camera; `moreNodes` (from index 5) are only reached as children.
class GltfCameraTest : public GltfTest {
protected:
    static constexpr const char* kCameras =
        R"("cameras":[{"type":"perspective","perspective":{"yfov":0.5,"znear":0.1}},
                      {"type":"orthographic","orthographic":{"xmag":1,"ymag":1,"zfar":10,"znear":0.1}}],)";
    static std::string file(const std::string& node3 = R"({"camera":0})",
                            const std::string& cameras = kCameras,
                            const std::string& moreNodes = "") {
        GltfWriter w;
        w.positions({0, 0, 0, 1, 0, 0, 0, 1, 0});
        w.indices32({0, 1, 2});
        const std::string nodes =
            R"([{"mesh":0},
                {"translation":[10,0,0],"rotation":[0,0.70710678,0,0.70710678],"scale":[2,2,2],
                 "children":[2]},
                {"name":"eye","camera":0,"translation":[0,1,0],"rotation":[0,0,0.70710678,0.70710678]},
                )" +
            node3 + R"(,
                {"name":"ortho","camera":1,"translation":[0,0,5]})" +
            moreNodes + "]";
        return w.json(kOneTriangleMesh, nodes, R"("scene":0,"scenes":[{"nodes":[3,0,1,4]}],)",
                      cameras);
    }
    // loadGltfWithCameras expects an InputError containing the file name and every needle.
    void expectCameraError(const fs::path& path, std::initializer_list<std::string> needles) {
        try {
            geometry::loadGltfWithCameras(path);
            ADD_FAILURE() << path << ": expected InputError";
        } catch (const geometry::InputError& e) {
            const std::string msg = e.what();
            EXPECT_NE(msg.find(path.filename().string()), std::string::npos) << msg;
            for (const auto& n : needles)
                EXPECT_NE(msg.find(n), std::string::npos) << msg;
        }
    }
};

// Far from the origin a unit step from the eye is lost in float rounding: the target steps
// farther, so the camera stays valid and keeps its direction.
TEST_F(GltfCameraTest, CameraFarFromTheOriginKeepsItsDirection) {
    glm::mat4 far(1.0f);
    far[3] = glm::vec4(3.0e6f, 0, 0, 1);
    const auto g = geometry::loadGltfWithCameras(write("far.gltf", file()), far);
    ASSERT_EQ(g.cameras.size(), 2u);
    const geometry::Camera& c = g.cameras[1].camera;
    EXPECT_NO_THROW(geometry::validateCamera(c));
    const glm::vec3 d = glm::normalize(c.target - c.eye);
    EXPECT_NEAR(d.x, 0.0f, 1e-3f);
    EXPECT_NEAR(d.z, -1.0f, 1e-6f);
}

TEST_F(GltfCameraTest, ParentTransformPlacesChildCamera) {
    glm::mat4 lift(1.0f);
    lift[3] = glm::vec4(0, 5, 0, 1);
    const auto g = geometry::loadGltfWithCameras(write("cams.gltf", file()), lift);
    EXPECT_EQ(g.mesh.triangles.size(), 1u);
    ASSERT_EQ(g.cameras.size(), 2u);
    EXPECT_EQ(g.orthographicCameras, 1);
    // File order (node 2 before node 3), although the scene walks node 3 first.
    const geometry::GltfCamera& eye = g.cameras[0];
    EXPECT_EQ(eye.name, "eye");
    EXPECT_EQ(eye.node, 2);
    // eye = lift + T(10,0,0) Ry(90°) S(2) (0,1,0) = (10, 2 + 5, 0).
    expectVec(eye.camera.eye, {10, 7, 0});
    // Forward: local -z, unchanged by the roll about z, turned by Ry(90°) to -x; unit length
    // despite the scale.
    expectVec(eye.camera.target - eye.camera.eye, {-1, 0, 0});
    // Up: local +y rolled to -x, then Ry(90°) to +z.
    expectVec(eye.camera.up, {0, 0, 1});
    EXPECT_NEAR(eye.camera.fovYDeg, 0.5f * 180.0f / 3.14159265f, 1e-4f);
    // The unnamed root camera: named by its index in the list, identity placement (+ lift).
    EXPECT_EQ(g.cameras[1].name, "camera 1");
    EXPECT_EQ(g.cameras[1].node, 3);
    expectVec(g.cameras[1].camera.eye, {0, 5, 0});
    expectVec(g.cameras[1].camera.target, {0, 5, -1});
    expectVec(g.cameras[1].camera.up, {0, 1, 0});

    // Cameras only: the same list; the mesh loader alone still works on the file.
    const auto only = geometry::loadGltfCameras(mDir / "cams.gltf", lift);
    ASSERT_EQ(only.size(), 2u);
    expectVec(only[0].camera.eye, {10, 7, 0});
    EXPECT_EQ(geometry::loadGltf(mDir / "cams.gltf").triangles.size(), 1u);
}

TEST_F(GltfCameraTest, CamerasOnlyNeedNoMesh) {
    const auto path = write("nomesh.gltf", R"({"asset":{"version":"2.0"},"scene":0,
        "scenes":[{"nodes":[0]}],"nodes":[{"name":"lone","camera":0,"translation":[1,2,3]}],
        "cameras":[{"type":"perspective","perspective":{"yfov":1.0,"znear":0.1}}]})");
    const auto cams = geometry::loadGltfCameras(path);
    ASSERT_EQ(cams.size(), 1u);
    expectVec(cams[0].camera.eye, {1, 2, 3});
    expectError(path, "no meshes"); // the mesh loader still needs one
}

TEST_F(GltfCameraTest, NonFiniteCameraTranslationNamesTheNode) {
    // JSON has no NaN (and tinygltf refuses 1e400), but a translation of finite doubles can
    // make one: under a parent whose x row is (1e300, 1e300, ...), x = 1e300² - 1e300² = NaN.
    expectCameraError(
        write("nan.gltf",
              file(R"({"matrix":[1e300,0,0,0, 1e300,1,0,0, 0,0,1,0, 0,0,0,1],"children":[5]})",
                   kCameras, R"(,{"name":"spawn x","camera":0,"translation":[1e300,-1e300,0]})")),
        {"node 5", "spawn x", "non-finite"});
    // 1e300 is finite in double but not in float.
    expectCameraError(
        write("huge.gltf", file(R"({"name":"spawn y","camera":0,"translation":[0,1e300,0]})")),
        {"node 3", "spawn y", "not finite"});
}

TEST_F(GltfCameraTest, DegenerateCamerasAreRefused) {
    expectCameraError(write("zero.gltf", file(R"({"name":"flat","camera":0,"scale":[1,1,0]})")),
                      {"node 3", "flat", "view direction"});
    expectCameraError(write("noup.gltf", file(R"({"name":"squashed","camera":0,"scale":[1,0,1]})")),
                      {"node 3", "squashed", "up direction"});
    // Shear: local +y mapped onto local -z's image.
    expectCameraError(
        write(
            "shear.gltf",
            file(
                R"({"name":"sheared","camera":0,"matrix":[1,0,0,0, 0,0,-1,0, 0,0,-1,0, 0,0,0,1]})")),
        {"node 3", "sheared", "parallel"});
    expectCameraError(
        write("fov.gltf",
              file(R"({"name":"wide","camera":0})",
                   R"("cameras":[{"type":"perspective","perspective":{"yfov":3.2,"znear":0.1}},
                                 {"type":"orthographic","orthographic":{"xmag":1,"ymag":1,"zfar":10,"znear":0.1}}],)")),
        {"node 3", "wide", "yfov"});
    expectCameraError(write("missing.gltf", file(R"({"camera":7})")),
                      {"node 3", "camera 7", "does not exist"});
}

TEST_F(GltfCameraTest, OpenArenaSpawnCameras) {
    const auto g = geometry::loadGltfWithCameras(kShared / "levels" / "oa_dm4.glb");
    EXPECT_EQ(g.mesh.triangles.size(), 4080u); // levels/README.md
    ASSERT_EQ(g.cameras.size(), 7u);           // 7 spawn points
    EXPECT_EQ(g.orthographicCameras, 0);
    const geometry::Aabb b = g.mesh.bounds();
    for (const auto& c : g.cameras) {
        SCOPED_TRACE(c.name);
        EXPECT_EQ(c.name.rfind("spawn ", 0), 0u);
        EXPECT_TRUE(glm::all(glm::greaterThan(c.camera.eye, b.min)) &&
                    glm::all(glm::lessThan(c.camera.eye, b.max)));
        // Spawn views are level: yaw only.
        expectVec(c.camera.up, {0, 1, 0});
        EXPECT_NEAR(c.camera.target.y, c.camera.eye.y, 1e-5f);
        EXPECT_NEAR(c.camera.fovYDeg, 73.7397953f, 1e-4f); // yfov 1.2870022 rad
    }
    EXPECT_EQ(g.cameras[0].name, "spawn 1 (info_player_start)");
    // Spawn 2 (node 2): eye (-1.6256, -6.858, -13.0048), rotated 180° about y: looks along +z.
    expectVec(g.cameras[1].camera.eye, {-1.6256f, -6.858f, -13.0048f});
    expectVec(g.cameras[1].camera.target - g.cameras[1].camera.eye, {0, 0, 1});
}

// An alpha-tested material on one textured triangle, with `material` and `texture` JSON
// spliced in; the 2×2 image (alpha 0 in its top-left texel) is a PNG beside the .gltf.
class AlphaMaterialTest : public GltfTest {
protected:
    fs::path writeTextured(const std::string& name, const std::string& material,
                           const std::string& texture = R"({"source":0})",
                           const std::string& samplers = "",
                           const std::string& attributes = R"("POSITION":0,"TEXCOORD_0":2)") {
        const std::uint8_t rgba[16] = {10, 20, 30, 0,   40, 50, 60, 255,
                                       70, 80, 90, 255, 100, 110, 120, 255};
        geometry::writePng(mDir / "leaf.png", 2, 2, 4, rgba);
        GltfWriter w;
        w.positions({0, 0, 0, 1, 0, 0, 0, 1, 0});
        w.indices32({0, 1, 2});
        w.accessor(w.view(bytesOf<float>({0, 0, 1, 0, 0, 1})), 5126, 3, "VEC2");
        const std::string extra = R"("materials":[)" + material + R"(],"textures":[)" + texture +
                                  R"(],"images":[{"uri":"leaf.png"}],)" + samplers;
        return write(name, w.json(R"([{"primitives":[{"attributes":{)" + attributes +
                                      R"(},"indices":1,"material":0}]}])",
                                  R"([{"mesh":0}])", R"("scene":0,"scenes":[{"nodes":[0]}],)",
                                  extra));
    }
};

TEST_F(AlphaMaterialTest, MaskKeepsCutoffTextureAndSamplerWraps) {
    const auto m = geometry::loadGltf(writeTextured(
        "mask.gltf",
        R"({"alphaMode":"MASK","alphaCutoff":0.3,"pbrMetallicRoughness":{"baseColorTexture":{"index":0},"baseColorFactor":[1,1,1,0.5]}})",
        R"({"source":0,"sampler":0})", R"("samplers":[{"wrapS":33071,"wrapT":33648}],)"));
    ASSERT_EQ(m.materials.size(), 1u);
    const geometry::Material& mat = m.materials[0];
    EXPECT_EQ(mat.alphaMode, geometry::AlphaMode::Mask);
    EXPECT_TRUE(mat.alphaTested());
    EXPECT_FLOAT_EQ(mat.alphaCutoff, 0.3f);
    EXPECT_FLOAT_EQ(mat.baseColor.a, 0.5f);
    ASSERT_EQ(mat.baseColorTexture, 0);
    ASSERT_EQ(m.textures.size(), 1u);
    EXPECT_EQ(m.textures[0].wrapS, geometry::TextureWrap::ClampToEdge);
    EXPECT_EQ(m.textures[0].wrapT, geometry::TextureWrap::MirroredRepeat);
    EXPECT_EQ(m.textures[0].rgba8[3], 0);   // the hole survived decoding
    EXPECT_EQ(m.textures[0].rgba8[7], 255);
    EXPECT_EQ(mat.baseColorUvTransform, glm::mat3(1.0f));
}

TEST_F(AlphaMaterialTest, WithoutSamplerWrapsRepeat) {
    const auto m = geometry::loadGltf(writeTextured(
        "repeat.gltf", R"({"alphaMode":"MASK","pbrMetallicRoughness":{"baseColorTexture":{"index":0}}})"));
    ASSERT_EQ(m.textures.size(), 1u);
    EXPECT_EQ(m.textures[0].wrapS, geometry::TextureWrap::Repeat);
    EXPECT_EQ(m.textures[0].wrapT, geometry::TextureWrap::Repeat);
    EXPECT_FLOAT_EQ(m.materials[0].alphaCutoff, 0.5f); // glTF default
}

TEST_F(AlphaMaterialTest, BlendIsTestedAtOneHalf) {
    // BLEND has no cutoff in glTF: a stray alphaCutoff must not move the test.
    const auto m = geometry::loadGltf(writeTextured(
        "blend.gltf",
        R"({"alphaMode":"BLEND","alphaCutoff":0.9,"pbrMetallicRoughness":{"baseColorTexture":{"index":0}}})"));
    EXPECT_EQ(m.materials[0].alphaMode, geometry::AlphaMode::Blend);
    EXPECT_TRUE(m.materials[0].alphaTested());
    EXPECT_FLOAT_EQ(m.materials[0].alphaCutoff, 0.5f);
}

TEST_F(AlphaMaterialTest, TextureTransformComposesOffsetRotationScale) {
    const auto m = geometry::loadGltf(writeTextured(
        "transform.gltf",
        R"({"alphaMode":"MASK","pbrMetallicRoughness":{"baseColorTexture":{"index":0,
            "extensions":{"KHR_texture_transform":{"offset":[0.5,0.25],"rotation":1.5707963,"scale":[2,3]}}}}})"));
    const glm::mat3& t = m.materials[0].baseColorUvTransform;
    // Scale, then rotate (x, y) -> (x cos + y sin, -x sin + y cos), then offset: (1, 0) -> (2, 0)
    // -> (0, -2) -> (0.5, -1.75); (0, 1) -> (0, 3) -> (3, 0) -> (3.5, 0.25).
    const glm::vec2 a = glm::vec2(t * glm::vec3(1.0f, 0.0f, 1.0f));
    EXPECT_NEAR(a.x, 0.5f, 1e-5f);
    EXPECT_NEAR(a.y, 0.25f - 2.0f, 1e-5f);
    const glm::vec2 b = glm::vec2(t * glm::vec3(0.0f, 1.0f, 1.0f));
    EXPECT_NEAR(b.x, 0.5f + 3.0f, 1e-5f);
    EXPECT_NEAR(b.y, 0.25f, 1e-5f);
}

TEST_F(AlphaMaterialTest, MaskThroughSecondTexcoordSetIsRefused) {
    expectError(writeTextured("uv1.gltf",
                              R"({"alphaMode":"MASK","pbrMetallicRoughness":{"baseColorTexture":{"index":0,"texCoord":1}}})"),
                "TEXCOORD_1");
}

TEST_F(AlphaMaterialTest, MaskWithoutTexcoordsIsRefused) {
    expectError(writeTextured("nouv.gltf",
                              R"({"alphaMode":"MASK","pbrMetallicRoughness":{"baseColorTexture":{"index":0}}})",
                              R"({"source":0})", "", R"("POSITION":0)"),
                "no TEXCOORD_0");
}

TEST_F(AlphaMaterialTest, UnknownWrapModeIsRefused) {
    expectError(writeTextured("wrap.gltf",
                              R"({"alphaMode":"MASK","pbrMetallicRoughness":{"baseColorTexture":{"index":0}}})",
                              R"({"source":0,"sampler":0})", R"("samplers":[{"wrapS":1234}],)"),
                "wrap mode 1234");
}

} // namespace
