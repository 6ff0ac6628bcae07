// Regression tests for textured glTF files made as an attacker would make them: images in GLB
// buffer views and data: URIs, image headers claiming huge sizes, offsets out of range, values
// finite as double but not as float, malformed material keys tinygltf drops without a word,
// required extensions, and URIs with a '+'. Each must load correctly or end in an InputError
// naming the key, before a pixel of a refused image is decoded (the fuzz build runs the same
// inputs under ASan/UBSan).
#include "TestErrors.h"

#include <geometry/core/Error.h>
#include <geometry/core/Limits.h>
#include <geometry/scene/GltfLoader.h>

#include <nlohmann/json.hpp>
#include <stb_image_write.h>

#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <random>
#include <span>
#include <string>

namespace {

namespace fs = std::filesystem;
using Json = nlohmann::json;

void sink(void* context, void* data, int size) {
    static_cast<std::string*>(context)->append(static_cast<const char*>(data), std::size_t(size));
}

// A w x h PNG of `channels` channels, every pixel `value` (alpha 0 in the first pixel when it
// has alpha, so that a mask has a hole).
std::string png(int w, int h, int channels, std::uint8_t value) {
    std::vector<std::uint8_t> pixels(std::size_t(w) * h * channels, value);
    if (channels == 4 || channels == 2) pixels[std::size_t(channels) - 1] = 0;
    std::string out;
    EXPECT_TRUE(stbi_write_png_to_func(sink, &out, w, h, channels, pixels.data(), w * channels));
    return out;
}

// A 4 x 2 baseline JPEG of one colour.
std::string jpeg() {
    std::uint8_t pixels[4 * 2 * 3];
    for (int i = 0; i < 8; ++i) {
        pixels[3 * i] = 200, pixels[3 * i + 1] = 100, pixels[3 * i + 2] = 50;
    }
    std::string out;
    EXPECT_TRUE(stbi_write_jpg_to_func(sink, &out, 4, 2, 3, pixels, 90));
    return out;
}

// The PNG with its IHDR's width and height replaced (stb does not check the CRC: the header
// is what a hostile file would send).
std::string pngClaiming(std::uint32_t w, std::uint32_t h) {
    std::string p = png(1, 1, 4, 255);
    const std::uint8_t be[8] = {std::uint8_t(w >> 24), std::uint8_t(w >> 16), std::uint8_t(w >> 8),
                                std::uint8_t(w),       std::uint8_t(h >> 24), std::uint8_t(h >> 16),
                                std::uint8_t(h >> 8),  std::uint8_t(h)};
    std::memcpy(p.data() + 16, be, 8);
    return p;
}

// The start of a baseline JPEG, up to a frame header claiming w x h (no pixel data follows):
// a few dozen bytes that would decode to w * h pixels.
std::string jpegClaiming(std::uint16_t w, std::uint16_t h) {
    const unsigned char head[] = {0xff, 0xd8, 0xff, 0xc0, 0x00, 0x11, 0x08,
                                  std::uint8_t(h >> 8), std::uint8_t(h), std::uint8_t(w >> 8),
                                  std::uint8_t(w), 0x03, 0x01, 0x11, 0x00, 0x02, 0x11, 0x01,
                                  0x03, 0x11, 0x01, 0xff, 0xd9};
    return std::string(reinterpret_cast<const char*>(head), sizeof head);
}

std::string base64(const std::string& bytes) {
    static const char* k = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    for (std::size_t i = 0; i < bytes.size(); i += 3) {
        std::uint32_t v = std::uint8_t(bytes[i]) << 16;
        if (i + 1 < bytes.size()) v |= std::uint8_t(bytes[i + 1]) << 8;
        if (i + 2 < bytes.size()) v |= std::uint8_t(bytes[i + 2]);
        out += k[(v >> 18) & 63];
        out += k[(v >> 12) & 63];
        out += i + 1 < bytes.size() ? k[(v >> 6) & 63] : '=';
        out += i + 2 < bytes.size() ? k[v & 63] : '=';
    }
    return out;
}

void putU32(std::string& s, std::uint32_t v) {
    s.append(reinterpret_cast<const char*>(&v), 4);
}

void pad4(std::string& s, char fill) {
    while (s.size() % 4)
        s += fill;
}

// One alpha-tested triangle ("grate", MASK) whose base colour texture is `images` (each one
// image's bytes, all in the one buffer); `edit` changes the document last.
struct TexturedTriangle {
    Json doc;
    std::string bin;

