#include "GltfChecks.h"

#include <geometry/core/Error.h>
#include <geometry/core/Limits.h>

#include <tiny_gltf.h>

#include <stb_image.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <sstream>
#include <string_view>

namespace geometry::detail {
namespace {

using Json = nlohmann::json;

// Extensions whose absence from the loader changes only shading, never geometry, masks or
// which image a texture reads: a file requiring them still loads.
bool harmlessExtension(const std::string& name) {
    return name.rfind("KHR_materials_", 0) == 0 || name == "KHR_texture_transform" ||
           name == "KHR_lights_punctual";
}

// What a required extension the loader does not read would change, for the message.
std::string extensionEffect(const std::string& name) {
    if (name == "KHR_draco_mesh_compression") return "Draco-compressed geometry";
    if (name == "EXT_meshopt_compression") return "meshopt-compressed buffers";
    if (name == "KHR_mesh_quantization") return "quantized vertex attributes";
    if (name == "KHR_texture_basisu") return "Basis Universal (KTX2) textures";
    if (name == "EXT_texture_webp") return "WebP textures";
    if (name == "EXT_mesh_gpu_instancing") return "instanced nodes";
    return "";
}

// "0", "1", "inf": a bound for a message.
std::string text(double x) {
    std::ostringstream s;
    s << x;
    return s.str();
}

// The checks of one document, each message "ORIGIN: KEY ...".
class DocumentCheck {
public:
    DocumentCheck(const std::string& origin, const Json& doc) : mOrigin(origin), mDoc(doc) {}

    void run() {
        extensions();
        const std::size_t buffers = count("buffers");
        std::vector<std::uint64_t> bufferLength(buffers, 0);
        forEach("buffers", [&](const Json& b, const std::string& key, std::size_t i) {
            bufferLength[i] = integer(b, key, "byteLength", 0, true);
        });
        const std::size_t views = count("bufferViews");
        forEach("bufferViews", [&](const Json& v, const std::string& key, std::size_t) {
            const std::uint64_t buffer = index(v, key, "buffer", buffers, "buffers", true);
            const std::uint64_t offset = integer(v, key, "byteOffset", 0, false);
            const std::uint64_t length = integer(v, key, "byteLength", 1, true);
            if (v.contains("byteStride")) {
                const std::uint64_t stride = integer(v, key, "byteStride", 4, true);
                if (stride > 252)
                    fail(key + ".byteStride is " + std::to_string(stride) +
                         " (glTF allows 4 to 252)");
            }
            if (offset > bufferLength[buffer] || length > bufferLength[buffer] - offset)
                fail(key + " covers bytes " + std::to_string(offset) + " to " +
                     std::to_string(offset + length) + " of buffers[" + std::to_string(buffer) +
                     "], which has " + std::to_string(bufferLength[buffer]));
        });
        forEach("accessors", [&](const Json& a, const std::string& key, std::size_t) {
            if (a.contains("bufferView")) index(a, key, "bufferView", views, "bufferViews", true);
            integer(a, key, "byteOffset", 0, false);
            if (const auto s = a.find("sparse"); s != a.end() && s->is_object()) {
                for (const char* part : {"indices", "values"}) {
                    const auto p = s->find(part);
                    if (p == s->end() || !p->is_object()) continue;
                    const std::string pk = key + ".sparse." + part;
                    index(*p, pk, "bufferView", views, "bufferViews", true);
                    integer(*p, pk, "byteOffset", 0, false);
                }
            }
        });
        forEach("images", [&](const Json& im, const std::string& key, std::size_t) {
            if (im.contains("bufferView")) index(im, key, "bufferView", views, "bufferViews", true);
        });
        const std::size_t textures = count("textures");
        forEach("materials", [&](const Json& m, const std::string& key, std::size_t) {
            material(m, key, textures);
        });
    }

private:
    [[noreturn]] void fail(const std::string& what) const {
        throw InputError(mOrigin + ": " + what);
    }

    std::size_t count(const char* list) const {
        const auto it = mDoc.find(list);
        return it != mDoc.end() && it->is_array() ? it->size() : 0;
    }

