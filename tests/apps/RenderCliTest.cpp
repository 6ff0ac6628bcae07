// penumbra-render's command-line contract (DESIGN.md §3): bad input exits with code 2, prints a
// clear error naming the key or file, and writes nothing; a good run writes the four outputs.
#include <geometry/scene/GltfLoader.h>
#include <geometry/scene/ImageIO.h>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <sys/wait.h>

#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>

namespace fs = std::filesystem;

namespace {

struct RunResult {
    int exitCode = -1;
    std::string output; // stdout + stderr
};

// Width and height from a PNG's IHDR chunk (bytes 16–23, big endian); 0x0 if it is not a PNG.
std::pair<std::uint32_t, std::uint32_t> pngSize(const fs::path& file) {
    std::ifstream in(file, std::ios::binary);
    unsigned char b[24] = {};
    if (!in.read(reinterpret_cast<char*>(b), sizeof b) || b[1] != 'P' || b[2] != 'N' || b[3] != 'G')
        return {0, 0};
    auto be = [&](int i) {
        return (std::uint32_t(b[i]) << 24) | (std::uint32_t(b[i + 1]) << 16) |
               (std::uint32_t(b[i + 2]) << 8) | std::uint32_t(b[i + 3]);
    };
    return {be(16), be(20)};
}

class RenderCli : public ::testing::Test {
protected:
    void SetUp() override {
        std::random_device rd;
        mDir = fs::temp_directory_path() / ("penumbra-cli-" + std::to_string(rd()));
        fs::create_directories(mDir);
    }
    void TearDown() override { fs::remove_all(mDir); }

    fs::path write(const std::string& name, const std::string& text) {
        const fs::path p = mDir / name;
        std::ofstream(p, std::ios::binary) << text;
        return p;
    }

    RunResult run(const std::string& args) {
        const fs::path log = mDir / "log.txt";
        const std::string cmd = std::string(PENUMBRA_BIN_DIR) + "/penumbra-render " + args +
                                " > '" + log.string() + "' 2>&1";
        const int status = std::system(cmd.c_str());
        RunResult r;
        r.exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
        std::ifstream in(log);
        std::stringstream ss;
        ss << in.rdbuf();
        r.output = ss.str();
        return r;
    }

    // Runs with a scene that must be rejected: exit 2, message mentions `needle`, no output dir.
    void expectRejected(const fs::path& scene, const std::string& needle,
                        const std::string& extra = "--method hard") {
        const fs::path out = mDir / "out";
        const RunResult r =
            run("--scene '" + scene.string() + "' " + extra + " --out '" + out.string() + "'");
        EXPECT_EQ(r.exitCode, 2) << r.output;
        EXPECT_NE(r.output.find(needle), std::string::npos)
            << "expected '" << needle << "' in: " << r.output;
        EXPECT_FALSE(fs::exists(out)) << "nothing may be written on bad input";
    }

    fs::path mDir;
};

const char* kValidScene = R"({
  "camera": {"eye": [0, 4, 4], "target": [0, 0, 0], "up": [0, 1, 0], "fov_y_deg": 50},
  "light":  {"center": [0, 3, 0], "u": [0.5, 0, 0], "v": [0, 0, 0.5]},
  "objects": [
    {"type": "quad", "center": [0, 0, 0], "u": [2, 0, 0], "v": [0, 0, -2]},
    {"type": "box", "center": [0, 1, 0], "size": [0.6, 0.2, 0.6]}
  ]
})";

std::string replaced(std::string s, const std::string& from, const std::string& to) {
    const auto pos = s.find(from);
    if (pos != std::string::npos) s.replace(pos, from.size(), to);
    return s;
}

TEST_F(RenderCli, BadJsonSyntax) {
    expectRejected(write("s.json", "{\"camera\": [1, 2,"), "s.json");
}

TEST_F(RenderCli, UnknownKey) {
    expectRejected(write("s.json", replaced(kValidScene, "\"fov_y_deg\"", "\"fov\"")), "fov");
}

TEST_F(RenderCli, WrongType) {
    expectRejected(write("s.json", replaced(kValidScene, "[0, 3, 0]", "\"up there\"")),
                   "light.center");
}

TEST_F(RenderCli, MissingSceneFile) { expectRejected(mDir / "nope.json", "nope.json"); }

TEST_F(RenderCli, MissingGltfFile) {
    expectRejected(write("s.json", replaced(kValidScene, "{\"type\": \"quad\"",
                                            "{\"type\": \"gltf\", \"file\": \"missing.glb\"}, "
                                            "{\"type\": \"quad\"")),
                   "missing.glb");
}

TEST_F(RenderCli, ZeroAreaLight) {
    expectRejected(write("s.json", replaced(kValidScene, "\"v\": [0, 0, 0.5]", "\"v\": [0, 0, 0]")),
                   "light");
}

TEST_F(RenderCli, LightIntersectingGeometry) {
    // The light plane y = 1 cuts through the box (y 0.9 .. 1.1).
    expectRejected(write("s.json", replaced(kValidScene, "\"center\": [0, 3, 0]",
                                            "\"center\": [0.1, 1, 0]")),
                   "light intersects object");
}