    explicit TexturedTriangle(const std::vector<std::string>& images) {
        const float xyz[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
        const float uv[6] = {0, 0, 1, 0, 0, 1};
        const std::uint16_t idx[3] = {0, 1, 2};
        bin.append(reinterpret_cast<const char*>(xyz), sizeof xyz);
        bin.append(reinterpret_cast<const char*>(uv), sizeof uv);
        bin.append(reinterpret_cast<const char*>(idx), sizeof idx);
        doc = Json::parse(R"({"asset":{"version":"2.0"},
            "bufferViews":[{"buffer":0,"byteOffset":0,"byteLength":36},
                           {"buffer":0,"byteOffset":36,"byteLength":24},
                           {"buffer":0,"byteOffset":60,"byteLength":6}],
            "accessors":[{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3",
                          "min":[0,0,0],"max":[1,1,0]},
                         {"bufferView":1,"componentType":5126,"count":3,"type":"VEC2"},
                         {"bufferView":2,"componentType":5123,"count":3,"type":"SCALAR"}],
            "meshes":[{"primitives":[{"attributes":{"POSITION":0,"TEXCOORD_0":1},"indices":2,
                                      "material":0}]}],
            "materials":[{"name":"grate","alphaMode":"MASK",
                          "pbrMetallicRoughness":{"baseColorTexture":{"index":0}}}],
            "textures":[{"source":0}],
            "nodes":[{"mesh":0}],"scene":0,"scenes":[{"nodes":[0]}]})");
        doc["images"] = Json::array();
        for (const std::string& image : images) {
            pad4(bin, '\0');
            doc["bufferViews"].push_back(
                {{"buffer", 0}, {"byteOffset", bin.size()}, {"byteLength", image.size()}});
            bin += image;
            const bool isPng = image.size() > 1 && image[1] == 'P';
            doc["images"].push_back({{"bufferView", doc["bufferViews"].size() - 1},
                                     {"mimeType", isPng ? "image/png" : "image/jpeg"}});
        }
        doc["buffers"] = Json::array({{{"byteLength", bin.size()}}});
    }

    // The model as GLB: images in the BIN chunk.
    std::string glb() const {
        std::string json = doc.dump();
        pad4(json, ' ');
        std::string b = bin;
        pad4(b, '\0');
        std::string out = "glTF";
        putU32(out, 2);
        putU32(out, std::uint32_t(12 + 8 + json.size() + 8 + b.size()));
        putU32(out, std::uint32_t(json.size()));
        out += "JSON" + json;
        putU32(out, std::uint32_t(b.size()));
        out += std::string("BIN\0", 4) + b;
        return out;
    }

