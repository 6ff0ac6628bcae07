// Regression tests for the loaders' answers to hostile input, each an exact input found by or
// fed to the fuzzers of fuzz/ (docs/hardening.md, Fuzzing): every one must end in an
// InputError with a message that says what is wrong, quickly, without touching memory it
// should not (the fuzz build runs the same inputs under ASan/UBSan).
#include <geometry/core/Error.h>
#include <geometry/scene/GltfLoader.h>
#include <geometry/scene/Scene.h>

#include <gtest/gtest.h>

#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>
#include <span>
#include <string>

namespace {

namespace fs = std::filesystem;

// fuzz/assets/triangle.gltf (written by scripts/make-fuzz-corpus.py): one triangle, positions
// (36 bytes) then three unsigned short indices, in an embedded base64 buffer of 42 bytes.
const std::string kTriangleGltf =
    R"({"asset":{"version":"2.0"},"bufferViews":[{"buffer":0,"byteOffset":0,"byteLength":36},)"
    R"({"buffer":0,"byteOffset":36,"byteLength":6}],"accessors":[{"bufferView":0,)"
    R"("componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,1,0]},)"
    R"({"bufferView":1,"componentType":5123,"count":3,"type":"SCALAR"}],"meshes":[{"primitives":)"
    R"([{"attributes":{"POSITION":0},"indices":1}]}],"nodes":[{"mesh":0}],"scene":0,"scenes":)"
    R"([{"nodes":[0]}],"buffers":[{"byteLength":42,"uri":"data:application/octet-stream;base64,)"
    R"(AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAAAAABAAIA"}]})";

// The same document with `from` replaced by `to` (once; the text must contain it).
std::string edited(std::string text, const std::string& from, const std::string& to) {
    const std::size_t at = text.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    if (at != std::string::npos) text.replace(at, from.size(), to);
    return text;
}

void putU32(std::string& s, std::uint32_t v) {
    s.append(reinterpret_cast<const char*>(&v), 4);
}

// A GLB of the triangle: its JSON (buffer without uri) and a BIN chunk of the 42 bytes padded to
// 44. `binLength`, when non-zero, overrides the BIN chunk's length field and the buffer's
// byteLength (so that tinygltf would copy all the chunk claims).
std::string triangleGlb(std::uint32_t binLength = 0) {
    std::string json = edited(kTriangleGltf, R"(,"uri":"data:application/octet-stream;base64,)"
                                             R"(AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAAAAABAAIA")",
                              "");
    if (binLength) {
        json = edited(json, R"("byteLength":42)", R"("byteLength":)" + std::to_string(binLength));
    }
    while (json.size() % 4)
        json += ' ';
    std::string bin(36, '\0');
    const float xyz[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    std::memcpy(bin.data(), xyz, 36);
    const std::uint16_t idx[4] = {0, 1, 2, 0};
    bin.append(reinterpret_cast<const char*>(idx), 8);
    std::string out = "glTF";
    putU32(out, 2);
    putU32(out, std::uint32_t(12 + 8 + json.size() + 8 + bin.size()));
    putU32(out, std::uint32_t(json.size()));
    out += "JSON";
    out += json;
    putU32(out, binLength ? binLength : std::uint32_t(bin.size()));
    out += std::string("BIN\0", 4);
    out += bin;
    return out;
}

std::span<const unsigned char> bytes(const std::string& s) {
    return {reinterpret_cast<const unsigned char*>(s.data()), s.size()};
}

// `parse` must throw an InputError whose message starts with "<name>: " and contains every needle.
template <class Parse>
void expectInputError(const Parse& parse, const std::string& name,
                      std::initializer_list<std::string> needles) {
    try {
        parse();
        ADD_FAILURE() << "expected an InputError containing \"" << *needles.begin() << "\"";
    } catch (const geometry::InputError& e) {
        const std::string msg = e.what();
        EXPECT_EQ(msg.rfind(name + ": ", 0), 0u) << msg;
        for (const std::string& n : needles)
            EXPECT_NE(msg.find(n), std::string::npos) << "missing \"" << n << "\" in: " << msg;
    }
}

// parseGltf of `text` with no folder must throw an InputError containing every needle.
void expectGltfError(const std::string& text, std::initializer_list<std::string> needles) {
    expectInputError([&] { geometry::parseGltf(bytes(text), {}, "input.gltf"); }, "input.gltf",
                     needles);
}