TEST_F(RenderCli, DegenerateAndNonManifoldMeshesRenderWithoutError) {
    // A zero-area triangle and three triangles sharing one edge: legal input, rendered.
    const std::string b64 = "AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAAAAAAAAAAAAAAAIA/"
                            "AAAAAAAAgL8AAAAAAAAAQAAAAAAAAAAA";
    // positions: (0,0,0) (1,0,0) (0,1,0) (0,0,1) (0,-1,0) (2,0,0)
    // triangles: 0 1 2 | 0 1 3 | 0 1 4 (fan on edge 0-1) | 0 1 5 (zero area: collinear)
    const std::string idx = "AAABAAIAAAABAAMAAAABAAQAAAABAAUA";
    const std::string gltf = R"({"asset": {"version": "2.0"}, "scene": 0,
      "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0, "translation": [0, 1, 0]}],
      "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]}],
      "buffers": [{"byteLength": 72, "uri": "data:application/octet-stream;base64,)" + b64 + R"("},
                  {"byteLength": 24, "uri": "data:application/octet-stream;base64,)" + idx + R"("}],
      "bufferViews": [{"buffer": 0, "byteLength": 72}, {"buffer": 1, "byteLength": 24}],
      "accessors": [{"bufferView": 0, "componentType": 5126, "count": 6, "type": "VEC3",
                     "min": [0, -1, 0], "max": [2, 1, 1]},
                    {"bufferView": 1, "componentType": 5123, "count": 12, "type": "SCALAR"}]})";
    write("fan.gltf", gltf);
    const fs::path scene = write("s.json", replaced(kValidScene, "{\"type\": \"quad\"",
                                                    "{\"type\": \"gltf\", \"file\": \"fan.gltf\"}, "
                                                    "{\"type\": \"quad\""));
    const fs::path out = mDir / "out";
    const RunResult r = run("--scene '" + scene.string() + "' --method hard --size 64x64 --out '" +
                            out.string() + "'");
    EXPECT_EQ(r.exitCode, 0) << r.output;
    EXPECT_TRUE(fs::exists(out / "visibility.pfm"));
}

TEST_F(RenderCli, GltfWithNoMeshes) {
    expectRejected(write("empty.gltf", R"({"asset": {"version": "2.0"}, "scenes": [{"nodes": []}]})"),
                   "empty.gltf");
}

TEST_F(RenderCli, GltfWithNanPosition) {
    // One triangle whose first x is NaN (0x7FC00000), as an embedded base64 buffer.
    // Bytes: 9 floats = 36 bytes: NaN,0,0, 1,0,0, 0,1,0.
    const std::string b64 = "AADAfwAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAA";
    const std::string gltf = R"({"asset": {"version": "2.0"}, "scene": 0,
      "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
      "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],
      "buffers": [{"byteLength": 36, "uri": "data:application/octet-stream;base64,)" + b64 + R"("}],
      "bufferViews": [{"buffer": 0, "byteLength": 36}],
      "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                     "min": [0, 0, 0], "max": [1, 1, 0]}]})";
    expectRejected(write("nan.gltf", gltf), "nan.gltf");
}

TEST_F(RenderCli, UnknownMethod) {
    expectRejected(write("s.json", kValidScene), "unknown method", "--method softest");
}

// pcss, the last method of the contract to be built: its parameters and counters in
// report.json, and --help lists it with them.
TEST_F(RenderCli, PcssRendersWithItsParameters) {
    expectRejected(write("s.json", kValidScene), "512, 1024, 2048",
                   "--method pcss --param resolution=4096");
    const fs::path out = mDir / "out";
    const RunResult r = run("--scene '" + write("s.json", kValidScene).string() +
                            "' --method pcss --param resolution=512 --param bias=3.0 --size 48x32 "
                            "--out '" + out.string() + "'");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    std::ifstream in(out / "report.json");
    const auto report = nlohmann::json::parse(in);
    EXPECT_EQ(report["parameters"]["resolution"], 512);
    EXPECT_EQ(report["parameters"]["blocker_samples"], 16);
    EXPECT_EQ(report["parameters"]["pcf_samples"], 32);
    EXPECT_EQ(report["parameters"]["bias"], "3.0");
    EXPECT_EQ(report["parameters"]["horizon"], "on");
    EXPECT_EQ(report["counters"]["pcss_resolution"], 512);
    EXPECT_EQ(report["counters"]["pcss_sides"], 1);
    EXPECT_EQ(report["counters"]["pcss_pixels_outside"], 0);
    EXPECT_TRUE(report["gpu_ms"].contains("pcss-lookup"));
    const RunResult help = run("--help");
    EXPECT_EQ(help.output.find("not implemented"), std::string::npos) << help.output;
    for (const char* line : {"--param resolution=512|1024|2048 (default 1024)",
                             "--param blocker_samples=16|32|64 (default 16)",
                             "--param pcf_samples=16|32|64 (default 32)"})
        EXPECT_NE(help.output.find(line), std::string::npos) << line << " in:\n" << help.output;
    EXPECT_LT(help.output.find("pcss:"), help.output.find("--param blocker_samples="));
}