    // Calls f(entry, "list[i]", i) for every entry; a list that is not an array, or an entry that
    // is not an object, is left to tinygltf, whose message says so.
    template <class F> void forEach(const char* list, F&& f) const {
        const auto it = mDoc.find(list);
        if (it == mDoc.end() || !it->is_array()) return;
        for (std::size_t i = 0; i < it->size(); ++i) {
            const Json& entry = (*it)[i];
            if (entry.is_object()) f(entry, std::string(list) + "[" + std::to_string(i) + "]", i);
        }
    }

    // o[name] as an integer of at least `min` (0 when absent and not required).
    std::uint64_t integer(const Json& o, const std::string& key, const char* name,
                          std::uint64_t min, bool required) const {
        const auto it = o.find(name);
        if (it == o.end()) {
            if (required) fail(key + " has no " + name);
            return 0;
        }
        const std::string k = key + "." + name;
        if (it->is_number_unsigned()) {
            const std::uint64_t v = it->get<std::uint64_t>();
            if (v < min) fail(k + " is " + std::to_string(v) + " (at least " + std::to_string(min) + ")");
            return v;
        }
        if (it->is_number_integer()) // signed, so negative here
            fail(k + " is " + std::to_string(it->get<std::int64_t>()) + " (must not be negative)");
        if (it->is_number_float()) {
            const double d = it->get<double>();
            // 36.0 is an integer written as a float; tinygltf reads it so, and so do we.
            if (std::isfinite(d) && d >= 0 && d < 9.0e15 && std::floor(d) == d &&
                std::uint64_t(d) >= min)
                return std::uint64_t(d);
            fail(k + " is " + it->dump() + " (must be an integer of at least " +
                 std::to_string(min) + ")");
        }
        fail(k + " is " + std::string(it->type_name()) + " (must be an integer)");
    }

    // o[name] as an index into `list` of `size` entries.
    std::uint64_t index(const Json& o, const std::string& key, const char* name, std::size_t size,
                        const char* list, bool required) const {
        const std::uint64_t i = integer(o, key, name, 0, required);
        if (o.contains(name) && i >= size)
            fail(key + "." + name + " is " + std::to_string(i) + " but there " +
                 (size == 1 ? "is 1 entry" : "are " + std::to_string(size) + " entries") + " in " +
                 list);
        return i;
    }

    // A number that stays finite as a float (1e39 is a double, not a float), within [lo, hi].
    double number(const Json& v, const std::string& k, double lo, double hi) const {
        if (!v.is_number()) fail(k + " is " + std::string(v.type_name()) + " (must be a number)");
        const double d = v.get<double>();
        if (!std::isfinite(d) || !std::isfinite(float(d)))
            fail(k + " is " + v.dump() + " (not finite in single precision)");
        if (d < lo || d > hi)
            fail(k + " is " + v.dump() + " (must lie in [" + text(lo) + ", " + text(hi) + "])");
        return d;
    }

    void numberArray(const Json& o, const std::string& key, const char* name, std::size_t n,
                     double lo, double hi) const {
        const auto it = o.find(name);
        if (it == o.end()) return;
        const std::string k = key + "." + name;
        if (!it->is_array() || it->size() != n)
            fail(k + " must be an array of " + std::to_string(n) + " numbers, not " + it->dump(-1).substr(0, 80));
        for (std::size_t i = 0; i < n; ++i)
            number((*it)[i], k + "[" + std::to_string(i) + "]", lo, hi);
    }

    // A textureInfo: an object with an integer index into textures, an optional texCoord, and
    // KHR_texture_transform numbers finite in single precision.
    void textureInfo(const Json& o, const std::string& key, const char* name,
                     std::size_t textures) const {
        const auto it = o.find(name);
        if (it == o.end()) return;
        const std::string k = key + "." + name;
        if (!it->is_object()) fail(k + " is " + std::string(it->type_name()) + " (must be an object)");
        index(*it, k, "index", textures, "textures", true);
        integer(*it, k, "texCoord", 0, false);
        if (const auto ext = it->find("extensions"); ext != it->end() && ext->is_object()) {
            if (const auto t = ext->find("KHR_texture_transform");
                t != ext->end() && t->is_object()) {
                const std::string tk = k + ".extensions.KHR_texture_transform";
                const double inf = std::numeric_limits<double>::infinity();
                numberArray(*t, tk, "offset", 2, -inf, inf);
                numberArray(*t, tk, "scale", 2, -inf, inf);
                if (t->contains("rotation")) number((*t)["rotation"], tk + ".rotation", -inf, inf);
            }
        }
    }

