// Image files: PFM (Portable Float Map) and 8-bit PNG (stb_image_write / stb_image).
// In memory, images are rows top to bottom; PFM stores rows bottom to top, little endian
// (negative scale), and the writers/readers convert.
#pragma once

#include <cstdint>
#include <filesystem>
#include <vector>

namespace geometry {

struct FloatImage {
    int width = 0;
    int height = 0;
    int channels = 1; // 1 (Pf) or 3 (PF)
    std::vector<float> data; // width * height * channels, rows top to bottom
};

void writePfm(const std::filesystem::path& path, const FloatImage& image); // throws runtime_error
FloatImage readPfm(const std::filesystem::path& path); // throws InputError on a malformed file

// RGB8 or RGBA8 (channels 3 or 4), rows top to bottom. Throws runtime_error on failure.
void writePng(const std::filesystem::path& path, int width, int height, int channels,
              const std::uint8_t* pixels);

// An 8-bit PNG read back as RGBA8 (any PNG stb_image decodes; grey/RGB expanded), rows top to
// bottom. Throws InputError for a missing or undecodable file.
struct Rgba8Image {
    int width = 0;
    int height = 0;
    std::vector<std::uint8_t> rgba; // width * height * 4
};
Rgba8Image readPng(const std::filesystem::path& path);

} // namespace geometry