// Alpha-tested casters with a method that would shadow with whole cards: not refused. The
// oak (every triangle a leaf-card material) goes to auto's alpha path whole (sample maps: it
// lies in front of the light); the textured level is split on loading, its walls to the method
// asked for, its grate and flames to the alpha path (pcss: they surround the lamp);
// report.json and the output say so per object.
TEST_F(RenderCli, AlphaTestedObjectsWithAWedgeMethodTakeTheAlphaPath) {
    const fs::path shared(PENUMBRA_SHARED_DIR);
    struct Case {
        fs::path scene;
        std::size_t opaque, tested;
        std::string alphaPath;
    };
    for (const Case& c : {Case{shared / "foliage" / "oak_hungarian_1.glb", 0, 1, "sample-maps"},
                          Case{shared / "levels" / "textured" / "kaos2.glb", 1, 1, "pcss"}}) {
        const fs::path out = mDir / "out";
        const RunResult r = run("--scene '" + c.scene.string() +
                                "' --method wedges-additive --size 48x48 --out '" + out.string() +
                                "'");
        ASSERT_EQ(r.exitCode, 0) << r.output;
        std::ifstream in(out / "report.json");
        const auto report = nlohmann::json::parse(in);
        std::size_t opaque = 0, tested = 0;
        for (const auto& object : report["objects"]) {
            ASSERT_TRUE(object.contains("shadow_path")) << object.dump();
            const std::string reason = object["shadow_path_reason"];
            if (object["shadow_path"] == c.alphaPath) { // auto's alpha path
                ++tested;
                EXPECT_NE(reason.find("alpha-tested materials: "), std::string::npos) << reason;
            } else {
                ++opaque;
                EXPECT_EQ(object["shadow_path"], "wedges-additive") << object.dump();
            }
        }
        EXPECT_EQ(opaque, c.opaque) << report["objects"].dump();
        EXPECT_EQ(tested, c.tested) << report["objects"].dump();
        EXPECT_NE(r.output.find(c.alphaPath + " (wedges-additive occludes with whole triangles"),
                  std::string::npos)
            << r.output; // said, not only written
    }
}

// sample-maps on a level around the lamp: the level reaches the light's plane, so its maps miss
// part of it. Said on stderr and in report.json's warnings, not only counted; the oak, which
// the maps hold, gets no warning.
TEST_F(RenderCli, SampleMapsSayWhenTheyClipTheCasters) {
    const fs::path shared(PENUMBRA_SHARED_DIR);
    struct Case {
        fs::path scene;
        bool clipped;
    };
    for (const Case& c : {Case{shared / "levels" / "oa_dm4.glb", true},
                          Case{shared / "foliage" / "oak_hungarian_1.glb", false}}) {
        SCOPED_TRACE(c.scene.string());
        const fs::path out = mDir / "out";
        const RunResult r = run("--scene '" + c.scene.string() +
                                "' --method sample-maps --size 32x32 --out '" + out.string() + "'");
        ASSERT_EQ(r.exitCode, 0) << r.output;
        std::ifstream in(out / "report.json");
        const auto report = nlohmann::json::parse(in);
        EXPECT_EQ(report["counters"]["sample_maps_clipped"], c.clipped ? 1.0 : 0.0);
        EXPECT_EQ(report["warnings"].size(), c.clipped ? 1u : 0u) << report["warnings"].dump();
        EXPECT_EQ(r.output.find("warning: sample-maps: casters reach the light's plane") !=
                      std::string::npos,
                  c.clipped)
            << r.output;
    }
}

TEST_F(RenderCli, FoliageRendersWithOcclusion) {
    const fs::path tree = fs::path(PENUMBRA_SHARED_DIR) / "foliage" / "oak_hungarian_1.glb";
    const fs::path out = mDir / "out";
    const RunResult r = run("--scene '" + tree.string() +
                            "' --method occlusion --param slices=16 --size 64x64 --out '" +
                            out.string() + "'");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    std::ifstream in(out / "report.json");
    const auto report = nlohmann::json::parse(in);
    EXPECT_EQ(report["parameters"]["slices"], 16);
    // A .glb without cameras: the automatic framing.
    EXPECT_EQ(report["camera_source"], "framed");
    EXPECT_EQ(report["cameras"], 0);
    EXPECT_NE(r.output.find("camera: framed"), std::string::npos) << r.output;
    EXPECT_EQ(report["parameters"]["prefilter"], "nbuffers");
    EXPECT_EQ(report["parameters"]["leakfix"], "auto");
    EXPECT_EQ(report["parameters"]["resolution"], 512);
    EXPECT_EQ(report["counters"]["occlusion_slices"], 16);
    EXPECT_EQ(report["counters"]["occlusion_casters_leakfix"], 1); // alpha-tested: a thin sheet
    EXPECT_GT(report["counters"]["occlusion_z_far"].get<double>(),
              report["counters"]["occlusion_z_near"].get<double>());
}

