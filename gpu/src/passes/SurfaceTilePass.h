// The world bounds of the visible surface per screen tile, measured from the G-buffer on the GPU
// and read back: what depth-aware culling (methods/GroupBatches.h) tests each silhouette group's
// reach against.
#pragma once

#include <gpu/gl/Objects.h>
#include <gpu/gl/ShaderLoader.h>

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
    explicit SurfaceTilePass(const ShaderLoader& shaders);
    SurfaceTiles measure(const Targets& t);

private:
    Program mProgram;
    Buffer mTiles;
    std::vector<glm::vec4> mScratch;
};

} // namespace gpu
