// GLSL preprocessing (version, defines, #include, #line) and program building with compiler logs
// mapped back to file:line.
//
// Source-string numbers: 0 is the generated prelude (#version and #defines), the stage's own file
// is 1, and each included file gets the next number the first time it is included. Drivers print
// the number in front of every message ("1:12(5): error" on Mesa, "1(12) : error" on NVIDIA),
// which is how a message is traced back to its file.
#include <gpu/gl/ShaderLoader.h>

#include <algorithm>
#include <cstdlib>
#include <fstream>
#include <regex>
#include <set>
#include <sstream>
#include <utility>

namespace gpu {

namespace fs = std::filesystem;

namespace {

constexpr const char* kPreludeName = "<prelude>";

struct Preprocessed {
    std::string source;
    std::vector<std::string> files; // display name per source-string number
};

bool readFile(const fs::path& path, std::string& out) {
    std::ifstream in(path, std::ios::binary);
    if (!in) return false;
    std::ostringstream ss;
    ss << in.rdbuf();
    out = ss.str();
    return true;
}

class Preprocessor {
public:
    Preprocessor(const fs::path& root, std::vector<fs::path>& dependencies)
        : mRoot(root), mDependencies(dependencies) {}

    Preprocessed run(const std::string& file, const std::vector<std::string>& defines) {
        mOut = "#version 450 core\n";
        for (const std::string& d : defines)
            mOut += "#define " + d + "\n";
        mFiles = {kPreludeName};
        fs::path path = mRoot / file;
        if (!fs::is_regular_file(path)) {
            throw ShaderError("cannot open shader '" + file + "' (looked for " +
                              path.lexically_normal().string() + ")");
        }
        processFile(path);
        return {std::move(mOut), std::move(mFiles)};
    }

private:
    const fs::path& mRoot;
    std::vector<fs::path>& mDependencies;
    std::string mOut;
    std::vector<std::string> mFiles;
    std::set<fs::path> mIncluded; // canonical paths already emitted (include once)
    std::vector<fs::path> mStack; // canonical paths being emitted (cycle detection)
    std::vector<std::string> mStackNames;