TEST_F(RenderCli, BadSize) {
    expectRejected(write("s.json", kValidScene), "--size", "--method hard --size 0x64");
    expectRejected(write("s.json", kValidScene), "--size", "--method hard --size big");
}

// --size and --samples have the limits every app shares (apps/Flags.h): each side 1 to 16384,
// 1 to 65536 light samples (penumbra-render took 2^20 before). Out of range is bad input, exit 2.
TEST_F(RenderCli, SizeAndSamplesHaveTheSharedLimits) {
    const fs::path scene = write("s.json", kValidScene);
    expectRejected(scene, "penumbra-render: error: --size: each side must be between 1 and 16384, "
                          "got '16385x64'",
                   "--method hard --size 16385x64");
    expectRejected(scene, "penumbra-render: error: --samples must be between 1 and 65536",
                   "--method reference --samples 65537");
    expectRejected(scene, "--samples must be between 1 and 65536",
                   "--method reference --samples 1048576");
    expectRejected(scene, "--samples must be between 1 and 65536", "--method hard --samples 0");
}

// --warmup N renders N frames first and leaves them out of every time: frame_ms_each holds the
// --frames counted ones, in order; frame_ms is their median. A method that precomputes (pdsm's
// deep map) does it in the first warm-up frame and keeps its counters. Out of range: exit 2.
TEST_F(RenderCli, WarmupFramesAreLeftOutOfTheTimes) {
    const fs::path scene = write("s.json", kValidScene);
    expectRejected(scene, "penumbra-render: error: --warmup must be between 0 and 10000",
                   "--method hard --warmup -1");
    expectRejected(scene, "--warmup must be between 0 and 10000", "--method hard --warmup 10001");
    const fs::path out = mDir / "out";
    const RunResult r = run("--scene '" + scene.string() + "' --method pdsm --param samples=16 " +
                            "--param resolution=128 --size 48x32 --warmup 2 --frames 3 --quiet " +
                            "--out '" + out.string() + "'");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    nlohmann::json report;
    std::ifstream(out / "report.json") >> report;
    EXPECT_EQ(report["parameters"]["frames"], 3);
    EXPECT_EQ(report["parameters"]["warmup"], 2);
    ASSERT_EQ(report["frame_ms_each"].size(), 3u);
    std::vector<double> each = report["frame_ms_each"];
    std::sort(each.begin(), each.end());
    EXPECT_DOUBLE_EQ(report["frame_ms"].get<double>(), each[1]);
    // Built in the first warm-up frame, reused in every counted one: a counted frame that built
    // it would take at least the precompute (about 20 ms here, 55 ms under ASan, against
    // 0.4 and 1.5-4.6 ms a frame after it).
    EXPECT_EQ(report["counters"]["pdsm_cached"], 1.0);
    const double precompute = report["counters"]["pdsm_precompute_ms"];
    EXPECT_GT(precompute, 0.0);
    for (double ms : each) {
        EXPECT_GT(ms, 0.0);
        EXPECT_LT(ms, precompute);
    }
}

// --simplify E (apps/Flags.h): 0 is off, (0, 0.25] replaces what can be simplified and says
// so on stdout and in report.json; anything else is bad input, exit 2.
TEST_F(RenderCli, SimplifyReportsWhatItDidAndRefusesBadValues) {
    const fs::path scene = write("s.json", replaced(kValidScene,
        R"({"type": "box", "center": [0, 1, 0], "size": [0.6, 0.2, 0.6]})",
        R"({"type": "sphere", "center": [0, 1, 0], "radius": 0.3, "segments": 96})"));
    for (const char* bad : {"-0.1", "0.3", "nan", "inf", "lots"})
        expectRejected(scene, "--simplify", std::string("--method hard --simplify ") + bad);
    const fs::path out = mDir / "out";
    RunResult r = run("--scene '" + scene.string() + "' --method hard --size 32x32 --simplify 0.1 " +
                      "--out '" + out.string() + "'");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_NE(r.output.find("simplify: visibility error about 0.1: 2 meshes"), std::string::npos)
        << r.output;
    nlohmann::json report;
    std::ifstream(out / "report.json") >> report;
    EXPECT_FLOAT_EQ(report["simplify"]["visibility_error"].get<float>(), 0.1f);
    EXPECT_EQ(report["simplify"]["meshes"], 2);
    const std::size_t before = report["simplify"]["triangles_before"];
    const std::size_t after = report["simplify"]["triangles_after"];
    EXPECT_EQ(before, 2u + 96u * 48u * 2u - 2u * 96u); // the quad and the 96-segment sphere
    EXPECT_LT(after, before);
    EXPECT_EQ(report["triangles"], after);
    // Off by default: nothing simplified, and nothing said.
    r = run("--scene '" + scene.string() + "' --method hard --size 32x32 --out '" + out.string() +
            "'");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_EQ(r.output.find("simplify:"), std::string::npos) << r.output;
    std::ifstream(out / "report.json") >> report;
    EXPECT_EQ(report["simplify"]["meshes"], 0);
    EXPECT_EQ(report["triangles"], before);
}

