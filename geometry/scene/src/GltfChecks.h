// What the glTF loader checks itself, before and around tinygltf: the parts of a document the
// library reads unchecked (a bufferView past its buffer is dereferenced while images are
// decoded), reads wrongly (a negative byteOffset becomes 0, '+' in a URI becomes a space) or
// replaces by defaults without a word (a malformed pbrMetallicRoughness loses its texture), and
// the decoding of images, which here checks dimensions and a pixel budget before any pixel is
// decoded. Every refusal is an InputError naming the key.
#pragma once

#include <nlohmann/json.hpp>

#include <cstddef>
#include <optional>
#include <string>

namespace tinygltf {
struct Image;
}

namespace geometry::detail {

// Refuses, naming the key, what tinygltf would crash on or silently get wrong: extensions the
// loader does not read in extensionsRequired; buffers, bufferViews and accessors whose
// offsets, lengths or indices are not non-negative integers in range; materials whose alpha and
// PBR keys are malformed (factors of the wrong length, values that are not finite as float,
// alphaCutoff below 0, texture infos without an integer index). `origin` prefixes every message.
void checkGltfDocument(const std::string& origin, const nlohmann::json& doc);

// A URI reference decoded as RFC 3986 says (what glTF's URIs are): "%XX" escapes only; '+' is
// a plus sign. Empty when an escape is malformed ('%' not followed by two hex digits).
std::optional<std::string> percentDecode(const std::string& uri);

// The decoding tinygltf applies to a URI before using it as a file name: "%XX" escapes, and
// '+' read as a space (form encoding, which glTF's URIs are not).
std::string tinygltfDecode(const std::string& uri);

// tinygltf's image callback (tinygltf::LoadImageDataFunction, user data: an ImageDecoder):
// reads the dimensions from the PNG or JPEG header, refuses images over kMaxTextureSide on a
// side or past the file's pixel budget (kMaxTexturePixels) before decoding, then decodes to 8
// bits per channel. On a refusal it returns false and keeps the message for the loader, which
// throws it in place of tinygltf's.
class ImageDecoder {
public:
    static bool decode(tinygltf::Image* image, int index, std::string* err, std::string* warn,
                       int reqWidth, int reqHeight, const unsigned char* bytes, int size,
                       void* self);
    // The first refusal, "images[2] (leaf.png): ..."; empty when none.
    const std::string& refusal() const { return mRefusal; }

private:
    bool refuse(const std::string& what, std::string* err);
    std::size_t mPixels = 0; // decoded so far, every image of the file
    std::string mRefusal;
};

} // namespace geometry::detail
