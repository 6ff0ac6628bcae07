// penumbra-bench's contract (DESIGN.md §3): a tiny sweep writes results.csv with the contract's
// columns and finite numbers, the truth scored against itself is 0, chart.png is drawn, bad input
// exits 2 writing nothing, and an interrupted run leaves a valid CSV of the runs done.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <sys/wait.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <random>
#include <sstream>
#include <string>
#include <vector>

namespace fs = std::filesystem;

namespace {

const std::string kBin = std::string(PENUMBRA_BIN_DIR) + "/penumbra-bench";
const fs::path kData = fs::path(PENUMBRA_SOURCE_DIR) / "data";

// A CSV without quoted fields containing newlines (the bench quotes commas and quotes only).
std::vector<std::map<std::string, std::string>> readCsv(const fs::path& file,
                                                        std::vector<std::string>* header) {
    auto split = [](const std::string& line) {
        std::vector<std::string> f;
        std::string cur;
        bool quoted = false;
        for (std::size_t i = 0; i < line.size(); ++i) {
            const char c = line[i];
            if (quoted && c == '"' && i + 1 < line.size() && line[i + 1] == '"') {
                cur += '"';
                ++i;
            } else if (c == '"') {
                quoted = !quoted;
            } else if (c == ',' && !quoted) {
                f.push_back(cur);
                cur.clear();
            } else {
                cur += c;
            }
        }
        f.push_back(cur);
        return f;
    };
    std::ifstream in(file);
    std::string line;
    std::vector<std::map<std::string, std::string>> rows;
    if (!std::getline(in, line)) return rows;
    *header = split(line);
    while (std::getline(in, line)) {
        const auto f = split(line);
        EXPECT_EQ(f.size(), header->size()) << line;
        std::map<std::string, std::string> row;
        for (std::size_t i = 0; i < f.size() && i < header->size(); ++i) row[(*header)[i]] = f[i];
        rows.push_back(row);
    }
    return rows;
}

// 'path' for a shell command line (built with append: GCC 12 warns falsely on "x" + string&&).
std::string q(const fs::path& p) {
    std::string s(1, '\'');
    s.append(p.string());
    s.push_back('\'');
    return s;
}

class BenchCli : public ::testing::Test {
protected:
    void SetUp() override {
        std::random_device rd;
        mDir = fs::temp_directory_path() / ("penumbra-bench-" + std::to_string(rd()));
        fs::create_directories(mDir);
    }
    void TearDown() override { fs::remove_all(mDir); }

    int run(const std::string& args, std::string* output = nullptr) {
        const fs::path log = mDir / "log.txt";
        const std::string cmd = kBin + " " + args + " > '" + log.string() + "' 2>&1";
        const int status = std::system(cmd.c_str());
        if (output) {
            std::ifstream in(log);
            std::stringstream ss;
            ss << in.rdbuf();
            *output = ss.str();
        }
        return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    }