// Sizes no GL implementation here can hold are refused with the limit, before anything is
// allocated: 16384x16384 once failed after 5 GB with an incomplete framebuffer, 100000x100000
// was blamed on its format.
TEST_F(RenderCli, HugeSizesAreRefusedWithTheLimit) {
    const fs::path scene = write("s.json", kValidScene);
    expectRejected(scene, "penumbra-render: error: --size: each side must be between 1 and 16384, "
                          "got '100000x100000'",
                   "--method hard --size 100000x100000");
    expectRejected(scene, "--size: each side must be between 1 and 16384",
                   "--method hard --size 99999999999x4");
    // 4 GiB per RGBA32F target: over llvmpipe's largest texture (its proxy query says so; the
    // tests run on llvmpipe), and 16 GB of targets in all; either message gives the largest
    // square that fits.
    expectRejected(scene, "penumbra-render: error: image size 16384x16384",
                   "--method hard --size 16384x16384");
    expectRejected(scene, "the largest square size", "--method hard --size 16384x16384");
}

// --out naming a file (or a path through a file) is bad input found before the scene is loaded
// or GL is set up (it was an internal error after the rendering).
TEST_F(RenderCli, OutputThatIsAFileIsBadInput) {
    const fs::path scene = write("s.json", kValidScene);
    const fs::path file = write("taken", "a file");
    RunResult r =
        run("--scene '" + scene.string() + "' --method hard --out '" + file.string() + "'");
    EXPECT_EQ(r.exitCode, 2) << r.output;
    EXPECT_NE(r.output.find("penumbra-render: error: --out: '" + file.string() +
                            "' exists and is not a folder"),
              std::string::npos)
        << r.output;
    r = run("--scene '" + (mDir / "missing.json").string() + "' --method hard --out '" +
            (file / "sub").string() + "'");
    EXPECT_EQ(r.exitCode, 2) << r.output;
    EXPECT_NE(r.output.find("cannot be created: '" + file.string() + "' is not a folder"),
              std::string::npos)
        << "checked before the scene: " << r.output;
    std::ifstream in(file);
    std::string text;
    std::getline(in, text);
    EXPECT_EQ(text, "a file");
}

// --out through a symbolic link to nothing (itself, or a folder on the way) is found before
// the work: it was an internal error from creating the folder after the rendering.
TEST_F(RenderCli, OutputThroughADanglingLinkIsBadInput) {
    const fs::path scene = write("s.json", kValidScene);
    const fs::path link = mDir / "dangling";
    fs::create_symlink(mDir / "nowhere", link);
    for (const fs::path& out : {link, link / "sub"}) {
        const RunResult r =
            run("--scene '" + scene.string() + "' --method hard --out '" + out.string() + "'");
        EXPECT_EQ(r.exitCode, 2) << r.output;
        EXPECT_NE(r.output.find("penumbra-render: error: --out: '" + out.string() +
                                "' cannot be created: '" + link.string() +
                                "' is a symbolic link to '" + (mDir / "nowhere").string() +
                                "', which does not exist"),
                  std::string::npos)
            << r.output;
        EXPECT_EQ(r.output.find("internal error"), std::string::npos) << r.output;
    }
    EXPECT_FALSE(fs::exists(mDir / "nowhere"));
}

// --compare given a device (read forever before) or a file far larger than its header says
// (read whole before: 3 GB, 33 s) is refused before the scene is loaded, nothing written.
TEST_F(RenderCli, CompareWithADeviceOrAnOversizedFileIsBadInput) {
    const fs::path scene = write("s.json", kValidScene);
    const fs::path out = mDir / "out";
    RunResult r = run("--scene '" + scene.string() + "' --method hard --size 64x64 --out '" +
                      out.string() + "' --compare /dev/zero");
    EXPECT_EQ(r.exitCode, 2) << r.output;
    EXPECT_NE(r.output.find("error: --compare: /dev/zero: not a regular file"), std::string::npos)
        << r.output;
    // A sparse file: 64x64 in its header, 1 GiB on the file system's word, no disk used.
    const fs::path big = write("big.pfm", "Pf\n64 64\n-1.0\n");
    fs::resize_file(big, std::uintmax_t(1) << 30);
    r = run("--scene '" + (mDir / "missing.json").string() + "' --method hard --size 64x64 " +
            "--out '" + out.string() + "' --compare '" + big.string() + "'");
    EXPECT_EQ(r.exitCode, 2) << r.output;
    EXPECT_NE(r.output.find("--compare: " + big.string() + ": malformed PFM: " +
                            std::to_string((std::uintmax_t(1) << 30) - 14 - 64 * 64 * 4) +
                            " unexpected bytes after the data"),
              std::string::npos)
        << "checked from the header, before the scene: " << r.output;
    EXPECT_FALSE(fs::exists(out));
}