    void material(const Json& m, const std::string& key, std::size_t textures) const {
        const double inf = std::numeric_limits<double>::infinity();
        if (m.contains("alphaMode") && !m["alphaMode"].is_string())
            fail(key + ".alphaMode is " + std::string(m["alphaMode"].type_name()) +
                 " (must be \"OPAQUE\", \"MASK\" or \"BLEND\")");
        if (m.contains("alphaCutoff")) number(m["alphaCutoff"], key + ".alphaCutoff", 0.0, inf);
        if (m.contains("doubleSided") && !m["doubleSided"].is_boolean())
            fail(key + ".doubleSided is " + std::string(m["doubleSided"].type_name()) +
                 " (must be true or false)");
        if (const auto pbr = m.find("pbrMetallicRoughness"); pbr != m.end()) {
            const std::string pk = key + ".pbrMetallicRoughness";
            if (!pbr->is_object())
                fail(pk + " is " + std::string(pbr->type_name()) + " (must be an object)");
            numberArray(*pbr, pk, "baseColorFactor", 4, 0.0, 1.0);
            for (const char* f : {"metallicFactor", "roughnessFactor"})
                if (pbr->contains(f)) number((*pbr)[f], pk + "." + f, 0.0, 1.0);
            textureInfo(*pbr, pk, "baseColorTexture", textures);
            textureInfo(*pbr, pk, "metallicRoughnessTexture", textures);
        }
        for (const char* t : {"normalTexture", "occlusionTexture", "emissiveTexture"})
            textureInfo(m, key, t, textures);
        numberArray(m, key, "emissiveFactor", 3, 0.0, inf);
    }

    void extensions() const {
        const auto it = mDoc.find("extensionsRequired");
        if (it == mDoc.end()) return;
        if (!it->is_array()) fail("extensionsRequired must be an array of extension names");
        for (const Json& e : *it) {
            if (!e.is_string()) fail("extensionsRequired holds " + e.dump(-1).substr(0, 80) + ", not a name");
            const std::string name = e.get<std::string>();
            if (harmlessExtension(name)) continue;
            const std::string effect = extensionEffect(name);
            fail("requires glTF extension " + name +
                 (effect.empty() ? std::string() : " (" + effect + ")") +
                 ", which penumbra does not read; export the file without it");
        }
    }

