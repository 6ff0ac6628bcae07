#include "passes/OcclusionPrefilter.h"

#include "engine/ShaderBindings.h"

#include <string>

namespace gpu {

NBufferPass::NBufferPass(const ShaderLoader& shaders, int slices)
    : mProgram(shaders.load({.stages = {{GL_COMPUTE_SHADER, "occlusion-nbuffer.comp"}},
                             .defines = {"SLICES " + std::to_string(slices)},
                             .label = "occlusion-nbuffer"})) {}

void NBufferPass::execute(const Texture& levels, int topLevel) const {
    glUseProgram(mProgram.id());
    glBindImageTexture(IMAGE_OCCLUSION_DST, levels.id(), 0, GL_TRUE, 0, GL_READ_WRITE,
                       GL_RGBA16);
    const GLuint groups = static_cast<GLuint>((levels.width() + 7) / 8);
    for (int level = 1; level <= topLevel; ++level) {
        // Level l reads what level l - 1 stored.
        glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
        glUniform1i(UNIFORM_PREFILTER_STEP, level);
        glDispatchCompute(groups, groups, 1);
    }
    glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT); // the lookup samples the levels
}

SatPass::SatPass(const ShaderLoader& shaders)
    : mProgram(shaders.load({.stages = {{GL_COMPUTE_SHADER, "occlusion-sat.comp"}},
                             .label = "occlusion-sat"})) {}

void SatPass::execute(const Texture& slices, const Texture& sat) const {
    glUseProgram(mProgram.id());
    glBindImageTexture(IMAGE_OCCLUSION_SRC, slices.id(), 0, GL_TRUE, 0, GL_READ_ONLY, GL_RGBA8);
    glBindImageTexture(IMAGE_OCCLUSION_DST, sat.id(), 0, GL_TRUE, 0, GL_READ_WRITE, GL_RGBA32UI);
    const GLuint lines = static_cast<GLuint>((sat.width() + 63) / 64); // R + 1 columns
    const GLuint targets = static_cast<GLuint>(sat.layers());
    glUniform1i(UNIFORM_PREFILTER_STEP, 0);
    glDispatchCompute(lines, targets, 1);
    glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT); // columns read the row sums
    glUniform1i(UNIFORM_PREFILTER_STEP, 1);
    glDispatchCompute(lines, targets, 1);
    glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT); // the lookup fetches the table
}

} // namespace gpu