// Command-line errors read like every other error, and say what is wrong.
TEST_F(RenderCli, FlagErrorsCarryThePrefixAndTheRange) {
    const fs::path scene = write("s.json", kValidScene);
    expectRejected(scene, "penumbra-render: error: --seed must be between 0 and 4294967295, got -1",
                   "--method hard --seed -1");
    expectRejected(scene, "got 4294967296", "--method hard --seed 4294967296");
    const fs::path out = mDir / "out";
    const RunResult r = run("--scene '" + scene.string() + "' --method hard --bogus --out '" +
                            out.string() + "'");
    EXPECT_EQ(r.exitCode, 2);
    EXPECT_EQ(r.output.rfind("penumbra-render: error: ", 0), 0u) << r.output;
    EXPECT_NE(r.output.find("--bogus"), std::string::npos) << r.output;
}

// A vertex at 1e19 once aborted the process inside Embree (the framing's rays): bad input now.
TEST_F(RenderCli, HugeCoordinateIsBadInputNotACrash) {
    // positions (0,0,0) (1,0,0) (0,1,1e19), indices 0 1 2 (uint16).
    const float pos[9] = {0, 0, 0, 1, 0, 0, 0, 1, 1e19f};
    const std::uint16_t idx[4] = {0, 1, 2, 0};
    std::ofstream(mDir / "huge.bin", std::ios::binary)
        .write(reinterpret_cast<const char*>(pos), sizeof pos)
        .write(reinterpret_cast<const char*>(idx), sizeof idx);
    const fs::path gltf = write("huge.gltf", R"({"asset": {"version": "2.0"}, "scene": 0,
        "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]}],
        "buffers": [{"byteLength": 44, "uri": "huge.bin"}],
        "bufferViews": [{"buffer": 0, "byteLength": 36},
                        {"buffer": 0, "byteOffset": 36, "byteLength": 6}],
        "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3"},
                      {"bufferView": 1, "componentType": 5123, "count": 3, "type": "SCALAR"}]})");
    expectRejected(gltf, "POSITION (accessor 0) vertex 2 has z = 1e+19, outside [-1e+07, 1e+07]");
}

// Method parameters (--param NAME=VALUE, declared in gpu/Methods.h): every mistake is bad input
// that names what is allowed.
TEST_F(RenderCli, UnknownParameterNamesTheMethodsParameters) {
    expectRejected(write("s.json", kValidScene), "unknown parameter 'corners'",
                   "--method wedges-blend --param corners=4");
    expectRejected(write("s.json", kValidScene), "parts, bits, overlap",
                   "--method wedges-blend --param corners=4");
}

TEST_F(RenderCli, ParameterValueNotAllowedNamesTheAllowedOnes) {
    expectRejected(write("s.json", kValidScene), "allowed: 1, 4, 8",
                   "--method wedges-blend --param parts=3");
    expectRejected(write("s.json", kValidScene), "allowed: 8, 16",
                   "--method wedges-blend --param bits=32");
    expectRejected(write("s.json", kValidScene), "allowed: paper, centroid",
                   "--method wedges-blend --param overlap=Paper");
}

TEST_F(RenderCli, ParameterOfAMethodWithoutParameters) {
    expectRejected(write("s.json", kValidScene), "method 'hard' has no parameters",
                   "--method hard --param parts=4");
}

TEST_F(RenderCli, MalformedOrRepeatedParameter) {
    expectRejected(write("s.json", kValidScene), "NAME=VALUE",
                   "--method wedges-blend --param parts");
    expectRejected(write("s.json", kValidScene), "NAME=VALUE",
                   "--method wedges-blend --param =8");
    expectRejected(write("s.json", kValidScene), "given twice",
                   "--method wedges-blend --param parts=8 --param parts=1");
}

TEST_F(RenderCli, HelpListsEachMethodsParameters) {
    const RunResult r = run("--help");
    EXPECT_EQ(r.exitCode, 0) << r.output;
    for (const char* line : {"--param parts=1|4|8 (default 4)", "--param bits=8|16 (default 8)",
                             "--param overlap=paper|centroid (default paper)"})
        EXPECT_NE(r.output.find(line), std::string::npos) << line << " in:\n" << r.output;
    // Listed under their method, before the next one.
    EXPECT_LT(r.output.find("wedges-blend:"), r.output.find("--param parts="));
    EXPECT_LT(r.output.find("--param overlap="), r.output.find("wedges-multiply:"));
}

