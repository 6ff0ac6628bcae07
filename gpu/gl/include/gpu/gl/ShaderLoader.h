// GLSL loading from shaders/: prepends `#version 450 core` and the variant #defines, resolves
// `#include "file"` (relative to the including file, then to the shader root, each file once),
// and emits `#line` directives with a source-string number per file so that compiler messages map
// back to file:line. On a compile or link error, throws ShaderError whose message names
// file:line for each reported line ("shaders/wedge.frag:42: error: ...").
#pragma once

#include <gpu/gl/Objects.h>

#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

namespace gpu {

class ShaderError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

struct ShaderStageDesc {
    GLenum stage = GL_VERTEX_SHADER;
    std::string file; // relative to the loader root, e.g. "gbuffer.vert"
};

struct ProgramDesc {
    std::vector<ShaderStageDesc> stages;
    std::vector<std::string> defines; // "NAME" or "NAME VALUE"
    const char* label = nullptr;
};

class ShaderLoader {
public:
    // root = directory holding the .vert/.frag/.glsl files.
    explicit ShaderLoader(std::filesystem::path root);
    const std::filesystem::path& root() const { return mRoot; }

    // Preprocessed source of one stage (for tests and error messages). Throws ShaderError on a
    // missing file or an include cycle.
    std::string preprocess(const std::string& file, const std::vector<std::string>& defines) const;
    Program load(const ProgramDesc& desc) const;

    // Files read by the last preprocess/load (for hot reload).
    const std::vector<std::filesystem::path>& dependencies() const { return mDependencies; }

private:
    std::filesystem::path mRoot;
    mutable std::vector<std::filesystem::path> mDependencies;
};

// The shader root: $PENUMBRA_SHADER_DIR if set, else the source tree's shaders/ (compiled in as
// PENUMBRA_SHADER_DIR_DEFAULT).
std::filesystem::path defaultShaderDir();

} // namespace gpu
