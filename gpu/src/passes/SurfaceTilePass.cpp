#include "passes/SurfaceTilePass.h"

#include "engine/ShaderBindings.h"
#include "engine/Targets.h"

namespace gpu {

SurfaceTilePass::SurfaceTilePass(const ShaderLoader& shaders, int tile)
    : mTile(tile),
      mProgram(shaders.load({.stages = {{GL_COMPUTE_SHADER, "surface-tiles.comp"}},
                             .defines = {"SURFACE_TILE " + std::to_string(tile)},
                             .label = "surface-tiles"})) {}

glm::ivec2 SurfaceTilePass::dispatch(const Targets& t) {
    const glm::ivec2 tiles((t.width + mTile - 1) / mTile, (t.height + mTile - 1) / mTile);
    const std::size_t bytes = 2 * static_cast<std::size_t>(tiles.x) * tiles.y * sizeof(glm::vec4);
    if (mTiles.size() < bytes)
        mTiles = Buffer({.size = bytes, .flags = 0, .label = "surface-tiles"});
    glUseProgram(mProgram.id());
    glBindTextureUnit(TEXUNIT_POSITION, t.position.id());
    bind();
    glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_FRAMEBUFFER_BARRIER_BIT);
    glUniform1i(0, tiles.x);
    glDispatchCompute(static_cast<GLuint>((tiles.x + 7) / 8), static_cast<GLuint>(tiles.y), 1);
    return tiles;
}

void SurfaceTilePass::bind(GLuint binding) const {
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, binding, mTiles.id());
}

SurfaceTiles SurfaceTilePass::measure(const Targets& t) {
    SurfaceTiles out;
    out.tile = mTile;
    const glm::ivec2 n = dispatch(t);
    out.tilesX = n.x;
    out.tilesY = n.y;
    const std::size_t tiles = static_cast<std::size_t>(out.tilesX) * out.tilesY;
    const std::size_t bytes = 2 * tiles * sizeof(glm::vec4);
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
