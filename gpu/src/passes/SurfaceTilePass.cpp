#include "passes/SurfaceTilePass.h"

#include "engine/ShaderBindings.h"
#include "engine/Targets.h"

namespace gpu {

SurfaceTilePass::SurfaceTilePass(const ShaderLoader& shaders)
    : mProgram(shaders.load(
          {.stages = {{GL_COMPUTE_SHADER, "surface-tiles.comp"}}, .label = "surface-tiles"})) {}

SurfaceTiles SurfaceTilePass::measure(const Targets& t) {
    SurfaceTiles out;
    out.tile = kTile;
    out.tilesX = (t.width + kTile - 1) / kTile;
    out.tilesY = (t.height + kTile - 1) / kTile;
    const std::size_t tiles = static_cast<std::size_t>(out.tilesX) * out.tilesY;
    const std::size_t bytes = 2 * tiles * sizeof(glm::vec4);
    if (mTiles.size() < bytes)
        mTiles = Buffer({.size = bytes, .flags = 0, .label = "surface-tiles"});
    glUseProgram(mProgram.id());
    glBindTextureUnit(TEXUNIT_POSITION, t.position.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BINDING_SURFACE_TILES, mTiles.id());
    glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_FRAMEBUFFER_BARRIER_BIT);
    glUniform1i(0, out.tilesX);
    glDispatchCompute(static_cast<GLuint>((out.tilesX + 7) / 8), static_cast<GLuint>(out.tilesY), 1);
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    mScratch.resize(2 * tiles);
    glGetNamedBufferSubData(mTiles.id(), 0, static_cast<GLsizeiptr>(bytes), mScratch.data());
    out.boxes.resize(tiles);
    for (std::size_t i = 0; i < tiles; ++i) {
        const glm::vec3 lo(mScratch[2 * i]), hi(mScratch[2 * i + 1]);
        if (lo.x <= hi.x && lo.y <= hi.y && lo.z <= hi.z) {
            out.boxes[i].extend(lo);
            out.boxes[i].extend(hi);
        }
    }
    return out;
}

} // namespace gpu