    fs::path mDir;
};

double finite(const std::map<std::string, std::string>& row, const std::string& key) {
    const auto it = row.find(key);
    if (it == row.end()) {
        ADD_FAILURE() << "no column " << key;
        return NAN;
    }
    char* end = nullptr;
    const double x = std::strtod(it->second.c_str(), &end);
    EXPECT_TRUE(!it->second.empty() && *end == '\0' && std::isfinite(x))
        << key << " = '" << it->second << "' in " << row.at("scene") << " " << row.at("method");
    return x;
}

TEST_F(BenchCli, TinySweepWritesTheContract) {
    const fs::path out = mDir / "out";
    std::string log;
    const int rc = run(q(kData / "overlap.json") + " " + q(kData / "sphere.json") +
                           " --methods hard,wedges-blend,reference --size 64x64 "
                           "--truth-samples 64 --frames 2 --flicker-steps 2 --out " + q(out),
                       &log);
    ASSERT_EQ(rc, 0) << log;
    std::vector<std::string> header;
    const auto rows = readCsv(out / "results.csv", &header);
    // The contract's columns, in its order, first.
    const std::vector<std::string> contract{
        "scene", "method", "params", "gpu_ms", "cpu_ms", "frame_ms", "mean_abs_err", "rmse",
        "p99_err", "max_err", "bad_pixel_pct", "flicker"};
    ASSERT_GE(header.size(), contract.size());
    EXPECT_TRUE(std::equal(contract.begin(), contract.end(), header.begin()));
    ASSERT_EQ(rows.size(), 6u); // 2 scenes x 3 methods
    for (const auto& row : rows) {
        EXPECT_EQ(row.at("status"), "ok");
        for (const char* key : {"gpu_ms", "cpu_ms", "frame_ms", "mean_abs_err", "rmse",
                                       "p99_err", "max_err", "bad_pixel_pct", "flicker",
                                       "frame_over_hard"})
            finite(row, key);
        EXPECT_GT(finite(row, "frame_ms"), 0.0);
        EXPECT_EQ(row.at("nan_pixels"), "0");
        EXPECT_EQ(row.at("out_of_range_pixels"), "0");
        EXPECT_EQ(row.at("gl_errors"), "0");
        if (row.at("method") == "reference") {
            // The truth (reference N=64, same seed) scored against itself.
            EXPECT_EQ(row.at("params"), "samples=64");
            EXPECT_EQ(finite(row, "mean_abs_err"), 0.0);
            EXPECT_EQ(finite(row, "max_err"), 0.0);
            EXPECT_EQ(finite(row, "flicker"), 0.0);
        } else {
            // Both scenes have penumbrae: a real method has a real, bounded error.
            EXPECT_GT(finite(row, "mean_abs_err"), 1e-4) << row.at("method");
            EXPECT_LT(finite(row, "mean_abs_err"), 0.2) << row.at("method");
        }
        if (row.at("method") == "hard") {
            EXPECT_EQ(finite(row, "frame_over_hard"), 1.0);
        }
        if (row.at("method") == "wedges-blend") {
            // Soft shadows move with the light more like the truth than hard ones do.
            const auto hard = std::find_if(rows.begin(), rows.end(), [&](const auto& r) {
                return r.at("scene") == row.at("scene") && r.at("method") == "hard";
            });
            EXPECT_LT(finite(row, "flicker"), finite(*hard, "flicker"));
            EXPECT_LT(finite(row, "mean_abs_err"), finite(*hard, "mean_abs_err"));
        }
    }
    nlohmann::json j;
    std::ifstream(out / "results.json") >> j;
    EXPECT_TRUE(j["complete"].get<bool>());
    EXPECT_FALSE(j["gl_renderer"].get<std::string>().empty());
    EXPECT_FALSE(j["cpu"].get<std::string>().empty());
    EXPECT_TRUE(j.contains("build_type"));
    EXPECT_TRUE(j.contains("date"));
    EXPECT_EQ(j["runs"].size(), rows.size());
    EXPECT_GT(fs::file_size(out / "chart.png"), 10000u);
}

TEST_F(BenchCli, SweepsMultiplyAndHardComesFirst) {
    const fs::path out = mDir / "out";
    std::string log;
    const int rc = run(q(kData / "overlap.json") + " --methods wedges-blend --sweep wedges-blend:parts=1,4 "
                           "--sweep wedges-blend:bits=8,16 --light-scale 0.5,1 --size 32x32 "
                           "--truth-samples 16 --frames 1 --warmup 0 --flicker-steps 0 "
                           "--no-chart --save-images --out " + q(out),
                       &log);
    ASSERT_EQ(rc, 0) << log;
    std::vector<std::string> header;
    const auto rows = readCsv(out / "results.csv", &header);
    ASSERT_EQ(rows.size(), 2u * (1u + 4u)); // per light scale: hard + 2 x 2 variants
    EXPECT_EQ(rows[0].at("method"), "hard");
    EXPECT_EQ(rows[0].at("light_scale"), "0.5");
    EXPECT_EQ(rows[1].at("params"), "parts=1;bits=8;overlap=paper");
    EXPECT_EQ(rows[4].at("params"), "parts=4;bits=16;overlap=paper");
    EXPECT_EQ(rows[5].at("light_scale"), "1");
    EXPECT_EQ(rows[0].at("flicker"), ""); // not measured: an empty cell, never a made-up 0
    EXPECT_FALSE(fs::exists(out / "chart.png"));
    // A bigger light has wider penumbrae: hard's error grows with it.
    EXPECT_LT(finite(rows[0], "mean_abs_err"), finite(rows[5], "mean_abs_err"));
    EXPECT_TRUE(fs::exists(out / "images"));
    std::size_t heatMaps = 0;
    for (const auto& e : fs::recursive_directory_iterator(out / "images"))
        heatMaps += e.path().string().ends_with("-error.png");
    EXPECT_EQ(heatMaps, rows.size());
}

TEST_F(BenchCli, AFolderOfScenesGivesItsJsonFiles) {
    // data/stability holds scene JSONs and the .gltf meshes they load: only the JSONs are scenes.
    const fs::path out = mDir / "out";
    std::string log;
    ASSERT_EQ(run(q(kData / "stability") + " --methods hard --size 16x16 --truth-samples 4 "
                  "--frames 1 --warmup 0 --flicker-steps 0 --no-chart --out " + q(out), &log), 0)
        << log;
    std::vector<std::string> header;
    const auto rows = readCsv(out / "results.csv", &header);
    std::size_t scenes = 0;
    for (const auto& e : fs::directory_iterator(kData / "stability"))
        scenes += e.path().extension() == ".json";
    ASSERT_GE(scenes, 10u);
    ASSERT_EQ(rows.size(), scenes);
    for (const auto& row : rows) {
        EXPECT_TRUE(row.at("scene").ends_with(".json")) << row.at("scene");
        EXPECT_EQ(row.at("status"), "ok") << row.at("scene");
    }
}

// A level is measured from its spawn cameras (--cameras), each lit by the viewer's lamp: one
// set of rows per view, named PATH@cameraN; `framed` keeps the automatic framed view.
TEST_F(BenchCli, LevelsAreMeasuredFromTheirSpawnCamerasWithTheLamp) {
    const fs::path level = fs::path(PENUMBRA_SHARED_DIR) / "levels" / "oa_dm4.glb";
    const std::string common = " --methods hard --size 32x24 --truth-samples 4 --frames 1 "
                               "--warmup 0 --flicker-steps 0 --no-chart --save-images";
    const fs::path out = mDir / "out";
    std::string log;
    ASSERT_EQ(run(q(level) + " --cameras 0,2" + common + " --out " + q(out), &log), 0) << log;
    std::vector<std::string> header;
    const auto rows = readCsv(out / "results.csv", &header);
    ASSERT_EQ(rows.size(), 2u) << log; // hard at each view
    EXPECT_EQ(rows[0].at("scene"), level.string() + "@camera0");
    EXPECT_EQ(rows[1].at("scene"), level.string() + "@camera2");
    for (const auto& row : rows) EXPECT_EQ(row.at("status"), "ok") << row.at("scene");
    EXPECT_NE(log.find("lamp at the view"), std::string::npos) << log;
    const fs::path framed = mDir / "framed";
    ASSERT_EQ(run(q(level) + " --cameras framed" + common + " --out " + q(framed), &log), 0)
        << log;
    const auto framedRows = readCsv(framed / "results.csv", &header);
    ASSERT_EQ(framedRows.size(), 1u);
    EXPECT_EQ(framedRows[0].at("scene"), level.string());
    // A camera the file does not have is bad input, before any work.
    EXPECT_EQ(run(q(level) + " --cameras 99" + common + " --out " + q(mDir / "bad"), &log), 2);
    EXPECT_NE(log.find("--cameras: '99' is not a glTF camera"), std::string::npos) << log;
    EXPECT_FALSE(fs::exists(mDir / "bad"));
}

TEST_F(BenchCli, BadInputExitsTwoAndWritesNothing) {
    const std::string scene = q(kData / "overlap.json");
    const fs::path out = mDir / "out";
    const std::string o = " --out " + q(out);
    const std::vector<std::pair<std::string, std::string>> cases{
        {scene + " --methods wedges-nope", "wedges-nope"},
        {scene + " --methods hard,hard", "twice"},
        {scene + " --sweep wedges-blend:parts=3", "parts"},
        {scene + " --methods hard --sweep wedges-blend:parts=4", "not among --methods"},
        {scene + " --methods hard --sweep hard:samples=4", "takes no light samples"},
        {scene + " --truth wedges-blend", "not a reference method"},
        {scene + " --flicker-steps 3", "even"},
        {scene + " --light-scale 0", "--light-scale"},
        {scene + " --size 0x4", "--size"},
        // The limits every app shares (apps/Flags.h): each side 1 to 16384 (the bench took 8192
        // at most before), 1 to 65536 light samples (the sweep's had no bound).
        {scene + " --size 16385x4", "--size: each side must be between 1 and 16384"},
        {scene + " --truth-samples 65537", "--truth-samples must be between 1 and 65536"},
        {scene + " --methods reference --sweep reference:samples=16,65537",
         "'65537' is not a sample count (1 to 65536)"},
        {q(mDir / "missing.json"), "no such file"},
        {q(mDir), "no .json/.gltf/.glb"},
    };
    for (const auto& [args, needle] : cases) {
        std::string log;
        EXPECT_EQ(run(args + o, &log), 2) << args << "\n" << log;
        EXPECT_NE(log.find(needle), std::string::npos) << args << "\n" << log;
        EXPECT_NE(log.find("penumbra-bench: error:"), std::string::npos) << log;
        EXPECT_FALSE(fs::exists(out)) << args;
    }
}

// The output folder is checked before any scene is loaded; command-line errors carry the
// program's prefix; --seed says its range.
TEST_F(BenchCli, OutputSeedAndParseErrorsAreCheckedFirst) {
    const std::string scene = q(kData / "overlap.json");
    const fs::path file = mDir / "results";
    std::ofstream(file) << "not a folder";
    std::string log;
    EXPECT_EQ(run(scene + " --out " + q(file), &log), 2) << log;
    EXPECT_NE(log.find("penumbra-bench: error: --out: '" + file.string() +
                       "' exists and is not a folder"),
              std::string::npos)
        << log;
    EXPECT_EQ(log.find("checking"), std::string::npos) << "scenes loaded first:\n" << log;
    EXPECT_EQ(run(scene + " --out " + q(file / "sub"), &log), 2) << log;
    EXPECT_NE(log.find("cannot be created: '" + file.string() + "' is not a folder"),
              std::string::npos)
        << log;

    const std::string o = " --out " + q(mDir / "out");
    EXPECT_EQ(run(scene + " --seed -1" + o, &log), 2) << log;
    EXPECT_NE(log.find("penumbra-bench: error: --seed must be between 0 and 4294967295, got -1"),
              std::string::npos)
        << log;
    EXPECT_EQ(run(scene + " --bogus" + o, &log), 2) << log;
    EXPECT_EQ(log.rfind("penumbra-bench: error: ", 0), 0u) << log;
    EXPECT_FALSE(fs::exists(mDir / "out"));
}

TEST_F(BenchCli, InterruptKeepsAValidCsv) {
    // A sweep far longer than the test; interrupt once two runs are in and check what is left.
    const fs::path out = mDir / "out";
    const fs::path csv = out / "results.csv";
    const std::string script =
        kBin + " " + q(kData / "sphere.json") +
        " --methods hard,wedges-additive,wedges-blend,wedges-multiply --sweep "
        "wedges-blend:parts=1,4,8 --light-scale 1,0.9,0.8,0.7,0.6,0.5 --size 64x64 "
        "--truth-samples 16 --frames 200 --flicker-steps 0 --no-chart --out " + q(out) + " > " +
        q(mDir / "log.txt") + " 2>&1 & pid=$!; for i in $(seq 600); do [ -f " + q(csv) +
        " ] && [ $(wc -l < " + q(csv) + ") -ge 3 ] && break; sleep 0.1; done; " +
        "kill -INT $pid; wait $pid; exit $?";
    const fs::path file = mDir / "interrupt.sh";
    std::ofstream(file) << script << "\n";
    const int status = std::system(("bash " + q(file)).c_str());
    ASSERT_TRUE(WIFEXITED(status));
    EXPECT_EQ(WEXITSTATUS(status), 130);
    std::vector<std::string> header;
    const auto rows = readCsv(csv, &header);
    EXPECT_GE(rows.size(), 2u);
    EXPECT_LT(rows.size(), 6u * 6u);
    for (const auto& row : rows) finite(row, "frame_ms");
    nlohmann::json j;
    std::ifstream(out / "results.json") >> j;
    EXPECT_FALSE(j["complete"].get<bool>());
    EXPECT_EQ(j["runs"].size(), rows.size());
}

} // namespace
