// The float C++ twins in geometry/ against the GLSL libraries in shaders/lib/ they mirror: the
// same functions, statement for statement, the same constants, vertex table and struct fields.
// Compared as text, after removing what only the spelling differs in (comments, whitespace,
// `const`, `std::`, `glm::`, references and `inout`, the `f` of float literals), so that the
// GPU-side code stays covered by the CPU tests of its twin.
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

namespace {

std::string readSource(const std::string& relative) {
    std::ifstream in(std::string(PENUMBRA_SOURCE_DIR) + "/" + relative);
    std::ostringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

std::string withoutComments(const std::string& text) {
    return std::regex_replace(text, std::regex(R"(//[^\n]*)"), "");
}

// The definition of `name` (its line must start at column 0) up to its closing brace; empty
// when absent.
std::string definition(const std::string& text, const std::string& name) {
    std::smatch m;
    const std::regex head("(^|\\n)[A-Za-z_][A-Za-z0-9_:<>]*[ \\t]+" + name + "\\(");
    if (!std::regex_search(text, m, head)) return {};
    const std::size_t start = static_cast<std::size_t>(m.position(0)) + m[1].length();
    std::size_t i = text.find('{', start);
    int depth = 0;
    for (; i < text.size(); ++i) {
        if (text[i] == '{') ++depth;
        if (text[i] == '}' && --depth == 0) return text.substr(start, i + 1 - start);
    }
    return {};
}

std::string normalised(std::string s) {
    const std::vector<std::pair<const char*, const char*>> rules = {
        {R"(\bstd::)", ""},    {R"(\bglm::)", ""},       {R"(\bconst\s+)", ""},
        {R"(\binout\s+)", ""}, {R"((\w)&(\s))", "$1$2"}, {R"((\d)f\b)", "$1"},
        {R"(\s+)", ""},
    };
    for (const auto& [from, to] : rules)
        s = std::regex_replace(s, std::regex(from), to);
    return s;
}

// name -> value of `constexpr <type> name = value;` (C++) or `const <type> name = value;` (GLSL).
std::vector<std::pair<std::string, double>> constants(const std::string& text,
                                                      const std::string& prefix) {
    std::vector<std::pair<std::string, double>> out;
    const std::regex re("const(?:expr)?\\s+(?:float|int)\\s+(" + prefix +
                        "\\w*)\\s*=\\s*([-0-9.e+]+)f?;");
    for (auto it = std::sregex_iterator(text.begin(), text.end(), re); it != std::sregex_iterator();
         ++it)
        out.emplace_back((*it)[1].str(), std::stod((*it)[2].str()));
    return out;
}

// The integers between `open` and the next `close` after `name`.
std::vector<int> integerList(const std::string& text, const std::string& name, char open,
                             char close) {
    std::vector<int> out;
    std::size_t i = text.find(name);
    if (i == std::string::npos) return out;
    i = text.find('=', i);
    i = text.find(open, i);
    const std::size_t end = text.find(close, i);
    const std::string body = text.substr(i + 1, end - i - 1);
    const std::regex number(R"(\d+)");
    for (auto it = std::sregex_iterator(body.begin(), body.end(), number);
         it != std::sregex_iterator(); ++it)
        out.push_back(std::stoi(it->str()));
    return out;
}

// "type name" of each field of `struct name { ... };`, initialisers dropped.
std::vector<std::string> fields(const std::string& text, const std::string& name) {
    std::vector<std::string> out;
    const std::size_t at = text.find("struct " + name + " {");
    if (at == std::string::npos) return out;
    std::size_t end = text.find('{', at);
    for (int depth = 0; end < text.size(); ++end) {
        if (text[end] == '{') ++depth;
        if (text[end] == '}' && --depth == 0) break;
    }
    const std::size_t open = text.find('{', at) + 1;
    const std::string body = text.substr(open, end - open);
    const std::regex re(R"(([A-Za-z_][\w:]*)\s+(\w+(?:\[\d+\])?)\s*(?:=[^;]*|\{[^}]*\})?;)");
    for (auto it = std::sregex_iterator(body.begin(), body.end(), re); it != std::sregex_iterator();
         ++it)
        out.push_back(normalised((*it)[1].str()) + " " + (*it)[2].str());
    return out;
}

void expectSameFunctions(const std::string& cppFile, const std::string& glslFile,
                         const std::vector<std::string>& names) {
    const std::string cpp = withoutComments(readSource(cppFile));
    const std::string glsl = withoutComments(readSource(glslFile));
    ASSERT_FALSE(cpp.empty()) << cppFile;
    ASSERT_FALSE(glsl.empty()) << glslFile;
    for (const std::string& name : names) {
        const std::string a = definition(cpp, name), b = definition(glsl, name);
        ASSERT_FALSE(a.empty()) << name << " not found in " << cppFile;
        ASSERT_FALSE(b.empty()) << name << " not found in " << glslFile;
        EXPECT_EQ(normalised(a), normalised(b)) << name << "\n--- C++\n"
                                                << a << "\n--- GLSL\n"
                                                << b;
    }
}

} // namespace

TEST(GlslTwinTest, WedgeHullFunctionsMatchStatementForStatement) {
    expectSameFunctions("geometry/src/WedgeHull.cpp", "shaders/lib/WedgeHull.glsl",
                        {"wedgeHullCross2", "wedgeHullSpread", "wedgeHullSide", "wedgeHull",
                         "wedgeHullVertex", "wedgeHullClipVertex", "wedgeHullContains"});
}

TEST(GlslTwinTest, CoverageFunctionsMatchStatementForStatement) {
    expectSameFunctions(
        "geometry/src/Coverage.cpp", "shaders/lib/Coverage.glsl",
        {"coverageCross2", "coverageClipLe0", "coverageClipHalf", "coverageSegment",
         "coverageProject", "coverageLight", "edgeCoverage"});
}

TEST(GlslTwinTest, WedgeHullConstantsTableAndStructMatch) {
    const std::string header = withoutComments(readSource("geometry/include/geometry/WedgeHull.h"));
    const std::string cpp = withoutComments(readSource("geometry/src/WedgeHull.cpp"));
    const std::string glsl = withoutComments(readSource("shaders/lib/WedgeHull.glsl"));
    auto cppConstants = constants(header, "kWedgeHull");
    const auto more = constants(cpp, "kWedgeHull");
    cppConstants.insert(cppConstants.end(), more.begin(), more.end());
    auto glslConstants = constants(glsl, "kWedgeHull");
    std::sort(cppConstants.begin(), cppConstants.end());
    std::sort(glslConstants.begin(), glslConstants.end());
    EXPECT_EQ(cppConstants.size(), 9u);
    EXPECT_EQ(cppConstants, glslConstants);

    const std::vector<int> table = integerList(header, "kWedgeHullIndex[", '{', '}');
    EXPECT_EQ(table.size(), 24u);
    EXPECT_EQ(table, integerList(glsl, "kWedgeHullIndex[", '(', ')'));

    const std::vector<std::string> f = fields(header, "WedgeHull");
    EXPECT_EQ(f, (std::vector<std::string>{"int kind", "vec3 e0", "vec3 e1", "vec3 g[4]",
                                           "vec4 planes[4]"}));
    EXPECT_EQ(f, fields(glsl, "WedgeHull"));
}

TEST(GlslTwinTest, CoverageLightStructMatches) {
    const std::vector<std::string> f = fields(
        withoutComments(readSource("geometry/include/geometry/Coverage.h")), "CoverageLight");
    EXPECT_EQ(f.size(), 6u);
    EXPECT_EQ(f, fields(withoutComments(readSource("shaders/lib/Coverage.glsl")), "CoverageLight"));
}

TEST(GlslTwinTest, PartsFunctionsAndStructMatch) {
    expectSameFunctions("geometry/src/Parts.cpp", "shaders/lib/Parts.glsl",
                        {"partsHalf", "partsAxisSide", "partsQuadrantArea", "partsSegmentBounds",
                         "partsEdgeBounds", "partsTriangleBounds", "partsInside",
                         "partsCornerWinding", "edgeParts4", "partsSegment", "partsSide",
                         "partsSquareMoments", "partsTriangleMoments", "partsLightMoments",
                         "partsSquareWindings", "partsTriangleWindings", "partsLightWindings",
                         "partsFrame", "partsWhole", "edgePartSet"});
    const std::vector<std::string> f =
        fields(withoutComments(readSource("geometry/include/geometry/Parts.h")), "EdgeParts4");
    EXPECT_EQ(f, (std::vector<std::string>{"vec4 coverage", "vec4 bounds[4]", "vec3 windings[4]"}));
    EXPECT_EQ(f, fields(withoutComments(readSource("shaders/lib/Parts.glsl")), "EdgeParts4"));
    const std::vector<std::string> g =
        fields(withoutComments(readSource("geometry/include/geometry/Parts.h")), "EdgePartSet");
    EXPECT_EQ(g, (std::vector<std::string>{"vec4 coverage", "vec4 momentX", "vec4 momentY",
                                           "vec4 bounds[4]", "vec4 windings"}));
    EXPECT_EQ(g, fields(withoutComments(readSource("shaders/lib/Parts.glsl")), "EdgePartSet"));
}