    const std::string& mOrigin;
    const Json& mDoc;
};

bool isHex(char c) {
    return (c >= '0' && c <= '9') || (c >= 'a' && c <= 'f') || (c >= 'A' && c <= 'F');
}

int hexValue(char c) {
    if (c >= '0' && c <= '9') return c - '0';
    if (c >= 'a' && c <= 'f') return c - 'a' + 10;
    if (c >= 'A' && c <= 'F') return c - 'A' + 10;
    return 0;
}

} // namespace

void checkGltfDocument(const std::string& origin, const nlohmann::json& doc) {
    DocumentCheck(origin, doc).run();
}

std::optional<std::string> percentDecode(const std::string& uri) {
    std::string out;
    for (std::size_t i = 0; i < uri.size(); ++i) {
        if (uri[i] != '%') {
            out += uri[i];
            continue;
        }
        if (i + 2 >= uri.size() || !isHex(uri[i + 1]) || !isHex(uri[i + 2])) return std::nullopt;
        out += char(hexValue(uri[i + 1]) << 4 | hexValue(uri[i + 2]));
        i += 2;
    }
    return out;
}

std::string tinygltfDecode(const std::string& uri) {
    std::string out;
    for (std::size_t i = 0; i < uri.size(); ++i) {
        if (uri[i] == '+') {
            out += ' ';
        } else if (uri[i] == '%' && i + 2 < uri.size()) {
            out += char(hexValue(uri[i + 1]) << 4 | hexValue(uri[i + 2]));
            i += 2;
        } else {
            out += uri[i];
        }
    }
    return out;
}

bool ImageDecoder::refuse(const std::string& what, std::string* err) {
    if (mRefusal.empty()) mRefusal = what;
    if (err) *err += what + "\n";
    return false;
}

bool ImageDecoder::decode(tinygltf::Image* image, int index, std::string* err, std::string*,
                          int, int, const unsigned char* bytes, int size, void* self) {
    auto& d = *static_cast<ImageDecoder*>(self);
    const std::string key = "images[" + std::to_string(index) + "]" +
                            (image->uri.empty() || image->uri.rfind("data:", 0) == 0
                                 ? std::string()
                                 : " (" + image->uri + ")");
    if (bytes == nullptr || size <= 0) return d.refuse(key + ": no image data", err);
    static const unsigned char kPng[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
    static const unsigned char kJpeg[3] = {0xff, 0xd8, 0xff};
    const bool png = size >= 8 && std::memcmp(bytes, kPng, 8) == 0;
    const bool jpeg = size >= 3 && std::memcmp(bytes, kJpeg, 3) == 0;
    if (!png && !jpeg)
        return d.refuse(key + ": not a PNG or JPEG image (the only formats of glTF 2.0 without "
                              "extensions)",
                        err);
    const char* format = png ? "PNG" : "JPEG";
    // A PNG's size is in its first chunk (IHDR), read here so that sizes past stb's own limit
    // are named too; a JPEG's frame header can follow other segments: stb finds it.
    std::uint64_t w = 0, h = 0;
    if (png && size >= 24 && std::memcmp(bytes + 12, "IHDR", 4) == 0) {
        for (int i = 0; i < 4; ++i) {
            w = w << 8 | bytes[16 + i];
            h = h << 8 | bytes[20 + i];
        }
    } else {
        int iw = 0, ih = 0, comp = 0;
        if (stbi_info_from_memory(bytes, size, &iw, &ih, &comp)) w = std::uint64_t(iw), h = std::uint64_t(ih);
    }
    if (w == 0 || h == 0)
        return d.refuse(key + ": malformed " + format + " header (no image size in it)", err);
    const std::string dims = std::to_string(w) + "x" + std::to_string(h);
    if (w > std::uint64_t(kMaxTextureSide) || h > std::uint64_t(kMaxTextureSide))
        return d.refuse(key + ": " + format + " of " + dims + " pixels; textures may be " +
                            std::to_string(kMaxTextureSide) + " pixels on a side at most",
                        err);
    const std::size_t pixels = std::size_t(w) * std::size_t(h);
    if (pixels > kMaxTexturePixels - d.mPixels)
        return d.refuse(key + ": " + format + " of " + dims + " pixels would take the file's " +
                            "textures past " + std::to_string(kMaxTexturePixels >> 20) +
                            " Mpixels (" + std::to_string(d.mPixels) + " pixels so far)",
                        err);
    int dw = 0, dh = 0, dc = 0;
    stbi_uc* pixelsOut = stbi_load_from_memory(bytes, size, &dw, &dh, &dc, 0);
    if (pixelsOut == nullptr)
        return d.refuse(key + ": " + format + " of " + dims +
                            " could not be decoded (corrupt or truncated data)",
                        err);
    if (std::uint64_t(dw) != w || std::uint64_t(dh) != h || dc < 1 || dc > 4) {
        stbi_image_free(pixelsOut);
        return d.refuse(key + ": " + format + " decoded to other dimensions than its header's",
                        err);
    }
    d.mPixels += pixels;
    image->width = dw;
    image->height = dh;
    image->component = dc;
    image->bits = 8;
    image->pixel_type = TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE;
    image->image.assign(pixelsOut, pixelsOut + pixels * std::size_t(dc));
    stbi_image_free(pixelsOut);
    return true;
}

} // namespace geometry::detail