void expectSceneError(const std::string& text, std::initializer_list<std::string> needles) {
    expectInputError([&] { geometry::parseScene(text, fs::temp_directory_path(), "input.json"); },
                     "input.json", needles);
}

std::string repeat(const std::string& s, int n) {
    std::string out;
    for (int i = 0; i < n; ++i)
        out += s;
    return out;
}

TEST(LoaderHardening, InMemoryGltfAndGlbLoad) {
    const geometry::GltfContents a = geometry::parseGltf(bytes(kTriangleGltf), {}, "tri.gltf");
    ASSERT_EQ(a.mesh.triangles.size(), 1u);
    EXPECT_EQ(a.mesh.positions.size(), 3u);
    EXPECT_EQ(a.mesh.positions[1], glm::vec3(1, 0, 0));
    EXPECT_EQ(a.mesh.name, "tri");
    const geometry::GltfContents b = geometry::parseGltf(bytes(triangleGlb()), {}, "tri.glb");
    ASSERT_EQ(b.mesh.triangles.size(), 1u);
    EXPECT_EQ(b.mesh.positions[2], glm::vec3(0, 1, 0));
}

// With no folder, no external file is read at all: not even one that would be inside a folder.
TEST(LoaderHardening, InMemoryGltfWithoutFolderRefusesExternalFiles) {
    expectGltfError(edited(kTriangleGltf, "data:application/octet-stream;base64,", "tri.bin?"),
                    {"buffers[0].uri", "no folder to read it from"});
}

// tinygltf's own check lets a BIN chunk whose length forgets its 8-byte header run 8 bytes past
// the end of the data (a heap read overflow when the buffer is copied).
TEST(LoaderHardening, GlbBinChunkRunningPastTheEndIsRefused) {
    const std::string good = triangleGlb();
    const std::uint32_t jsonLength = *reinterpret_cast<const std::uint32_t*>(good.data() + 12);
    const std::uint32_t overrun = std::uint32_t(good.size() - 20 - jsonLength); // + 8 too many
    expectGltfError(triangleGlb(overrun),
                    {"malformed GLB", "claims 52 bytes but 44 follow its header"});
    expectGltfError(triangleGlb(0xFFFFFFFCu), {"malformed GLB", "claims 4294967292 bytes"});
}

TEST(LoaderHardening, GlbHeaderLengthsAreChecked) {
    std::string longer = triangleGlb();
    const std::uint32_t claimed = std::uint32_t(longer.size() + 100);
    std::memcpy(longer.data() + 8, &claimed, 4);
    expectGltfError(longer, {"malformed GLB", "length of", "truncated?"});
    std::string json = triangleGlb();
    const std::uint32_t big = 0x7FFFFFF0u;
    std::memcpy(json.data() + 12, &big, 4);
    expectGltfError(json, {"malformed GLB", "JSON chunk's length 2147483632 runs past the end"});
    expectGltfError(triangleGlb().substr(0, 17), {"malformed GLB", "only 17 bytes"});
    std::string v1 = triangleGlb();
    v1[4] = 1;
    expectGltfError(v1, {"malformed GLB", "version 1"});
}