    // The model as .gltf: the buffer and every image as data: URIs.
    std::string gltf() const {
        Json d = doc;
        d["buffers"][0]["uri"] = "data:application/octet-stream;base64," + base64(bin);
        for (Json& image : d["images"]) {
            const Json& view = d["bufferViews"][image["bufferView"].get<std::size_t>()];
            const std::string bytes = bin.substr(view["byteOffset"].get<std::size_t>(),
                                                 view["byteLength"].get<std::size_t>());
            image = {{"uri", "data:" + image["mimeType"].get<std::string>() + ";base64," +
                                 base64(bytes)}};
        }
        return d.dump();
    }
};

std::span<const unsigned char> bytes(const std::string& s) {
    return {reinterpret_cast<const unsigned char*>(s.data()), s.size()};
}

geometry::GltfContents parse(const std::string& data, const std::string& name) {
    return geometry::parseGltf(bytes(data), {}, name);
}

// parseGltf of `data` must throw an InputError starting "NAME: " and containing every needle.
void expectRefused(const std::string& data, const std::string& name,
                   std::initializer_list<std::string> needles) {
    const auto msg = testutil::errorOf<geometry::InputError>([&] { parse(data, name); });
    ASSERT_TRUE(msg) << "expected an InputError containing \"" << *needles.begin() << "\"";
    EXPECT_EQ(msg->rfind(name + ": ", 0), 0u) << *msg;
    for (const std::string& n : needles)
        EXPECT_NE(msg->find(n), std::string::npos) << "missing \"" << n << "\" in: " << *msg;
}

// Both containers of the model after `edit`: GLB (images in buffer views) and .gltf (data:
// URIs) must be refused with the same needles.
void expectBothRefused(const TexturedTriangle& model, std::initializer_list<std::string> needles) {
    expectRefused(model.glb(), "hostile.glb", needles);
    expectRefused(model.gltf(), "hostile.gltf", needles);
}

TexturedTriangle edited(const std::vector<std::string>& images,
                        const std::function<void(Json&)>& edit) {
    TexturedTriangle m(images);
    edit(m.doc);
    return m;
}

// The model with `edit` applied to its material's pbrMetallicRoughness.
TexturedTriangle pbrEdited(const std::function<void(Json&)>& edit) {
    return edited({png(2, 2, 4, 255)},
                  [&](Json& d) { edit(d["materials"][0]["pbrMetallicRoughness"]); });
}

TEST(TextureHardening, PngAndJpegLoadFromBufferViewsAndDataUris) {
    for (const std::string& image : {png(3, 2, 4, 180), jpeg()}) {
        const TexturedTriangle model({image});
        for (const auto& [data, name] : {std::pair{model.glb(), "t.glb"}, {model.gltf(), "t.gltf"}}) {
            const geometry::MeshData m = parse(data, name).mesh;
            ASSERT_EQ(m.textures.size(), 1u) << name;
            ASSERT_EQ(m.materials.size(), 1u);
            EXPECT_EQ(m.materials[0].baseColorTexture, 0);
            const geometry::TextureImage& t = m.textures[0];
            ASSERT_EQ(t.rgba8.size(), std::size_t(t.width) * t.height * 4);
            if (image[1] == 'P') {
                EXPECT_EQ(t.width, 3);
                EXPECT_EQ(t.height, 2);
                EXPECT_EQ(t.rgba8[3], 0);   // the hole
                EXPECT_EQ(t.rgba8[7], 180); // the rest
                EXPECT_EQ(t.rgba8[4], 180);
            } else {
                EXPECT_EQ(t.width, 4);
                EXPECT_EQ(t.height, 2);
                EXPECT_NEAR(t.rgba8[0], 200, 6); // lossy, within a few levels
                EXPECT_NEAR(t.rgba8[1], 100, 6);
                EXPECT_NEAR(t.rgba8[2], 50, 6);
                EXPECT_EQ(t.rgba8[3], 255);
            }
        }
    }
}

// tinygltf dereferenced an image's buffer view without checking it against its buffer
// (SIGSEGV while decoding images, before any check of ours ran).
TEST(TextureHardening, ImageBufferViewOutsideItsBufferIsRefused) {
    const std::string image = png(2, 2, 4, 255);
    expectRefused(edited({image}, [](Json& d) { d["bufferViews"][3]["byteOffset"] = 1 << 30; })
                      .glb(),
                  "hostile.glb", {"bufferViews[3] covers bytes 1073741824 to", "of buffers[0]"});
    expectRefused(edited({image}, [](Json& d) { d["bufferViews"][3]["byteLength"] = 1 << 30; })
                      .glb(),
                  "hostile.glb", {"bufferViews[3] covers bytes 68 to"});
    expectRefused(edited({image}, [](Json& d) { d["images"][0]["bufferView"] = 9; }).glb(),
                  "hostile.glb", {"images[0].bufferView is 9 but there are 4 entries in bufferViews"});
    expectRefused(edited({image}, [](Json& d) { d["bufferViews"][0]["buffer"] = 1; }).glb(),
                  "hostile.glb", {"bufferViews[0].buffer is 1 but there is 1 entry in buffers"});
}

// A negative byteOffset was read as 0: the triangle read from another place, silently.
TEST(TextureHardening, NegativeOffsetsAreRefused) {
    const std::string image = png(2, 2, 4, 255);
    expectBothRefused(edited({image}, [](Json& d) { d["bufferViews"][1]["byteOffset"] = -12; }),
                      {"bufferViews[1].byteOffset is -12 (must not be negative)"});
    expectBothRefused(edited({image}, [](Json& d) { d["accessors"][0]["byteOffset"] = -4; }),
                      {"accessors[0].byteOffset is -4 (must not be negative)"});
    expectBothRefused(edited({image}, [](Json& d) { d["bufferViews"][1]["byteOffset"] = 1.5; }),
                      {"bufferViews[1].byteOffset is 1.5 (must be an integer"});
}

// Images past GL 4.5's guaranteed texture size, or a JPEG of a few bytes claiming 4 gigapixels
// (an internal GL error, or gigabytes decoded), are refused from the header, naming the limit.
TEST(TextureHardening, ImagesPastTheSideLimitAreRefusedFromTheirHeader) {
    const std::string side = std::to_string(geometry::kMaxTextureSide);
    expectBothRefused(TexturedTriangle({pngClaiming(geometry::kMaxTextureSide + 1, 1)}),
                      {"images[0]: PNG of " + std::to_string(geometry::kMaxTextureSide + 1) +
                           "x1 pixels; textures may be " + side + " pixels on a side at most"});
    const std::string tiny = jpegClaiming(65000, 65000);
    EXPECT_LT(tiny.size(), 32u);
    expectBothRefused(TexturedTriangle({tiny}),
                      {"images[0]: JPEG of 65000x65000 pixels; textures may be " + side});
    // Within the limit the same header decodes: stb fills the missing scan with grey, as
    // lenient JPEG decoders do with truncated files (64 x 64, not gigapixels).
    const geometry::MeshData m = parse(TexturedTriangle({jpegClaiming(64, 64)}).glb(), "t.glb").mesh;
    ASSERT_EQ(m.textures.size(), 1u);
    EXPECT_EQ(m.textures[0].width, 64);
    EXPECT_EQ(m.textures[0].height, 64);
}

// The file's textures together stay within kMaxTexturePixels: four 4096 x 4096 images fill it
// (grey, one byte a pixel while decoding), a fifth of one pixel is refused before decoding.
TEST(TextureHardening, TexturesPastTheFilesPixelBudgetAreRefused) {
    ASSERT_EQ(geometry::kMaxTexturePixels, std::size_t(4) * 4096 * 4096);
    const std::string big = png(4096, 4096, 1, 128);
    const TexturedTriangle model({big, big, big, big, png(1, 1, 1, 0)});
    expectRefused(model.glb(), "budget.glb",
                  {"images[4]: PNG of 1x1 pixels would take the file's textures past 64 Mpixels "
                   "(67108864 pixels so far)"});
    const TexturedTriangle four({big, big, big, big});
    EXPECT_EQ(parse(four.glb(), "four.glb").mesh.textures.size(), 1u); // only the one used
}

TEST(TextureHardening, ImagesThatAreNotPngOrJpegAreRefused) {
    expectBothRefused(TexturedTriangle({std::string("GIF89a\x01\x00\x01\x00", 10)}),
                      {"images[0]: not a PNG or JPEG image"});
    std::string truncated = png(8, 8, 4, 200);
    truncated.resize(40);
    expectBothRefused(TexturedTriangle({truncated}), {"images[0]: PNG of 8x8 could not be decoded"});
}

// Values finite as double but infinite as float were taken (an infinite texture-transform scale
// or colour factor); they are bad input naming the key.
TEST(TextureHardening, ValuesMustBeFiniteInSinglePrecision) {
    const std::string image = png(2, 2, 4, 255);
    expectBothRefused(pbrEdited([](Json& p) {
                          p["baseColorTexture"]["extensions"]["KHR_texture_transform"]["scale"] = {
                              1e39, 1};
                      }),
                      {"materials[0].pbrMetallicRoughness.baseColorTexture.extensions."
                       "KHR_texture_transform.scale[0] is 1e+39 (not finite in single precision)"});
    expectBothRefused(pbrEdited([](Json& p) { p["baseColorFactor"] = {1, 1, 1, 1e39}; }),
                      {"materials[0].pbrMetallicRoughness.baseColorFactor[3] is 1e+39 (not "
                       "finite in single precision)"});
    expectBothRefused(pbrEdited([](Json& p) { p["baseColorFactor"] = {1, 1.5, 1, 1}; }),
                      {"baseColorFactor[1] is 1.5 (must lie in [0, 1])"});
    expectBothRefused(edited({image}, [](Json& d) { d["materials"][0]["alphaCutoff"] = 1e39; }),
                      {"materials[0].alphaCutoff is 1e+39 (not finite in single precision)"});
}

TEST(TextureHardening, AlphaCutoffBelowZeroIsRefused) {
    expectBothRefused(edited({png(2, 2, 4, 255)},
                             [](Json& d) { d["materials"][0]["alphaCutoff"] = -0.5; }),
                      {"materials[0].alphaCutoff is -0.5 (must lie in [0, inf])"});
}

// tinygltf drops the whole pbrMetallicRoughness, its baseColorTexture with it, when one key is
// malformed: the masked triangle loaded opaque. Each such key is bad input.
TEST(TextureHardening, MalformedPbrKeysAreRefusedNotDropped) {
    const std::string image = png(2, 2, 4, 255);
    const auto& pbr = pbrEdited;
    expectBothRefused(pbr([](Json& p) { p["baseColorFactor"] = {1, 1, 1}; }),
                      {"materials[0].pbrMetallicRoughness.baseColorFactor must be an array of 4 "
                       "numbers"});
    expectBothRefused(pbr([](Json& p) { p["metallicFactor"] = "shiny"; }),
                      {"materials[0].pbrMetallicRoughness.metallicFactor is string (must be a "
                       "number)"});
    expectBothRefused(pbr([](Json& p) { p["baseColorTexture"]["index"] = "0"; }),
                      {"materials[0].pbrMetallicRoughness.baseColorTexture.index is string"});
    expectBothRefused(pbr([](Json& p) { p["baseColorTexture"]["index"] = 3; }),
                      {"baseColorTexture.index is 3 but there is 1 entry in textures"});
    expectBothRefused(edited({image},
                             [](Json& d) { d["materials"][0]["pbrMetallicRoughness"] = {1, 2}; }),
                      {"materials[0].pbrMetallicRoughness is array (must be an object)"});
    // The well-formed material keeps its mask.
    const geometry::MeshData m = parse(TexturedTriangle({image}).glb(), "ok.glb").mesh;
    EXPECT_TRUE(m.materials[0].alphaTested());
    EXPECT_EQ(m.materials[0].baseColorTexture, 0);
}

// Required extensions the loader does not read were refused by whatever parse error they
// caused first (a Draco primitive has no buffer views); the refusal now names the extension.
TEST(TextureHardening, RequiredExtensionsAreNamed) {
    const std::string image = png(2, 2, 4, 255);
    const std::pair<const char*, const char*> cases[] = {
        {"KHR_draco_mesh_compression", "Draco-compressed geometry"},
        {"EXT_meshopt_compression", "meshopt-compressed buffers"},
        {"KHR_texture_basisu", "Basis Universal (KTX2) textures"}};
    for (const auto& [name, effect] : cases) {
        const std::string ext = name;
        expectBothRefused(edited({image},
                                 [&](Json& d) {
                                     d["extensionsUsed"] = {ext};
                                     d["extensionsRequired"] = {ext};
                                     // What such files hold that tinygltf stumbles over first.
                                     d["accessors"][0].erase("bufferView");
                                     d["images"][0]["mimeType"] = "image/ktx2";
                                     d["bufferViews"][1].erase("byteLength");
                                 }),
                          {"requires glTF extension " + ext + " (" + effect +
                           "), which penumbra does not read"});
    }
    // Extensions that change only shading still load.
    const TexturedTriangle shading = edited({image}, [](Json& d) {
        d["extensionsRequired"] = {"KHR_materials_unlit", "KHR_texture_transform"};
    });
    EXPECT_EQ(parse(shading.glb(), "unlit.glb").mesh.triangles.size(), 1u);
}

// An opaque material whose image file is missing loads without its texture (it only colours
// the image), and says so; an alpha-tested one is refused (its mask is its shape).
TEST(TextureHardening, MissingImageFileIsAWarningForOpaqueAndAnErrorForMasked) {
    std::random_device rd;
    const fs::path dir = fs::temp_directory_path() / ("penumbra-missing-" + std::to_string(rd()));
    fs::create_directories(dir);
    TexturedTriangle model({png(2, 2, 4, 255)});
    std::ofstream(dir / "tri.bin", std::ios::binary) << model.bin;
    Json d = model.doc;
    d["buffers"][0]["uri"] = "tri.bin";
    d["images"][0] = {{"uri", "gone.png"}};
    std::ofstream(dir / "masked.gltf") << d.dump();
    const auto masked =
        testutil::errorOf<geometry::InputError>([&] { geometry::loadGltf(dir / "masked.gltf"); });
    ASSERT_TRUE(masked);
    EXPECT_NE(masked->find("image 0 (gone.png) could not be read"), std::string::npos) << *masked;
    d["materials"][0]["alphaMode"] = "OPAQUE";
    std::ofstream(dir / "opaque.gltf") << d.dump();
    testing::internal::CaptureStderr();
    const geometry::MeshData m = geometry::loadGltf(dir / "opaque.gltf");
    const std::string err = testing::internal::GetCapturedStderr();
    EXPECT_EQ(m.materials[0].baseColorTexture, -1);
    EXPECT_NE(err.find("warning: " + (dir / "opaque.gltf").string() +
                       ": material \"grate\": base colour texture image 0 (gone.png) could not "
                       "be read (no such file beside the model?); drawn without it"),
              std::string::npos)
        << err;
    fs::remove_all(dir);
}

// glTF URIs are RFC 3986 references: '+' is a plus sign (tinygltf read it as a space, the form
// encoding), "%20" a space; a malformed escape is bad input.
TEST(TextureHardening, PlusInAUriIsAPlus) {
    std::random_device rd;
    const fs::path dir = fs::temp_directory_path() / ("penumbra-uri-" + std::to_string(rd()));
    fs::create_directories(dir);
    const std::string image = png(2, 2, 4, 77);
    TexturedTriangle model({image});
    auto write = [&](const fs::path& p, const std::string& s) {
        std::ofstream(p, std::ios::binary) << s;
    };
    write(dir / "tri+1.bin", model.bin);
    write(dir / "leaf+1.png", image);
    // Decoys where the form decoding would look: the same sizes, another triangle (its second
    // vertex at x = 2), another image.
    std::string decoy = model.bin;
    const float two = 2.0f;
    std::memcpy(decoy.data() + 12, &two, 4);
    write(dir / "tri 1.bin", decoy);
    write(dir / "leaf 1.png", png(5, 5, 4, 1));
    Json d = model.doc;
    d["buffers"][0]["uri"] = "tri+1.bin";
    d["images"][0] = {{"uri", "leaf%2B1.png"}};
    write(dir / "plus.gltf", d.dump());
    const geometry::MeshData m = geometry::loadGltf(dir / "plus.gltf");
    ASSERT_EQ(m.positions.size(), 3u);
    EXPECT_EQ(m.positions[1], glm::vec3(1, 0, 0));
    ASSERT_EQ(m.textures.size(), 1u);
    EXPECT_EQ(m.textures[0].width, 2);
    EXPECT_EQ(m.textures[0].rgba8[7], 77);
    d["images"][0] = {{"uri", "leaf+1.png"}};
    d["buffers"][0]["uri"] = "tri%201.bin"; // the decoy, asked for by its name
    write(dir / "space.gltf", d.dump());
    const geometry::MeshData s = geometry::loadGltf(dir / "space.gltf");
    ASSERT_EQ(s.positions.size(), 3u);
    EXPECT_EQ(s.positions[1], glm::vec3(2, 0, 0));
    EXPECT_EQ(s.textures[0].rgba8[7], 77);
    d["images"][0] = {{"uri", "leaf%2.png"}};
    write(dir / "bad.gltf", d.dump());
    const auto bad =
        testutil::errorOf<geometry::InputError>([&] { geometry::loadGltf(dir / "bad.gltf"); });
    ASSERT_TRUE(bad) << "a malformed escape loaded";
    EXPECT_NE(bad->find("images[0].uri 'leaf%2.png' has a malformed escape"), std::string::npos)
        << *bad;
    fs::remove_all(dir);
}

} // namespace
