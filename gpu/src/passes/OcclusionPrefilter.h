// Occlusion textures, prefilters (Eisemann & Décoret 2006 §3.2) of the slices the slicing pass
// drew, so that the lookup reads a box-filtered mean in a few fetches:
// - NBufferPass: level l = mean over 2^l × 2^l windows, each level from the one below with four
//   reads (compute, image load/store on one RGBA16 array: levels × targets layers).
// - SatPass: integer summed-area tables (compute: rows, then columns; RGBA32UI, R + 1 square).
// (Mipmaps need no pass of ours: glGenerateTextureMipmap.)
#pragma once

#include <gpu/gl/ShaderLoader.h>

namespace gpu {

class NBufferPass {
public:
    NBufferPass(const ShaderLoader& shaders, int slices);
    // Builds levels 1..topLevel of `levels` (layer l * targets + t; level 0 drawn already).
    void execute(const Texture& levels, int topLevel) const;

private:
    Program mProgram;
};

class SatPass {
public:
    explicit SatPass(const ShaderLoader& shaders);
    // `sat` (R + 1 square, one layer per target) from `slices` (R square, RGBA8).
    void execute(const Texture& slices, const Texture& sat) const;

private:
    Program mProgram;
};

} // namespace gpu