// tinygltf converts extras by recursion: 20000 levels of arrays exhausted the stack.
TEST(LoaderHardening, DeeplyNestedGltfJsonIsRefused) {
    const std::string deep = R"({"asset":{"version":"2.0"},"extras":)" + repeat("[", 20000) +
                             repeat("]", 20000) + "}";
    expectGltfError(deep, {"nested deeper than 256 levels", "at byte 291"});
    // Brackets inside strings do not count.
    const std::string inString =
        edited(kTriangleGltf, R"("nodes":[{"mesh":0}])",
               R"("nodes":[{"mesh":0,"name":")" + repeat("[", 1000) + R"("}])");
    EXPECT_EQ(geometry::parseGltf(bytes(inString), {}, "in.gltf").mesh.triangles.size(), 1u);
}

TEST(LoaderHardening, DeeplyNestedSceneJsonIsRefused) {
    expectSceneError(R"({"camera": {"eye": )" + repeat("[", 5000) + repeat("]", 5000) + "}}",
                     {"JSON nested deeper than 64 levels (at byte 81)"});
    expectSceneError(repeat(R"({"a":)", 200) + "1" + repeat("}", 200),
                     {"JSON nested deeper than 64 levels"});
}

// A chain of nodes, each listing the next twice, is no cycle but was walked once per path:
// 2^40 visits.
TEST(LoaderHardening, NodeListedTwiceIsRefusedAtOnce) {
    std::string nodes = "[";
    for (int i = 0; i < 39; ++i)
        nodes += R"({"mesh":0,"children":[)" + std::to_string(i + 1) + "," +
                 std::to_string(i + 1) + "]},";
    nodes += R"({"mesh":0}])";
    const auto start = std::chrono::steady_clock::now();
    expectGltfError(edited(kTriangleGltf, R"("nodes":[{"mesh":0}])", R"("nodes":)" + nodes),
                    {"node 39 is reached a second time", "only one parent"});
    EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(5));
    // Two parents of one node.
    expectGltfError(edited(edited(kTriangleGltf, R"("nodes":[{"mesh":0}])",
                                  R"("nodes":[{"children":[2]},{"children":[2]},{"mesh":0}])"),
                           R"("scenes":[{"nodes":[0]}])", R"("scenes":[{"nodes":[0,1]}])"),
                    {"node 2 is reached a second time"});
}

TEST(LoaderHardening, HugeAccessorCountsAreRefusedBeforeAllocating) {
    expectGltfError(edited(kTriangleGltf, R"("count":3,"type":"VEC3")",
                           R"("count":4294967295,"type":"VEC3")"),
                    {"4294967295 vertices bring the file to 4294967295"});
    // Indices: the triangle budget names it before any index is read.
    expectGltfError(edited(kTriangleGltf, R"("count":3,"type":"SCALAR")",
                           R"("count":12582915,"type":"SCALAR")"),
                    {"4194305 triangles bring the file to 4194305, more than the 4194304"});
    // A texture-coordinate accessor with sparse data only: nothing backs its count, which once
    // sized an allocation of count x 2 doubles before the mismatch with POSITION was noticed.
    expectGltfError(
        edited(edited(kTriangleGltf, R"("attributes":{"POSITION":0})",
                      R"("attributes":{"POSITION":0,"TEXCOORD_0":2})"),
               R"({"bufferView":1,"componentType":5123,"count":3,"type":"SCALAR"}])",
               R"({"bufferView":1,"componentType":5123,"count":3,"type":"SCALAR"},)"
               R"({"componentType":5126,"count":12000000,"type":"VEC2","sparse":{"count":1,)"
               R"("indices":{"bufferView":1,"componentType":5123},"values":{"bufferView":0}}}])"),
        {"TEXCOORD_0 has 12000000 elements, POSITION 3"});
}

// A buffer that names a FIFO in the model's folder: opening it would block forever.
TEST(LoaderHardening, FifoUriIsRefused) {
    static std::atomic<int> counter{0};
    const fs::path dir = fs::temp_directory_path() /
                         ("penumbra-hardening-" + std::to_string(::getpid()) + "-" +
                          std::to_string(counter++) + "-" + std::to_string(std::random_device{}()));
    fs::create_directories(dir);
    ASSERT_EQ(::mkfifo((dir / "pipe.bin").c_str(), 0600), 0);
    const std::string text = edited(
        kTriangleGltf,
        "data:application/octet-stream;base64,AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAA"
        "AAABAAIA",
        "pipe.bin");
    std::ofstream(dir / "model.gltf", std::ios::binary) << text;
    for (const fs::path& path : {dir / "model.gltf"}) {
        try {
            geometry::loadGltf(path);
            ADD_FAILURE() << "a FIFO was accepted as a buffer";
        } catch (const geometry::InputError& e) {
            const std::string msg = e.what();
            EXPECT_NE(msg.find("buffers[0].uri 'pipe.bin' is not a regular file"),
                      std::string::npos) << msg;
        }
    }
    try {
        geometry::parseGltf(bytes(text), dir, "memory.gltf");
        ADD_FAILURE() << "a FIFO was accepted as a buffer";
    } catch (const geometry::InputError& e) {
        EXPECT_NE(std::string(e.what()).find("is not a regular file"), std::string::npos)
            << e.what();
    }
    std::error_code ec;
    fs::remove_all(dir, ec);
}

} // namespace
