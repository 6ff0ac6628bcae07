// ShaderLoader: preprocessing (version, defines, includes, #line), include errors, and compile/link
// errors mapped back to file:line on the real driver.
#include "GlTestEnv.h"
#include "TestErrors.h"

#include <gpu/gl/ShaderLoader.h>

#include <algorithm>
#include <atomic>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <optional>
#include <sstream>
#include <string>
#include <unistd.h>

namespace {

namespace fs = std::filesystem;

// A fresh shader root per test, removed afterwards.
class TempDir {
public:
    TempDir() {
        static std::atomic<int> counter{0};
        mRoot = fs::temp_directory_path() / ("penumbra-shader-test-" + std::to_string(::getpid()) +
                                             "-" + std::to_string(counter++));
        fs::remove_all(mRoot);
        fs::create_directories(mRoot);
    }
    ~TempDir() {
        std::error_code ec;
        fs::remove_all(mRoot, ec);
    }
    const fs::path& root() const { return mRoot; }
    fs::path write(const std::string& name, const std::string& text) const {
        fs::path p = mRoot / name;
        fs::create_directories(p.parent_path());
        std::ofstream(p) << text;
        return p;
    }

private:
    fs::path mRoot;
};

std::vector<std::string> lines(const std::string& text) {
    std::vector<std::string> out;
    std::istringstream in(text);
    for (std::string l; std::getline(in, l);)
        out.push_back(l);
    return out;
}

std::string name(const TempDir& dir, const std::string& file) {
    return (dir.root() / file).lexically_normal().string();
}

bool contains(const std::string& haystack, const std::string& needle) {
    return haystack.find(needle) != std::string::npos;
}

// Preprocessing `file` must throw a ShaderError (a fatal failure saying `failure` otherwise) whose
// message contains every one of `needles`.
void expectPreprocessError(const gpu::ShaderLoader& loader, const std::string& file,
                           const char* failure, std::initializer_list<std::string> needles) {
    const std::optional<std::string> what =
        testutil::errorOf<gpu::ShaderError>([&] { loader.preprocess(file, {}); });
    ASSERT_TRUE(what) << failure;
    for (const std::string& needle : needles)
        EXPECT_TRUE(contains(*what, needle)) << *what;
}

// Layout used by several tests:
//   main.frag          includes lib/a.glsl (line 2) and common.glsl twice (lines 3 and 5)
//   lib/a.glsl         includes b.glsl (relative: lib/b.glsl) and common.glsl (from the root)
void writeNested(const TempDir& dir) {
    dir.write("main.frag", "// main line 1\n"
                           "#include \"lib/a.glsl\"\n"
                           "#include \"common.glsl\"\n"
                           "float mainLine4;\n"
                           "  #  include \"common.glsl\"   // again: included once\n"
                           "void main() {}\n");
    dir.write("lib/a.glsl", "#include \"b.glsl\"\n"
                            "float aLine2;\n"
                            "#include \"common.glsl\"\n");
    dir.write("lib/b.glsl", "float bLine1;\n");
    dir.write("common.glsl", "float commonLine1;\n");
}

TEST(ShaderLoaderTest, PreprocessEmitsVersionDefinesIncludesAndLines) {
    TempDir dir;
    writeNested(dir);
    gpu::ShaderLoader loader(dir.root());
    std::string out = loader.preprocess("main.frag", {"FOO 1", "BAR"});
    std::vector<std::string> l = lines(out);

    // Source strings: 0 prelude, 1 main.frag, 2 lib/a.glsl, 3 lib/b.glsl, 4 common.glsl.
    std::vector<std::string> expected = {
        "#version 450 core", "#define FOO 1",      "#define BAR",    "#line 1 1", "// main line 1",
        "#line 1 2",         "#line 1 3",          "float bLine1;",  "#line 2 2", "float aLine2;",
        "#line 1 4",         "float commonLine1;", "#line 4 2",      "#line 3 1",
        "#line 4 1", // common.glsl was already included by lib/a.glsl
        "float mainLine4;",  "#line 6 1",          "void main() {}",
    };
    EXPECT_EQ(l, expected) << out;

    const std::vector<fs::path>& deps = loader.dependencies();
    ASSERT_EQ(deps.size(), 4u);
    EXPECT_EQ(deps[0], dir.root() / "main.frag");
    EXPECT_EQ(deps[1], dir.root() / "lib/a.glsl");
    EXPECT_EQ(deps[2], dir.root() / "lib/b.glsl");
    EXPECT_EQ(deps[3], dir.root() / "common.glsl");
}

TEST(ShaderLoaderTest, VersionLineInAFileIsReplacedKeepingLineNumbers) {
    TempDir dir;
    dir.write("v.vert", "#version 330 core\nvoid main() {}\n");
    std::vector<std::string> l = lines(gpu::ShaderLoader(dir.root()).preprocess("v.vert", {}));
    ASSERT_EQ(l.size(), 4u);
    EXPECT_EQ(l[0], "#version 450 core");
    EXPECT_EQ(std::count_if(l.begin(), l.end(),
                            [](const std::string& s) { return s.rfind("#version", 0) == 0; }),
              1);
    EXPECT_EQ(l[3], "void main() {}");
}

TEST(ShaderLoaderTest, IncludeCycleThrows) {
    TempDir dir;
    dir.write("x.glsl", "#include \"y.glsl\"\n");
    dir.write("y.glsl", "float y;\n#include \"x.glsl\"\n");
    dir.write("top.frag", "#include \"x.glsl\"\nvoid main() {}\n");
    gpu::ShaderLoader loader(dir.root());
    ASSERT_NO_FATAL_FAILURE(
        expectPreprocessError(loader, "top.frag", "cycle not detected",
                              {"cycle", name(dir, "x.glsl") + " -> " + name(dir, "y.glsl") +
                                            " -> " + name(dir, "x.glsl")}));
    // A file including itself is the shortest cycle.
    dir.write("self.glsl", "#include \"self.glsl\"\n");
    EXPECT_THROW(loader.preprocess("self.glsl", {}), gpu::ShaderError);
}

TEST(ShaderLoaderTest, MissingIncludeNamesFileAndLine) {
    TempDir dir;
    dir.write("lib/user.glsl", "float a;\nfloat b;\n#include \"nowhere.glsl\"\n");
    dir.write("m.frag", "#include \"lib/user.glsl\"\nvoid main() {}\n");
    gpu::ShaderLoader loader(dir.root());
    ASSERT_NO_FATAL_FAILURE(
        expectPreprocessError(loader, "m.frag", "missing include accepted",
                              {"nowhere.glsl", name(dir, "lib/user.glsl") + ":3:"}));
    EXPECT_THROW(loader.preprocess("absent.frag", {}), gpu::ShaderError);
    dir.write("angle.frag", "#include <x.glsl>\n");
    EXPECT_THROW(loader.preprocess("angle.frag", {}), gpu::ShaderError);
}

TEST(ShaderLoaderTest, DefaultShaderDirHonoursEnvironment) {
    const char* old = std::getenv("PENUMBRA_SHADER_DIR");
    std::string saved = old ? old : "";
    setenv("PENUMBRA_SHADER_DIR", "/tmp/some-shaders", 1);
    EXPECT_EQ(gpu::defaultShaderDir(), fs::path("/tmp/some-shaders"));
    unsetenv("PENUMBRA_SHADER_DIR");
    // Compiled in from the source tree.
    EXPECT_EQ(gpu::defaultShaderDir(), fs::path(PENUMBRA_SOURCE_DIR) / "shaders");
    if (old) setenv("PENUMBRA_SHADER_DIR", saved.c_str(), 1);
}

// --- On the driver ---------------------------------------------------------------------------

class ShaderLoaderGlTest : public GlTest {};

const char* kVert = "layout(location = 0) in vec2 position;\n"
                    "void main() { gl_Position = vec4(position, 0.0, 1.0); }\n";

TEST_F(ShaderLoaderGlTest, ValidProgramLoadsWithDefines) {
    TempDir dir;
    dir.write("p.vert", kVert);
    dir.write("lib/colour.glsl", "vec4 colour() { return vec4(TINT, 0.0, 0.0, 1.0); }\n");
    dir.write("p.frag", "#include \"lib/colour.glsl\"\n"
                        "uniform float gain;\n"
                        "out vec4 fragColour;\n"
                        "void main() { fragColour = gain * colour(); }\n");
    gpu::ShaderLoader loader(dir.root());
    gpu::Program program =
        loader.load({.stages = {{GL_VERTEX_SHADER, "p.vert"}, {GL_FRAGMENT_SHADER, "p.frag"}},
                     .defines = {"TINT 0.5"},
                     .label = "valid"});
    ASSERT_TRUE(program);
    GLint linked = GL_FALSE;
    glGetProgramiv(program.id(), GL_LINK_STATUS, &linked);
    EXPECT_EQ(linked, GL_TRUE);
    EXPECT_GE(program.uniformLocation("gain"), 0);
    GLint attached = -1;
    glGetProgramiv(program.id(), GL_ATTACHED_SHADERS, &attached);
    EXPECT_EQ(attached, 0); // shaders are detached and deleted after the link
    EXPECT_EQ(loader.dependencies().size(), 3u);
}

TEST_F(ShaderLoaderGlTest, CompileErrorInIncludedFileNamesThatFileAndLine) {
    TempDir dir;
    dir.write("e.vert", kVert);
    dir.write("lib/helpers.glsl", "// helpers\n"
                                  "float fine() { return 1.0; }\n"
                                  "float broken() { return undefinedSymbol; }\n");
    dir.write("e.frag", "// e.frag\n"
                        "#include \"lib/helpers.glsl\"\n"
                        "out vec4 c;\n"
                        "void main() { c = vec4(fine() + broken()); }\n");
    gpu::ShaderLoader loader(dir.root());
    const std::optional<std::string> what = testutil::errorOf<gpu::ShaderError>([&] {
        loader.load({.stages = {{GL_VERTEX_SHADER, "e.vert"}, {GL_FRAGMENT_SHADER, "e.frag"}},
                     .label = "broken-include"});
    });
    ASSERT_TRUE(what) << "compile error not reported";
    EXPECT_TRUE(contains(*what, "broken-include")) << *what;
    EXPECT_TRUE(contains(*what, name(dir, "lib/helpers.glsl") + ":3: ")) << *what;
    EXPECT_TRUE(contains(*what, "undefinedSymbol")) << *what;
}

TEST_F(ShaderLoaderGlTest, CompileErrorAfterIncludeKeepsMainFileLines) {
    TempDir dir;
    dir.write("m.vert", "#include \"lib/one.glsl\"\n"
                        "#include \"lib/two.glsl\"\n"
                        "\n"
                        "void main() {\n"
                        "    gl_Position = vec4(one() + two(), 0.0, 0.0, 1.0)\n" // no ';'
                        "}\n");
    dir.write("lib/one.glsl", "float one() {\n    return 1.0;\n}\n");
    dir.write("lib/two.glsl", "float two() { return 2.0; }\n");
    dir.write("m.frag", "out vec4 c;\nvoid main() { c = vec4(1.0); }\n");
    const std::optional<std::string> what = testutil::errorOf<gpu::ShaderError>([&] {
        gpu::ShaderLoader(dir.root())
            .load({.stages = {{GL_VERTEX_SHADER, "m.vert"}, {GL_FRAGMENT_SHADER, "m.frag"}}});
    });
    ASSERT_TRUE(what) << "compile error not reported";
    // The missing ';' is diagnosed at the next token, on line 6 of m.vert.
    EXPECT_TRUE(contains(*what, name(dir, "m.vert") + ":6: ") ||
                contains(*what, name(dir, "m.vert") + ":5: "))
        << *what;
    EXPECT_FALSE(contains(*what, "one.glsl:")) << *what;
}

TEST_F(ShaderLoaderGlTest, ErrorFromADefineIsReportedWhereItIsExpanded) {
    TempDir dir;
    dir.write("d.frag", "out vec4 c;\nvoid main() { c = vec4(VALUE); }\n");
    const std::optional<std::string> what = testutil::errorOf<gpu::ShaderError>([&] {
        gpu::ShaderLoader(dir.root())
            .load({.stages = {{GL_FRAGMENT_SHADER, "d.frag"}}, .defines = {"VALUE ]"}});
    });
    ASSERT_TRUE(what) << "compile error not reported";
    // The bad token comes from a define but is diagnosed where it is expanded.
    EXPECT_TRUE(contains(*what, name(dir, "d.frag") + ":2: ")) << *what;
}

TEST_F(ShaderLoaderGlTest, ErrorInsideTheGeneratedPreludeIsNamedSo) {
    TempDir dir;
    dir.write("ok.frag", "out vec4 c;\nvoid main() { c = vec4(1.0); }\n");
    // Line 2 of the prelude is the first #define, which is malformed.
    const std::optional<std::string> what = testutil::errorOf<gpu::ShaderError>([&] {
        gpu::ShaderLoader(dir.root())
            .load({.stages = {{GL_FRAGMENT_SHADER, "ok.frag"}}, .defines = {"1BAD x"}});
    });
    ASSERT_TRUE(what) << "bad define accepted";
    EXPECT_TRUE(contains(*what, "<prelude>:2: ")) << *what;
}

TEST_F(ShaderLoaderGlTest, LinkErrorIsReported) {
    TempDir dir;
    // Declared but never defined in any stage: compiles, fails to link.
    dir.write("l.vert", "float missing();\n"
                        "void main() { gl_Position = vec4(missing()); }\n");
    dir.write("l.frag", "out vec4 c;\nvoid main() { c = vec4(1.0); }\n");
    const std::optional<std::string> what = testutil::errorOf<gpu::ShaderError>([&] {
        gpu::ShaderLoader(dir.root())
            .load({.stages = {{GL_VERTEX_SHADER, "l.vert"}, {GL_FRAGMENT_SHADER, "l.frag"}},
                   .label = "unlinkable"});
    });
    ASSERT_TRUE(what) << "link error not reported";
    EXPECT_TRUE(contains(*what, "unlinkable")) << *what;
    EXPECT_TRUE(contains(*what, "link error")) << *what;
    EXPECT_TRUE(contains(*what, "missing")) << *what;
}

TEST_F(ShaderLoaderGlTest, MissingStageFileThrowsBeforeTouchingGl) {
    TempDir dir;
    dir.write("only.vert", kVert);
    const std::optional<std::string> what = testutil::errorOf<gpu::ShaderError>([&] {
        gpu::ShaderLoader(dir.root())
            .load({.stages = {{GL_VERTEX_SHADER, "only.vert"}, {GL_FRAGMENT_SHADER, "gone.frag"}},
                   .label = "incomplete"});
    });
    ASSERT_TRUE(what) << "missing stage file accepted";
    EXPECT_TRUE(contains(*what, "gone.frag")) << *what;
    EXPECT_TRUE(contains(*what, "incomplete")) << *what;
}

} // namespace