// report.json's "parameters": samples, seed and frames as before, and every parameter of the
// method with the value used (given or default).
TEST_F(RenderCli, ReportListsEveryParameterOfTheMethod) {
    const fs::path scene = write("s.json", kValidScene);
    auto parameters = [&](const std::string& args) {
        const fs::path out = mDir / "out";
        fs::remove_all(out);
        const RunResult r = run("--scene '" + scene.string() + "' --size 48x32 --quiet " + args +
                                " --out '" + out.string() + "'");
        EXPECT_EQ(r.exitCode, 0) << r.output;
        nlohmann::json report;
        std::ifstream(out / "report.json") >> report;
        return report["parameters"];
    };
    EXPECT_EQ(parameters("--method hard --seed 3"),
              (nlohmann::json{{"samples", 1}, {"seed", 3}, {"frames", 1}, {"warmup", 0}}));
    EXPECT_EQ(parameters("--method wedges-blend"),
              (nlohmann::json{{"samples", 1}, {"seed", 1}, {"frames", 1}, {"warmup", 0},
                              {"parts", 4}, {"bits", 8}, {"overlap", "paper"}}));
    EXPECT_EQ(parameters("--method wedges-blend --param overlap=centroid --param parts=8"),
              (nlohmann::json{{"samples", 1}, {"seed", 1}, {"frames", 1}, {"warmup", 0},
                              {"parts", 8}, {"bits", 8}, {"overlap", "centroid"}}));
}

TEST_F(RenderCli, GoodRunWritesTheContractOutputs) {
    const fs::path scene = write("s.json", kValidScene);
    const fs::path out = mDir / "out";
    const RunResult r = run("--scene '" + scene.string() + "' --method reference --samples 16 " +
                            "--size 64x48 --frames 2 --out '" + out.string() + "'");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    for (const char* f : {"image.png", "visibility.pfm", "position.pfm", "report.json"})
        EXPECT_TRUE(fs::exists(out / f)) << f;

    const auto v = geometry::readPfm(out / "visibility.pfm");
    EXPECT_EQ(v.width, 64);
    EXPECT_EQ(v.height, 48);
    EXPECT_EQ(v.channels, 1);
    const auto p = geometry::readPfm(out / "position.pfm");
    EXPECT_EQ(p.channels, 3);
    int surface = 0, shadowed = 0;
    for (float x : v.data) {
        surface += std::isfinite(x);
        shadowed += std::isfinite(x) && x < 0.5f;
    }
    EXPECT_GT(surface, 1000);
    EXPECT_GT(shadowed, 20);

    nlohmann::json report;
    std::ifstream(out / "report.json") >> report;
    for (const char* key : {"method", "parameters", "size", "gl_renderer", "gl_version",
                            "triangles", "silhouette_edges", "silhouette_groups", "wedges",
                            "gpu_ms", "cpu_ms", "frame_ms", "objects", "camera", "light"})
        EXPECT_TRUE(report.contains(key)) << key;
    EXPECT_EQ(report["method"], "reference");
    EXPECT_EQ(report["camera_source"], "scene");
    EXPECT_EQ(report["cameras"], 0);
    EXPECT_EQ(report["size"], nlohmann::json::array({64, 48}));
    EXPECT_EQ(report["triangles"], 14);
    EXPECT_FALSE(report["gl_renderer"].get<std::string>().empty());
    EXPECT_TRUE(report["gpu_ms"].contains("shadow-volume"));
    EXPECT_GT(report["frame_ms"].get<double>(), 0.0);
    // The quad is open (4 boundary edges), the box closed.
    ASSERT_EQ(report["objects"].size(), 2u);
    EXPECT_EQ(report["objects"][0]["topology"], "open");
    EXPECT_EQ(report["objects"][0]["boundary_edges"], 4);
    EXPECT_EQ(report["objects"][1]["topology"], "closed");
}

TEST_F(RenderCli, CompareReportsErrorAgainstAReference) {
    const fs::path scene = write("s.json", kValidScene);
    const fs::path ref = mDir / "ref", hard = mDir / "hard";
    ASSERT_EQ(run("--scene '" + scene.string() + "' --method reference --samples 16 --size 64x64 "
                  "--quiet --out '" + ref.string() + "'").exitCode, 0);
    const RunResult r = run("--scene '" + scene.string() + "' --method hard --size 64x64 --out '" +
                            hard.string() + "' --compare '" + (ref / "visibility.pfm").string() +
                            "'");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    nlohmann::json report;
    std::ifstream(hard / "report.json") >> report;
    ASSERT_TRUE(report.contains("error"));
    // Hard shadows are not soft: a real penumbra means a non-zero error.
    EXPECT_GT(report["error"]["mean_abs_err"].get<double>(), 0.001);
    EXPECT_GT(report["error"]["pixels"].get<int>(), 1000);
    // The heat map: the view plus its legend, named in the report with its scale.
    EXPECT_EQ(report["error_image"]["file"], "error.png");
    EXPECT_FLOAT_EQ(report["error_image"]["scale_max"].get<float>(), 0.2f);
    const auto [w, h] = pngSize(hard / "error.png");
    EXPECT_EQ(w, 64u);
    EXPECT_GT(h, 64u);
    EXPECT_TRUE(r.output.find("error.png") != std::string::npos) << r.output;
    // A size mismatch with the reference is bad input.
    const RunResult bad = run("--scene '" + scene.string() + "' --method hard --size 32x32 --out '" +
                              (mDir / "x").string() + "' --compare '" +
                              (ref / "visibility.pfm").string() + "'");
    EXPECT_EQ(bad.exitCode, 2) << bad.output;
    EXPECT_FALSE(fs::exists(mDir / "x"));
    const RunResult badScale = run("--scene '" + scene.string() + "' --method hard --size 64x64 " +
                                   "--error-scale 0 --out '" + (mDir / "y").string() +
                                   "' --compare '" + (ref / "visibility.pfm").string() + "'");
    EXPECT_EQ(badScale.exitCode, 2) << badScale.output;
    EXPECT_NE(badScale.output.find("--error-scale"), std::string::npos) << badScale.output;
    EXPECT_FALSE(fs::exists(mDir / "y"));
}

