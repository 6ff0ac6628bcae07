// PFM and PNG files. PFM is the standard Portable Float Map: "Pf" (1 channel) or "PF" (3),
// "width height", a scale whose sign gives the byte order (negative = little endian), then rows
// from the bottom of the image to the top. Our images are top to bottom, so rows are flipped on
// both read and write. PNG goes through stb_image_write (implementation inside Debian's libstb).
#include <geometry/scene/ImageIO.h>

#include <geometry/core/Error.h>

#include <stb_image.h>
#include <stb_image_write.h>

#include <bit>
#include <cctype>
#include <cmath>
#include <algorithm>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <stdexcept>
#include <string>

namespace geometry {
namespace {

std::uint32_t byteSwap(std::uint32_t x) {
    return (x >> 24) | ((x >> 8) & 0x0000ff00u) | ((x << 8) & 0x00ff0000u) | (x << 24);
}

// Reads one whitespace-delimited header token starting at `pos`.
std::string headerToken(const std::string& bytes, std::size_t& pos) {
    while (pos < bytes.size() && std::isspace(static_cast<unsigned char>(bytes[pos])))
        ++pos;
    const std::size_t start = pos;
    // Header tokens are short; a long run means binary garbage, not a PFM header.
    while (pos < bytes.size() && !std::isspace(static_cast<unsigned char>(bytes[pos])) &&
           pos - start < 64) {
        ++pos;
    }
    return bytes.substr(start, pos - start);
}

} // namespace

void writePfm(const std::filesystem::path& path, const FloatImage& image) {
    if (image.channels != 1 && image.channels != 3) {
        throw std::runtime_error("writePfm " + path.string() + ": channels must be 1 or 3, got " +
                                 std::to_string(image.channels));
    }
    if (image.width <= 0 || image.height <= 0 ||
        image.data.size() != std::size_t(image.width) * image.height * image.channels) {
        throw std::runtime_error("writePfm " + path.string() + ": data size does not match " +
                                 std::to_string(image.width) + "x" + std::to_string(image.height) +
                                 "x" + std::to_string(image.channels));
    }
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    if (!out) throw std::runtime_error("writePfm: cannot open " + path.string() + " for writing");

    out << (image.channels == 3 ? "PF" : "Pf") << "\n"
        << image.width << " " << image.height << "\n-1.0\n";
    const std::size_t rowFloats = std::size_t(image.width) * image.channels;
    std::vector<std::uint32_t> row(rowFloats);
    for (int y = image.height - 1; y >= 0; --y) {
        std::memcpy(row.data(), image.data.data() + y * rowFloats, rowFloats * sizeof(float));
        // The file is always little endian ("-1.0"), whatever the host is.
        if constexpr (std::endian::native == std::endian::big) {
            for (auto& w : row)
                w = byteSwap(w);
        }
        out.write(reinterpret_cast<const char*>(row.data()),
                  static_cast<std::streamsize>(rowFloats * sizeof(float)));
    }
    out.close();
    if (!out) throw std::runtime_error("writePfm: failed writing " + path.string());
}

// The size of the regular file at `path`; an InputError for anything else (a device or FIFO
// would be read forever, a folder cannot be).
std::uintmax_t regularFileSize(const std::filesystem::path& path, const char* what) {
    std::error_code ec;
    const auto status = std::filesystem::status(path, ec);
    if (!std::filesystem::exists(status))
        throw InputError(path.string() + ": " + what + " file not found");
    if (!std::filesystem::is_regular_file(status))
        throw InputError(path.string() + ": not a regular file (a device, FIFO, socket or " +
                         "folder); a " + what + " must be a file");
    const std::uintmax_t size = std::filesystem::file_size(path, ec);
    if (ec) throw InputError(path.string() + ": cannot read the size of the " + what + " file");
    return size;
}

FloatImage readPfm(const std::filesystem::path& path) {
    const std::uintmax_t fileSize = regularFileSize(path, "PFM");
    std::ifstream in(path, std::ios::binary);
    if (!in) throw InputError(path.string() + ": cannot open PFM file");
    // The header first: the raster is read only once the header's dimensions account for every
    // byte of the file (a file of gigabytes after a 64 x 64 header is refused unread).
    constexpr std::uintmax_t kHeaderBytes = 4096;
    std::string bytes(std::size_t(std::min(fileSize, kHeaderBytes)), '\0');
    in.read(bytes.data(), std::streamsize(bytes.size()));
    if (!in) throw InputError(path.string() + ": cannot read PFM file");
    auto fail = [&](const std::string& what) {
        return InputError(path.string() + ": malformed PFM: " + what);
    };

    std::size_t pos = 0;
    const std::string magic = headerToken(bytes, pos);
    FloatImage image;
    if (magic == "PF") {
        image.channels = 3;
    } else if (magic == "Pf") {
        image.channels = 1;
    } else {
        throw fail("bad magic (expected \"PF\" or \"Pf\")");
    }

    auto parseInt = [&](const std::string& tok, const char* what) {
        if (tok.empty() || tok.size() > 9 ||
            tok.find_first_not_of("0123456789") != std::string::npos) {
            throw fail(std::string("bad ") + what + " \"" + tok + "\"");
        }
        const int value = std::stoi(tok);
        if (value <= 0) throw fail(std::string(what) + " must be > 0");
        return value;
    };
    image.width = parseInt(headerToken(bytes, pos), "width");
    image.height = parseInt(headerToken(bytes, pos), "height");

    const std::string scaleTok = headerToken(bytes, pos);
    double scale = 0.0;
    try {
        std::size_t used = 0;
        scale = std::stod(scaleTok, &used);
        if (used != scaleTok.size()) throw std::invalid_argument("trailing characters");
    } catch (const std::exception&) {
        throw fail("bad scale \"" + scaleTok + "\"");
    }
    if (!std::isfinite(scale) || scale == 0.0) throw fail("scale must be finite and non-zero");
    // Exactly one whitespace character separates the header from the raster.
    if (pos >= bytes.size() || !std::isspace(static_cast<unsigned char>(bytes[pos]))) {
        throw fail("missing data after header");
    }
    ++pos;

    const std::size_t rowFloats = std::size_t(image.width) * image.channels;
    const std::size_t count = rowFloats * std::size_t(image.height);
    const std::size_t expected = count * sizeof(float);
    const std::uintmax_t available = fileSize - pos;
    if (available < expected) {
        throw fail("truncated data: expected " + std::to_string(expected) + " bytes for " +
                   std::to_string(image.width) + "x" + std::to_string(image.height) + ", got " +
                   std::to_string(available));
    }
    if (available > expected) {
        throw fail(std::to_string(available - expected) + " unexpected bytes after the data");
    }
    const std::size_t headerRead = bytes.size();
    bytes.resize(std::size_t(fileSize));
    in.read(bytes.data() + headerRead, std::streamsize(bytes.size() - headerRead));
    if (!in && bytes.size() > headerRead)
        throw InputError(path.string() + ": cannot read PFM file");

    const bool fileLittle = scale < 0.0;
    const bool swap = fileLittle != (std::endian::native == std::endian::little);
    image.data.resize(count);
    for (int fileRow = 0; fileRow < image.height; ++fileRow) {
        const int y = image.height - 1 - fileRow; // file rows run bottom to top
        for (std::size_t i = 0; i < rowFloats; ++i) {
            std::uint32_t w;
            std::memcpy(&w, bytes.data() + pos + (fileRow * rowFloats + i) * sizeof(float),
                        sizeof(w));
            if (swap) w = byteSwap(w);
            std::memcpy(&image.data[y * rowFloats + i], &w, sizeof(float));
        }
    }
    return image;
}

void writePng(const std::filesystem::path& path, int width, int height, int channels,
              const std::uint8_t* pixels) {
    if (channels < 1 || channels > 4 || width <= 0 || height <= 0 || pixels == nullptr) {
        throw std::runtime_error("writePng " + path.string() + ": invalid image " +
                                 std::to_string(width) + "x" + std::to_string(height) + "x" +
                                 std::to_string(channels));
    }
    // Encode to memory and write ourselves: stb's file writer gives no error detail and takes a
    // narrow path string.
    std::string encoded;
    auto sink = [](void* context, void* data, int size) {
        static_cast<std::string*>(context)->append(static_cast<const char*>(data),
                                                   static_cast<std::size_t>(size));
    };
    if (!stbi_write_png_to_func(sink, &encoded, width, height, channels, pixels,
                                width * channels)) {
        throw std::runtime_error("writePng " + path.string() + ": PNG encoding failed");
    }
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    if (!out) throw std::runtime_error("writePng: cannot open " + path.string() + " for writing");
    out.write(encoded.data(), static_cast<std::streamsize>(encoded.size()));
    out.close();
    if (!out) throw std::runtime_error("writePng: failed writing " + path.string());
}

Rgba8Image readPng(const std::filesystem::path& path) {
    regularFileSize(path, "PNG");
    std::ifstream in(path, std::ios::binary);
    if (!in) throw InputError(path.string() + ": cannot open PNG");
    const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    int w = 0, h = 0, n = 0;
    stbi_uc* pixels = stbi_load_from_memory(reinterpret_cast<const stbi_uc*>(bytes.data()),
                                            static_cast<int>(bytes.size()), &w, &h, &n, 4);
    if (!pixels)
        throw InputError(path.string() + ": not a decodable PNG (" + stbi_failure_reason() + ")");
    Rgba8Image image{w, h, {}};
    image.rgba.assign(pixels, pixels + static_cast<std::size_t>(w) * h * 4);
    stbi_image_free(pixels);
    return image;
}

} // namespace geometry