    void processFile(const fs::path& path) {
        fs::path key = fs::weakly_canonical(path);
        std::string name = path.lexically_normal().string();
        for (std::size_t i = 0; i < mStack.size(); ++i) {
            if (mStack[i] != key) continue;
            std::string chain;
            for (std::size_t j = i; j < mStackNames.size(); ++j)
                chain += mStackNames[j] + " -> ";
            throw ShaderError("include cycle: " + chain + name);
        }
        if (mIncluded.count(key)) return;

        std::string text;
        if (!readFile(path, text)) throw ShaderError("cannot read shader file " + name);
        mIncluded.insert(key);
        mDependencies.push_back(path.lexically_normal());
        mStack.push_back(key);
        mStackNames.push_back(name);
        const int number = static_cast<int>(mFiles.size());
        mFiles.push_back(name);

        // GLSL >= 3.30: "#line L S" makes the *next* line number L in source string S.
        mOut += "#line 1 " + std::to_string(number) + "\n";
        static const std::regex includeRe(R"re(^\s*#\s*include\s*"([^"]+)"\s*(//.*)?$)re");
        static const std::regex anyIncludeRe(R"(^\s*#\s*include\b.*)");
        static const std::regex versionRe(R"(^\s*#\s*version\b.*)");
        std::istringstream lines(text);
        std::string line;
        int lineNo = 0;
        while (std::getline(lines, line)) {
            ++lineNo;
            if (!line.empty() && line.back() == '\r') line.pop_back();
            std::smatch m;
            if (std::regex_match(line, m, includeRe)) {
                fs::path target = resolveInclude(path, m[1].str(), name, lineNo);
                processFile(target);
                mOut += "#line " + std::to_string(lineNo + 1) + " " + std::to_string(number) + "\n";
            } else if (std::regex_match(line, anyIncludeRe)) {
                throw ShaderError(name + ":" + std::to_string(lineNo) +
                                  ": malformed #include (expected #include \"file\")");
            } else if (std::regex_match(line, versionRe)) {
                // The loader owns the version line; keep a placeholder so line numbers hold.
                mOut += "// " + line + " (replaced by the loader's #version)\n";
            } else {
                mOut += line;
                mOut += '\n';
            }
        }
        mStack.pop_back();
        mStackNames.pop_back();
    }

    fs::path resolveInclude(const fs::path& from, const std::string& target,
                            const std::string& fromName, int lineNo) const {
        fs::path local = from.parent_path() / target;
        if (fs::is_regular_file(local)) return local;
        fs::path rooted = mRoot / target;
        if (fs::is_regular_file(rooted)) return rooted;
        throw ShaderError(fromName + ":" + std::to_string(lineNo) + ": cannot find include \"" +
                          target + "\" (looked for " + local.lexically_normal().string() + " and " +
                          rooted.lexically_normal().string() + ")");
    }
};

// Rewrites driver messages that start with a source-string number and line into "file:line: ".
std::string rewriteLog(const std::string& log, const std::vector<std::string>& files) {
    // Mesa: "1:12(5): error: ..."   NVIDIA: "1(12) : error C0000: ..."
    // AMD/Intel (Windows), glslang: "ERROR: 1:12: ..."
    static const std::regex mesaRe(R"(^(\d+):(\d+)\(\d+\): (.*)$)");
    static const std::regex nvidiaRe(R"(^(\d+)\((\d+)\) : (.*)$)");
    static const std::regex prefixedRe(R"(^(ERROR|WARNING): (\d+):(\d+): (.*)$)");

    auto fileName = [&](const std::string& number) -> const std::string* {
        std::size_t n = std::stoul(number);
        return n < files.size() ? &files[n] : nullptr;
    };
    std::istringstream lines(log);
    std::string line, out;
    while (std::getline(lines, line)) {
        if (!line.empty() && line.back() == '\r') line.pop_back();
        std::smatch m;
        const std::string* file = nullptr;
        std::string rewritten;
        if (std::regex_match(line, m, mesaRe) || std::regex_match(line, m, nvidiaRe)) {
            if ((file = fileName(m[1].str()))) {
                rewritten = *file + ":" + m[2].str() + ": " + m[3].str();
            }
        } else if (std::regex_match(line, m, prefixedRe)) {
            std::string kind = m[1].str() == "ERROR" ? "error" : "warning";
            if ((file = fileName(m[2].str()))) {
                rewritten = *file + ":" + m[3].str() + ": " + kind + ": " + m[4].str();
            }
        }
        if (!out.empty()) out += '\n';
        out += file ? rewritten : line;
    }
    while (!out.empty() && (out.back() == '\n' || out.back() == ' '))
        out.pop_back();
    return out;
}

const char* stageName(GLenum stage) {
    switch (stage) {
    case GL_VERTEX_SHADER:
        return "vertex";
    case GL_FRAGMENT_SHADER:
        return "fragment";
    case GL_GEOMETRY_SHADER:
        return "geometry";
    case GL_TESS_CONTROL_SHADER:
        return "tess control";
    case GL_TESS_EVALUATION_SHADER:
        return "tess evaluation";
    case GL_COMPUTE_SHADER:
        return "compute";
    default:
        return "unknown stage";
    }
}

std::string shaderLog(GLuint shader) {
    GLint length = 0;
    glGetShaderiv(shader, GL_INFO_LOG_LENGTH, &length);
    std::string log(static_cast<std::size_t>(std::max(length, 1)), '\0');
    glGetShaderInfoLog(shader, length, nullptr, log.data());
    log.resize(log.find('\0') == std::string::npos ? log.size() : log.find('\0'));
    return log;
}

std::string programLog(GLuint program) {
    GLint length = 0;
    glGetProgramiv(program, GL_INFO_LOG_LENGTH, &length);
    std::string log(static_cast<std::size_t>(std::max(length, 1)), '\0');
    glGetProgramInfoLog(program, length, nullptr, log.data());
    log.resize(log.find('\0') == std::string::npos ? log.size() : log.find('\0'));
    return log;
}

// Shader objects are only needed until the link; they are deleted on every path out of load().
struct ShaderList {
    GLuint program = 0;
    std::vector<GLuint> shaders;
    ~ShaderList() {
        for (GLuint s : shaders) {
            if (program) glDetachShader(program, s);
            glDeleteShader(s);
        }
    }
};

} // namespace

ShaderLoader::ShaderLoader(fs::path root) : mRoot(std::move(root)) {}

std::string ShaderLoader::preprocess(const std::string& file,
                                     const std::vector<std::string>& defines) const {
    mDependencies.clear();
    return Preprocessor(mRoot, mDependencies).run(file, defines).source;
}

Program ShaderLoader::load(const ProgramDesc& desc) const {
    mDependencies.clear();
    std::string name =
        desc.label ? desc.label : (desc.stages.empty() ? std::string("?") : desc.stages[0].file);
    std::string what = "shader program '" + name + "'";
    if (desc.stages.empty()) throw ShaderError(what + ": no stages");

    // Preprocess everything first: a missing file is reported before any GL object exists.
    std::vector<Preprocessed> sources;
    for (const ShaderStageDesc& stage : desc.stages) {
        try {
            sources.push_back(Preprocessor(mRoot, mDependencies).run(stage.file, desc.defines));
        } catch (const ShaderError& e) {
            throw ShaderError(what + ": " + e.what());
        }
    }

    Program program(glCreateProgram());
    if (desc.label) glObjectLabel(GL_PROGRAM, program.id(), -1, desc.label);
    ShaderList list{program.id(), {}};
    std::string errors;
    for (std::size_t i = 0; i < desc.stages.size(); ++i) {
        const ShaderStageDesc& stage = desc.stages[i];
        GLuint shader = glCreateShader(stage.stage);
        if (!shader) {
            throw ShaderError(what + ": glCreateShader failed for " + stage.file + " (" +
                              stageName(stage.stage) + ")");
        }
        list.shaders.push_back(shader);
        // Attached at once (legal before compiling) so ShaderList can detach every shader.
        glAttachShader(program.id(), shader);
        glObjectLabel(GL_SHADER, shader, -1, stage.file.c_str());
        const char* text = sources[i].source.c_str();
        glShaderSource(shader, 1, &text, nullptr);
        glCompileShader(shader);
        GLint ok = GL_FALSE;
        glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
        if (!ok) {
            // Keep compiling the other stages: one run then reports every broken file.
            errors += "\ncompile error in " + stage.file + " (" + stageName(stage.stage) +
                      " shader):\n" + rewriteLog(shaderLog(shader), sources[i].files);
        }
    }
    if (!errors.empty()) throw ShaderError(what + ":" + errors);

    glLinkProgram(program.id());
    GLint linked = GL_FALSE;
    glGetProgramiv(program.id(), GL_LINK_STATUS, &linked);
    if (!linked) {
        // Link messages carry no per-stage source numbers, so the log is passed through as is.
        std::string files;
        for (const ShaderStageDesc& stage : desc.stages)
            files += " " + stage.file;
        std::string log = programLog(program.id());
        while (!log.empty() && (log.back() == '\n' || log.back() == ' '))
            log.pop_back();
        throw ShaderError(what + ": link error (" + files.substr(1) + "):\n" + log);
    }
    return program;
}

fs::path defaultShaderDir() {
    if (const char* dir = std::getenv("PENUMBRA_SHADER_DIR"); dir && *dir) return dir;
#ifdef PENUMBRA_SHADER_DIR_DEFAULT
    return PENUMBRA_SHADER_DIR_DEFAULT;
#else
    return "shaders";
#endif
}

} // namespace gpu
