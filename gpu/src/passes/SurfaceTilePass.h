// The world bounds of the visible surface per screen tile, measured from the G-buffer on the GPU
// and read back: what depth-aware culling (methods/GroupBatches.h) tests each silhouette group's
// reach against.
#pragma once

#include <gpu/gl/Objects.h>
#include <gpu/gl/ShaderLoader.h>

#include "engine/ShaderBindings.h"

#include <geometry/core/Types.h>

#include <glm/glm.hpp>

#include <vector>

namespace gpu {

struct Targets;

// World bounds of the visible surface per tile of `tile` x `tile` pixels, row by row from the
// bottom left; an empty box where a tile has no surface pixel.
struct SurfaceTiles {
    int tile = 16, tilesX = 0, tilesY = 0;
    std::vector<geometry::Aabb> boxes;
};

// Measures SurfaceTiles from the G-buffer's positions (shaders/surface-tiles.comp) and reads
// them back: the CPU batching needs them before the batches' passes (a wait for the G-buffer).
class SurfaceTilePass {
public:
    static constexpr int kTile = 16; // pixels per tile side (shaders/surface-tiles.comp)
    // `tile`: pixels per tile side (kTile for the batching; WedgeTilePass its own).
    explicit SurfaceTilePass(const ShaderLoader& shaders, int tile = kTile);
    SurfaceTiles measure(const Targets& t);
    // The same on the GPU only, bound at BINDING_SURFACE_TILES, not read back (the tiled wedge
    // evaluation bins on the GPU); tiles across and down.
    glm::ivec2 dispatch(const Targets& t);
    // Binds the last dispatch's (or measure's) tiles at `binding`.
    void bind(GLuint binding = BINDING_SURFACE_TILES) const;

private:
    int mTile = kTile;
    Program mProgram;
    Buffer mTiles;
    std::vector<glm::vec4> mScratch;
};

} // namespace gpu
