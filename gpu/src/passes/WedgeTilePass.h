// wedges-bitmask silhouettes=potential evaluate=tiles: the wedge pass without rasterising the
// hulls. The hulls are binned to the 8 x 8 pixel tiles whose visible surface they may reach
// (shaders/wedge-tiles.comp, against SurfaceTilePass's boxes per tile and per 32 x 32
// super-tile), then one compute invocation per
// pixel runs over its tile's list with the fragment shader's own arithmetic
// (shaders/lib/BitmaskEdge.glsl) and writes the counts, checksums and areas that the raster
// pass's atomics and blending would leave (shaders/wedge-bitmask-tiles.comp), for the same
// resolve. The raster pass runs the fragment shader for every pixel where a hull's entry face
// lies in front of the surface; on a curved caster most of those rays leave the hull before
// they reach the surface (nine in ten on data/sphere.json), and a tile's surface box rules most
// of them out before any pixel work.
#pragma once

#include <gpu/gl/Objects.h>
#include <gpu/gl/ShaderLoader.h>

#include "engine/CasterSet.h"
#include "engine/Targets.h"
#include "passes/SurfaceTilePass.h"

#include <cstdint>
#include <string>
#include <vector>

namespace gpu {

struct WedgeTileStats {
    std::uint64_t entries = 0;    // (tile, wedge) list entries
    std::uint64_t pairsAdded = 0; // (pixel, wedge) pairs that added something (the raster
                                  // pass's fragments that passed its discards)
    std::uint64_t tiles = 0;
    std::uint64_t activeTiles = 0; // tiles whose list is not empty: the evaluation's work groups
    // Invocations that stopped at WEDGE_TILES_LOOP_BUDGET (a slot's binning or a pixel's
    // list): the frame was rasterised instead.
    std::uint64_t truncated = 0;
    // 1 where the count stage's entries did not fit the buffer that records them (the first
    // tiled frame, or one with many more entries than the last): the fill stage tested every
    // slot's tiles again instead of placing the recorded entries.
    std::uint64_t refilled = 0;
    // estimate=moments: pixels whose samples see two or more layer counts and that kept their
    // regions for P (wedge-moments.comp), and 1 where the moments buffer was too small for
    // them and the evaluation ran again with room for all.
    std::uint64_t momentPixels = 0;
    std::uint64_t momentRerun = 0;
};

class WedgeTilePass {
public:
    // `defines`: the evaluation's (BITMASK_SAMPLES, BITMASK_POTENTIAL, ...).
    WedgeTilePass(const ShaderLoader& shaders, const std::vector<std::string>& defines);

    // After WedgePass::setup of `set` (its wedges bound at BINDING_WEDGES, the potential set's
    // arrays bound): bins the slots of `set` (`slots` wedge slots in all) and evaluates every
    // pixel into the counts image bound at IMAGE_GROUP_COUNTS (the biased counts, two checksum
    // layers, the mark layer; with `moments`, estimate=moments, the second moment of the
    // wedges' sum per pixel in the layer after it, which reads the stencil view bound at
    // TEXUNIT_STENCIL) and `area`. `samples`: the light-samples table. Reads back the lists'
    // total to size them, and the counters after. False where the counts would be incomplete:
    // the lists would pass what a buffer texture holds (GL_MAX_TEXTURE_BUFFER_SIZE texels) or
    // `entryLimit` entries where that is not 0, or an invocation would pass its loop budget
    // (WEDGE_TILES_LOOP_BUDGET: a tile's list too long for one pixel's loop on llvmpipe); the
    // caller rasterises instead.
    bool run(const Targets& t, const DrawSet& set, std::uint32_t slots, const Texture& area,
             const Buffer& samples, std::size_t entryLimit = 0, bool moments = false);
    // The last run's counters (read back by run).
    const WedgeTileStats& stats() const { return mStats; }

private:
    static constexpr int kTile = 8; // pixels per tile side (WEDGE_TILE)
    SurfaceTilePass mSurface, mSupertiles; // per tile, per 32 x 32 pixels
    Program mRecord, mCount, mScan, mFill, mPlace, mEvaluate, mMoments;
    Buffer mRecords, mLists, mPairs, mMomentBuffer; // (moments: MOMENT_SLOT_UINTS per pixel)
    glm::ivec2 mTiles{0};
    std::uint32_t mEntries = 0;
    WedgeTileStats mStats;
    std::size_t mMaxTexels = 0; // GL_MAX_TEXTURE_BUFFER_SIZE
    std::vector<std::uint32_t> mSlots;
    // The records and lists as buffer textures (re-attached when a buffer is reallocated).
    struct TextureDeleter {
        void operator()(GLuint id) const { glDeleteTextures(1, &id); }
    };
    Handle<TextureDeleter> mRecordTexels, mListTexels;
};

} // namespace gpu
