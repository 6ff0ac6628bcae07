#include <geometry/scene/AlphaMask.h>

#include <algorithm>
#include <cmath>

namespace geometry {

bool isAlphaMasked(const Material& material) { return material.alphaTested(); }

float effectiveAlphaCutoff(const Material& material) {
    // The loader gives BLEND the cutoff 0.5; a material built in code may not have.
    switch (material.alphaMode) {
    case AlphaMode::Mask: return material.alphaCutoff;
    case AlphaMode::Blend: return 0.5f;
    case AlphaMode::Opaque: break;
    }
    return 0.0f;
}

bool hasAlphaMask(const MeshData& mesh) {
    if (mesh.triangleMaterial.empty()) return false;
    if (std::none_of(mesh.materials.begin(), mesh.materials.end(), isAlphaMasked)) return false;
    return std::any_of(mesh.triangleMaterial.begin(), mesh.triangleMaterial.end(),
                       [&](std::uint32_t m) {
                           return m < mesh.materials.size() && isAlphaMasked(mesh.materials[m]);
                       });
}

namespace {

int wrapIndex(int i, int n, TextureWrap wrap) {
    switch (wrap) {
    case TextureWrap::ClampToEdge: return std::clamp(i, 0, n - 1);
    case TextureWrap::MirroredRepeat: {
        const int period = 2 * n;
        int r = i % period;
        if (r < 0) r += period;
        return r < n ? r : period - 1 - r;
    }
    case TextureWrap::Repeat: break;
    }
    const int r = i % n;
    return r < 0 ? r + n : r;
}

float texelAlpha(const TextureImage& image, int x, int y) {
    const std::size_t i = (static_cast<std::size_t>(wrapIndex(y, image.height, image.wrapT)) *
                               static_cast<std::size_t>(image.width) +
                           static_cast<std::size_t>(wrapIndex(x, image.width, image.wrapS))) *
                              4 +
                          3;
    return static_cast<float>(image.rgba8[i]) / 255.0f;
}

// A texel coordinate brought near [0, n) without changing what it samples under `wrap`
// (huge UVs must not overflow an int): whole periods of 2n are removed for the repeating modes.
float reduceCoordinate(float x, int n, TextureWrap wrap) {
    if (wrap == TextureWrap::ClampToEdge) return std::clamp(x, -1.0f, static_cast<float>(n));
    const float period = 2.0f * static_cast<float>(n);
    return x - period * std::floor(x / period);
}

} // namespace

float sampleAlpha(const TextureImage& image, glm::vec2 uv) {
    if (image.width <= 0 || image.height <= 0 ||
        image.rgba8.size() < static_cast<std::size_t>(image.width) * image.height * 4)
        return 1.0f;
    if (!std::isfinite(uv.x) || !std::isfinite(uv.y)) return 1.0f;
    // Texel centres at (i + 0.5) / size.
    const float x = reduceCoordinate(uv.x * static_cast<float>(image.width) - 0.5f, image.width,
                                     image.wrapS);
    const float y = reduceCoordinate(uv.y * static_cast<float>(image.height) - 0.5f,
                                     image.height, image.wrapT);
    const float fx = std::floor(x), fy = std::floor(y);
    const float ax = x - fx, ay = y - fy;
    const int x0 = static_cast<int>(fx), y0 = static_cast<int>(fy);
    const float a00 = texelAlpha(image, x0, y0), a10 = texelAlpha(image, x0 + 1, y0);
    const float a01 = texelAlpha(image, x0, y0 + 1), a11 = texelAlpha(image, x0 + 1, y0 + 1);
    return (a00 * (1.0f - ax) + a10 * ax) * (1.0f - ay) + (a01 * (1.0f - ax) + a11 * ax) * ay;
}

float surfaceAlpha(const MeshData& mesh, std::uint32_t triangle, glm::vec2 barycentric) {
    if (triangle >= mesh.triangleMaterial.size()) return 1.0f;
    const std::uint32_t m = mesh.triangleMaterial[triangle];
    if (m >= mesh.materials.size()) return 1.0f;
    const Material& material = mesh.materials[m];
    float alpha = material.baseColor.a;
    if (material.baseColorTexture >= 0 &&
        static_cast<std::size_t>(material.baseColorTexture) < mesh.textures.size() &&
        triangle < mesh.triangles.size() && !mesh.texcoords.empty()) {
        const glm::uvec3 t = mesh.triangles[triangle];
        if (t.x < mesh.texcoords.size() && t.y < mesh.texcoords.size() &&
            t.z < mesh.texcoords.size()) {
            const glm::vec2 uv = (1.0f - barycentric.x - barycentric.y) * mesh.texcoords[t.x] +
                                 barycentric.x * mesh.texcoords[t.y] +
                                 barycentric.y * mesh.texcoords[t.z];
            const glm::vec2 st = glm::vec2(material.baseColorUvTransform * glm::vec3(uv, 1.0f));
            alpha *= sampleAlpha(mesh.textures[static_cast<std::size_t>(material.baseColorTexture)],
                                 st);
        }
    }
    return alpha;
}

bool surfaceOccludes(const MeshData& mesh, std::uint32_t triangle, glm::vec2 barycentric) {
    if (triangle >= mesh.triangleMaterial.size()) return true;
    const std::uint32_t m = mesh.triangleMaterial[triangle];
    if (m >= mesh.materials.size() || !isAlphaMasked(mesh.materials[m])) return true;
    return surfaceAlpha(mesh, triangle, barycentric) >= effectiveAlphaCutoff(mesh.materials[m]);
}

float surfaceOpacity(const MeshData& mesh, std::uint32_t triangle, glm::vec2 barycentric) {
    if (triangle >= mesh.triangleMaterial.size()) return 1.0f;
    const std::uint32_t m = mesh.triangleMaterial[triangle];
    if (m >= mesh.materials.size() || !isAlphaMasked(mesh.materials[m])) return 1.0f;
    const float alpha = surfaceAlpha(mesh, triangle, barycentric);
    return std::isfinite(alpha) ? std::clamp(alpha, 0.0f, 1.0f) : 1.0f;
}

} // namespace geometry