// A level given directly opens at its first glTF camera (a spawn point); --camera N picks
// another; a camera that is not there is bad input.
TEST_F(RenderCli, LevelOpensAtItsGltfCameras) {
    const fs::path level = fs::path(PENUMBRA_SHARED_DIR) / "levels" / "oa_dm4.glb";
    ASSERT_TRUE(fs::exists(level)) << level << " missing (the shared levels are part of the suite)";
    const auto cameras = geometry::loadGltfCameras(level);
    ASSERT_EQ(cameras.size(), 7u);
    auto render = [&](const std::string& extra, const std::string& dir) {
        const fs::path out = mDir / dir;
        const RunResult r = run("--scene '" + level.string() + "' --method hard --size 64x64 " +
                                extra + " --out '" + out.string() + "'");
        EXPECT_EQ(r.exitCode, 0) << r.output;
        nlohmann::json report;
        std::ifstream(out / "report.json") >> report;
        return std::make_pair(r, report);
    };
    auto expectEye = [](const nlohmann::json& report, const glm::vec3& eye) {
        ASSERT_EQ(report["camera"]["eye"].size(), 3u);
        for (int i = 0; i < 3; ++i)
            EXPECT_FLOAT_EQ(report["camera"]["eye"][i].get<float>(), eye[i]) << i;
    };

    const auto [first, firstReport] = render("", "first");
    EXPECT_EQ(firstReport["camera_source"], "gltf camera 0: " + cameras[0].name);
    EXPECT_EQ(firstReport["camera_source"].get<std::string>().rfind("gltf camera 0: spawn", 0), 0u);
    EXPECT_EQ(firstReport["cameras"], 7);
    expectEye(firstReport, cameras[0].camera.eye);
    EXPECT_FLOAT_EQ(firstReport["camera"]["fov_y_deg"].get<float>(), cameras[0].camera.fovYDeg);
    EXPECT_NE(first.output.find("camera: gltf camera 0: spawn"), std::string::npos) << first.output;

    const auto [fourth, fourthReport] = render("--camera 3", "fourth");
    EXPECT_EQ(fourthReport["camera_source"], "gltf camera 3: " + cameras[3].name);
    expectEye(fourthReport, cameras[3].camera.eye);
    EXPECT_NE(cameras[3].camera.eye, cameras[0].camera.eye);

    expectRejected(level, "camera 99", "--method hard --camera 99");
    expectRejected(level, "7 glTF cameras", "--method hard --camera 99");
    expectRejected(level, "--camera", "--method hard --camera -1");
    expectRejected(write("s.json", kValidScene), "no glTF cameras", "--method hard --camera 0");
}

TEST_F(RenderCli, HelpDocumentsCamera) {
    const RunResult help = run("--help");
    EXPECT_EQ(help.exitCode, 0);
    EXPECT_NE(help.output.find("--camera"), std::string::npos) << help.output;
}

// --debug-view: a bad name is bad input naming the views; `error` renders until its progressive
// reference is complete (ceil(samples / 16) frames) and says so; --help lists the views.
TEST_F(RenderCli, DebugViews) {
    const fs::path scene = write("s.json", kValidScene);
    expectRejected(scene, "unknown debug view 'nope'", "--method hard --debug-view nope");
    expectRejected(scene, "group-parts", "--method hard --debug-view nope");
    const fs::path out = mDir / "out";
    const RunResult r = run("--scene '" + scene.string() +
                            "' --method wedges-blend --samples 40 --size 48x48 --debug-view error "
                            "--out '" + out.string() + "'");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    nlohmann::json report;
    std::ifstream(out / "report.json") >> report;
    EXPECT_EQ(report["parameters"]["frames"], 3);
    EXPECT_EQ(report["debug_view"]["name"], "error");
    const std::string note = report["debug_view"]["note"];
    EXPECT_NE(note.find("reference 40/40 samples (complete)"), std::string::npos) << note;
    EXPECT_NE(r.output.find(note), std::string::npos) << r.output;
    EXPECT_EQ(pngSize(out / "image.png"), std::make_pair(48u, 48u));

    const RunResult help = run("--help");
    for (const char* line : {"--debug-view", "--debug-group", "shaded:", "visibility:",
                             "silhouettes:", "wedges:", "stencil:", "group-parts:", "error:"})
        EXPECT_NE(help.output.find(line), std::string::npos) << line << " in:\n" << help.output;
}

} // namespace
