#include "passes/WedgeTilePass.h"

#include "engine/ShaderBindings.h"

#include <shared/Spread.h>

#include <algorithm>
#include <array>
#include <stdexcept>
#include <string>

namespace gpu {

namespace {

constexpr std::size_t kTileWedgeBytes = 12 * 16; // TileWedge (shaders/lib/WedgeTiles.glsl)
constexpr std::size_t kPairBytes = 3 * 4;         // a recorded entry (BINDING_WEDGE_TILE_PAIRS)
constexpr std::size_t kMaxPairs = std::size_t(1) << 24; // 192 MiB of recorded entries
constexpr std::size_t kMomentSlotBytes = MOMENT_SLOT_UINTS * 4; // a pixel's edges for P
constexpr std::size_t kFirstMomentSlots = 1024; // the moments buffer before a frame needs more

// `groups` work groups of the bound compute program in rows of at most 32768 (GL guarantees
// 65535 per dimension; a 4K frame has 129 600 tiles): the shader numbers them
// gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x and returns past its count.
void dispatchRows(GLuint groups) {
    constexpr GLuint kMaxGroupsX = 32768;
    const GLuint groupsX = std::min(groups, kMaxGroupsX);
    glDispatchCompute(groupsX, (groups + groupsX - 1) / groupsX, 1);
}

Program binning(const ShaderLoader& shaders, int stage, int tile, const char* label) {
    return shaders.load({.stages = {{GL_COMPUTE_SHADER, "wedge-tiles.comp"}},
                         .defines = {"WEDGE_TILES_STAGE " + std::to_string(stage),
                                     "WEDGE_TILE " + std::to_string(tile)},
                         .label = label});
}

std::vector<std::string> withTile(std::vector<std::string> defines, int tile) {
    defines.push_back("WEDGE_TILE " + std::to_string(tile));
    return defines;
}

// The evaluation counts its loops per SIMD vector by votes (wedge-bitmask-tiles.comp): every
// desktop GL 4.5 driver has the extension, llvmpipe included; a clear error where one does not.
const ShaderLoader& withGroupVote(const ShaderLoader& shaders) {
    if (!epoxy_has_gl_extension("GL_ARB_shader_group_vote")) {
        const auto* renderer = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
        throw std::runtime_error(
            std::string("wedges-bitmask's tiled evaluation needs GL_ARB_shader_group_vote, which ") +
            (renderer ? renderer : "this GL renderer") +
            " lacks: render with --param evaluate=raster --param estimate=quadrants");
    }
    return shaders;
}

} // namespace

WedgeTilePass::WedgeTilePass(const ShaderLoader& shaders, const std::vector<std::string>& defines)
    : mSurface(withGroupVote(shaders), kTile),
      mSupertiles(shaders, 32),
      mRecord(binning(shaders, 0, kTile, "wedge-tiles-record")),
      mCount(binning(shaders, 1, kTile, "wedge-tiles-count")),
      mScan(binning(shaders, 2, kTile, "wedge-tiles-scan")),
      mFill(binning(shaders, 3, kTile, "wedge-tiles-fill")),
      mPlace(binning(shaders, 4, kTile, "wedge-tiles-place")),
      mEvaluate(shaders.load({.stages = {{GL_COMPUTE_SHADER, "wedge-bitmask-tiles.comp"}},
                              .defines = withTile(defines, kTile),
                              .label = "wedge-bitmask-tiles"})),
      mMoments(shaders.load({.stages = {{GL_COMPUTE_SHADER, "wedge-moments.comp"}},
                             .defines = defines,
                             .label = "wedge-moments"})) {
    GLint texels = 0;
    glGetIntegerv(GL_MAX_TEXTURE_BUFFER_SIZE, &texels);
    mMaxTexels = static_cast<std::size_t>(std::max(texels, 0));
}

bool WedgeTilePass::run(const Targets& t, const DrawSet& set, std::uint32_t slots,
                        const Texture& area, const Buffer& samples, std::size_t entryLimit,
                        bool moments) {
    mSupertiles.dispatch(t);
    mSupertiles.bind(BINDING_WEDGE_SUPERTILES);
    mTiles = mSurface.dispatch(t);
    const std::size_t tiles = static_cast<std::size_t>(mTiles.x) * mTiles.y;
    const std::size_t headWords = 4 * tiles + WEDGE_TILES_HEADER;
    // The set's slots as one list (a level's set is a hundred runs of kept edges: one dispatch
    // per stage instead of one per run).
    mSlots.clear();
    for (std::size_t r = 0; r < set.edgeFirst.size(); ++r)
        for (GLsizei i = 0; i < set.edgeCount[r]; ++i)
            mSlots.push_back(static_cast<std::uint32_t>(set.edgeFirst[r] + i));
    const std::size_t listBase = headWords + mSlots.size();
    const std::size_t recordBytes = std::max<std::size_t>(slots, 1) * kTileWedgeBytes;
    mStats = WedgeTileStats{.tiles = tiles};
    if (recordBytes / 16 > mMaxTexels || listBase > mMaxTexels) return false;
    if (mRecords.size() < recordBytes)
        mRecords = Buffer({.size = recordBytes, .flags = 0, .label = "wedge-tile-records"});
    // Sized for the lists of the last frame, grown below when this frame's are longer.
    const std::size_t guess = (listBase + std::max<std::size_t>(mEntries, 1)) * 4;
    if (mLists.size() < guess)
        mLists = Buffer({.size = guess + guess / 2, .label = "wedge-tile-lists"});
    const GLuint zero = 0;
    glClearNamedBufferSubData(mLists.id(), GL_R32UI, 0, static_cast<GLsizeiptr>(headWords * 4),
                              GL_RED_INTEGER, GL_UNSIGNED_INT, &zero);
    if (!mSlots.empty()) mLists.upload(mSlots.data(), mSlots.size() * 4, headWords * 4);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BINDING_WEDGE_TILE_RECORDS, mRecords.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BINDING_WEDGE_TILE_LISTS, mLists.id());
    // The count stage records its entries for the place stage while they fit: room for the
    // last frame's, and half as many again (at most kMaxPairs: a frame with more refills).
    const std::size_t pairCapacity =
        std::clamp<std::size_t>(mEntries + mEntries / 2, 4096, kMaxPairs);
    if (mPairs.size() < pairCapacity * kPairBytes)
        mPairs = Buffer({.size = pairCapacity * kPairBytes, .flags = 0, .label = "wedge-tile-pairs"});
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BINDING_WEDGE_TILE_PAIRS, mPairs.id());
    glProgramUniform1ui(mCount.id(), 5, static_cast<GLuint>(mPairs.size() / kPairBytes));
    const GLint size[2] = {t.width, t.height};
    const auto slotCount = static_cast<GLuint>(mSlots.size());
    const auto useBinning = [&](const Program& program) {
        glUseProgram(program.id());
        glUniform2ui(0, static_cast<GLuint>(headWords), slotCount);
        glUniform2i(1, mTiles.x, mTiles.y);
        glUniform2iv(2, 1, size);
        glUniform1ui(3, static_cast<GLuint>(listBase));
    };
    const auto binning = [&](const Program& program, GLuint groups) {
        useBinning(program);
        glDispatchCompute(groups, 1, 1);
    };
    // The slots' records, a count per tile, then first entries by a prefix sum.
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
    if (slotCount > 0) binning(mRecord, (slotCount + 63) / 64);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
    // The count and fill stages: WEDGE_TILES_SLOT_GROUP slots per work group, the groups in
    // spread order (shared/Spread.h; wedge-tiles.comp says why).
    const GLuint slotGroups = (slotCount + WEDGE_TILES_SLOT_GROUP - 1) / WEDGE_TILES_SLOT_GROUP;
    const GLuint slotSpread = ::shader::spreadStride(slotGroups);
    const auto perSlot = [&](const Program& program) {
        useBinning(program);
        glUniform1ui(6, slotSpread);
        dispatchRows(slotGroups);
    };
    if (slotCount > 0) perSlot(mCount);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
    for (GLint step = 0; step < 3; ++step) {
        glProgramUniform1i(mScan.id(), 4, step);
        binning(mScan, (static_cast<GLuint>(mTiles.y) + 63) / 64);
        glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
    }
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT | GL_SHADER_STORAGE_BARRIER_BIT);
    // The lists' length decides the buffer's: the total and its flags read back.
    std::array<std::uint32_t, WEDGE_TILES_HEADER> header{};
    glGetNamedBufferSubData(mLists.id(), static_cast<GLintptr>(3 * tiles * 4),
                            static_cast<GLsizeiptr>(sizeof(header)), header.data());
    mStats.truncated = header[WEDGE_TILES_TRUNCATED];
    if (header[WEDGE_TILES_OVERFLOW] != 0 || header[WEDGE_TILES_TRUNCATED] != 0 ||
        listBase + header[WEDGE_TILES_TOTAL] > mMaxTexels ||
        (entryLimit > 0 && header[WEDGE_TILES_TOTAL] > entryLimit)) {
        mEntries = 0;
        return false;
    }
    mEntries = header[WEDGE_TILES_TOTAL];
    mStats.activeTiles = header[WEDGE_TILES_ACTIVE];
    const std::size_t needed = (listBase + std::max<std::size_t>(mEntries, 1)) * 4;
    if (mLists.size() < needed) {
        Buffer grown({.size = needed + needed / 2, .label = "wedge-tile-lists"});
        glCopyNamedBufferSubData(mLists.id(), grown.id(), 0, 0, static_cast<GLsizeiptr>(listBase * 4));
        mLists = std::move(grown);
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BINDING_WEDGE_TILE_LISTS, mLists.id());
    }
    // Every entry into its tile's list: from the count stage's record (one invocation per
    // entry, in rows of work groups), or, where they did not all fit, by testing
    // every slot's tiles again (counted: wedge_tiles_refilled; the next frame has room).
    const std::uint32_t recorded = header[WEDGE_TILES_RECORDED];
    mStats.refilled = recorded > mPairs.size() / kPairBytes ? 1 : 0;
    if (mStats.refilled != 0) {
        if (slotCount > 0) perSlot(mFill);
    } else if (recorded > 0) {
        glUseProgram(mPlace.id());
        glUniform2i(1, mTiles.x, mTiles.y);
        glUniform1ui(3, static_cast<GLuint>(listBase));
        dispatchRows((recorded + 63) / 64);
    }
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
    // Every pixel over its tile's list, reading records and lists as texels.
    const auto texels = [](Handle<TextureDeleter>& tex, GLenum format, const Buffer& buffer,
                           GLuint unit) {
        if (!tex) {
            GLuint id = 0;
            glCreateTextures(GL_TEXTURE_BUFFER, 1, &id);
            tex = Handle<TextureDeleter>(id);
        }
        glTextureBuffer(tex.id(), format, buffer.id());
        glBindTextureUnit(unit, tex.id());
    };
    texels(mRecordTexels, GL_RGBA32F, mRecords, TEXUNIT_WEDGE_TILE_RECORDS);
    texels(mListTexels, GL_R32UI, mLists, TEXUNIT_WEDGE_TILE_LISTS);
    // The light-samples table as a uniform block (lib/Bindings.h BINDING_LIGHT_SAMPLES_UBO; its
    // size checked where it is made).
    glBindBufferBase(GL_UNIFORM_BUFFER, BINDING_LIGHT_SAMPLES_UBO, samples.id());
    glUseProgram(mEvaluate.id());
    glUniform2i(1, mTiles.x, mTiles.y);
    glUniform2iv(2, 1, size);
    glUniform1ui(3, static_cast<GLuint>(listBase));
    glUniform1ui(4, moments ? 1u : 0u);
    glBindTextureUnit(TEXUNIT_POSITION, t.position.id());
    glBindImageTexture(IMAGE_BITMASK_AREA, area.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32F);
    // estimate=moments: the slots for the pixels that need P (their edges), at least `wanted`,
    // bound; how many the buffer holds (grown where a frame needed more: its size carries over).
    const auto momentSlots = [&](std::size_t wanted) {
        if (mMomentBuffer.size() < wanted * kMomentSlotBytes)
            mMomentBuffer = Buffer({.size = wanted * kMomentSlotBytes, .flags = 0,
                                    .label = "wedge-tile-moments"});
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BINDING_WEDGE_TILE_MOMENTS, mMomentBuffer.id());
        return mMomentBuffer.size() / kMomentSlotBytes;
    };
    std::size_t slotsHeld = momentSlots(kFirstMomentSlots);
    glUniform1ui(5, static_cast<GLuint>(moments ? slotsHeld : 0));
    // One work group per tile whose list is not empty (their number read back with the total);
    // the other pixels' mark layer is the caller's clear.
    const GLuint active = header[WEDGE_TILES_ACTIVE];
    glUniform1ui(6, ::shader::spreadStride(active)); // the groups' order (shared/Spread.h)
    if (active > 0) dispatchRows(active);
    glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT |
                    GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
    // The evaluation's counters; a pixel that ran out of its loop budget makes the frame's
    // counts incomplete: the caller rasterises instead.
    glGetNamedBufferSubData(mLists.id(), static_cast<GLintptr>(3 * tiles * 4),
                            static_cast<GLsizeiptr>(sizeof(header)), header.data());
    mStats.momentRerun = 0;
    const std::size_t momentNeeded = header[WEDGE_TILES_MOMENT_PIXELS];
    if (moments && momentNeeded > slotsHeld && header[WEDGE_TILES_TRUNCATED] == 0) {
        // More pixels needed P than there were slots: the evaluation again with room for all
        // (it overwrites everything it wrote; its counters start again), so that no pixel
        // loses its moment to the buffer's size. Counted: wedge_moment_reruns.
        slotsHeld = momentSlots(momentNeeded + momentNeeded / 2);
        glUniform1ui(5, static_cast<GLuint>(slotsHeld));
        for (const int counter : {WEDGE_TILES_PAIRS_ADDED, WEDGE_TILES_MOMENT_PIXELS})
            glClearNamedBufferSubData(mLists.id(), GL_R32UI,
                                      static_cast<GLintptr>((3 * tiles + counter) * 4), 4,
                                      GL_RED_INTEGER, GL_UNSIGNED_INT, &zero);
        glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
        dispatchRows(active);
        glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT |
                        GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
        glGetNamedBufferSubData(mLists.id(), static_cast<GLintptr>(3 * tiles * 4),
                                static_cast<GLsizeiptr>(sizeof(header)), header.data());
        mStats.momentRerun = 1;
    }
    mStats.entries = mEntries;
    mStats.pairsAdded = header[WEDGE_TILES_PAIRS_ADDED];
    mStats.truncated = header[WEDGE_TILES_TRUNCATED];
    mStats.momentPixels = moments ? header[WEDGE_TILES_MOMENT_PIXELS] : 0;
    if (mStats.truncated != 0) return false;
    // P for the pixels with a slot, one invocation each.
    const auto slotsUsed =
        static_cast<GLuint>(std::min<std::size_t>(mStats.momentPixels, slotsHeld));
    if (slotsUsed > 0) {
        const GLuint groups = (slotsUsed + 63) / 64;
        glUseProgram(mMoments.id());
        glUniform1ui(0, slotsUsed);
        glUniform1ui(1, ::shader::spreadStride(groups));
        dispatchRows(groups);
        glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT);
    }
    return true;
}

} // namespace gpu
