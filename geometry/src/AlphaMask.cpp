#include <geometry/AlphaMask.h>

#include <algorithm>
#include <cmath>

namespace geometry {

bool isAlphaMasked(const Material& material) {
    return material.alphaMode == AlphaMode::Mask || material.alphaMode == AlphaMode::Blend;
}

float effectiveAlphaCutoff(const Material& material) {
    switch (material.alphaMode) {
    case AlphaMode::Mask: return material.alphaCutoff;
    case AlphaMode::Blend: return 0.5f;
    case AlphaMode::Opaque: break;
    }
    return 0.0f;
}

bool hasAlphaMask(const MeshData& mesh) {
    if (mesh.triangleMaterial.empty()) return false;
    return std::any_of(mesh.materials.begin(), mesh.materials.end(), isAlphaMasked);
}

namespace {

int wrapIndex(int i, int n) {
    const int r = i % n;
    return r < 0 ? r + n : r;
}

float texelAlpha(const TextureImage& image, int x, int y) {
    const std::size_t i = (static_cast<std::size_t>(wrapIndex(y, image.height)) *
                               static_cast<std::size_t>(image.width) +
                           static_cast<std::size_t>(wrapIndex(x, image.width))) *
                              4 +
                          3;
    return static_cast<float>(image.rgba8[i]) / 255.0f;
}

} // namespace

float sampleAlpha(const TextureImage& image, glm::vec2 uv) {
    if (image.width <= 0 || image.height <= 0 ||
        image.rgba8.size() < static_cast<std::size_t>(image.width) * image.height * 4)
        return 1.0f;
    if (!std::isfinite(uv.x) || !std::isfinite(uv.y)) return 1.0f;
    // Texel centres at (i + 0.5) / size.
    const float x = uv.x * static_cast<float>(image.width) - 0.5f;
    const float y = uv.y * static_cast<float>(image.height) - 0.5f;
    const float fx = std::floor(x), fy = std::floor(y);
    const float ax = x - fx, ay = y - fy;
    // Wrap before converting: UVs far outside [0, 1] must not overflow an int.
    const int x0 = wrapIndex(static_cast<int>(std::fmod(fx, float(image.width))), image.width);
    const int y0 = wrapIndex(static_cast<int>(std::fmod(fy, float(image.height))), image.height);
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
            alpha *= sampleAlpha(mesh.textures[static_cast<std::size_t>(material.baseColorTexture)],
                                 uv);
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

} // namespace geometry
