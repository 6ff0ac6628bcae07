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

// Alpha byte of the texel at integer texel coordinates (x, y) (doubles: UVs far from 0), wrapped
// as the sampler says.
float texelByte(const TextureImage& image, double x, double y) {
    auto reduce = [](double c, int n, TextureWrap wrap) {
        if (wrap == TextureWrap::ClampToEdge)
            return static_cast<int>(std::clamp(c, -1.0, static_cast<double>(n)));
        const double period = 2.0 * n;
        return static_cast<int>(c - period * std::floor(c / period));
    };
    const int ix = wrapIndex(reduce(x, image.width, image.wrapS), image.width, image.wrapS);
    const int iy = wrapIndex(reduce(y, image.height, image.wrapT), image.height, image.wrapT);
    return static_cast<float>(
        image.rgba8[(static_cast<std::size_t>(iy) * static_cast<std::size_t>(image.width) +
                     static_cast<std::size_t>(ix)) * 4 + 3]);
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

Aabb occlusionBounds(const MeshData& mesh, std::uint32_t triangle, AlphaRule rule) {
    Aabb whole;
    if (triangle >= mesh.triangles.size()) return whole;
    const glm::uvec3 t = mesh.triangles[triangle];
    if (t.x >= mesh.positions.size() || t.y >= mesh.positions.size() ||
        t.z >= mesh.positions.size())
        return whole;
    const glm::vec3 p[3] = {mesh.positions[t.x], mesh.positions[t.y], mesh.positions[t.z]};
    for (const glm::vec3& q : p) whole.extend(q);
    if (triangle >= mesh.triangleMaterial.size()) return whole;
    const std::uint32_t m = mesh.triangleMaterial[triangle];
    if (m >= mesh.materials.size() || !isAlphaMasked(mesh.materials[m])) return whole;
    const Material& material = mesh.materials[m];
    // Transmittance: any opacity above 0 (a byte of 1 counts, half a byte does not).
    const float cutoff = rule == AlphaRule::Cutoff ? effectiveAlphaCutoff(material) : 0.5f / 255.0f;
    const bool textured =
        material.baseColorTexture >= 0 &&
        static_cast<std::size_t>(material.baseColorTexture) < mesh.textures.size() &&
        !mesh.texcoords.empty() && t.x < mesh.texcoords.size() && t.y < mesh.texcoords.size() &&
        t.z < mesh.texcoords.size();
    const TextureImage* image =
        textured ? &mesh.textures[static_cast<std::size_t>(material.baseColorTexture)] : nullptr;
    if (image && (image->width <= 0 || image->height <= 0 ||
                  image->rgba8.size() <
                      static_cast<std::size_t>(image->width) * image->height * 4))
        image = nullptr; // sampleAlpha reads such an image as 1
    if (!image) {
        const bool hides = rule == AlphaRule::Cutoff ? material.baseColor.a >= cutoff
                                                     : material.baseColor.a > 0.0f;
        return hides || !std::isfinite(material.baseColor.a) ? whole : Aabb{};
    }
    if (!(material.baseColor.a > 0.0f) || !std::isfinite(material.baseColor.a) ||
        !std::isfinite(cutoff))
        return cutoff <= 0.0f ? whole : Aabb{};
    // A texel matters where alpha = baseColor.a * texel >= cutoff: as bytes, over `need`.
    const float need = cutoff / material.baseColor.a * 255.0f;
    if (need <= 0.0f) return whole;

    // The corners in texel coordinates (texel centres at i + 0.5), through the uv transform.
    const glm::vec2 size(static_cast<float>(image->width), static_cast<float>(image->height));
    glm::dvec2 uv[3];
    for (int k = 0; k < 3; ++k) {
        const glm::vec2 st =
            glm::vec2(material.baseColorUvTransform * glm::vec3(mesh.texcoords[t[k]], 1.0f));
        if (!std::isfinite(st.x) || !std::isfinite(st.y)) return whole;
        uv[k] = glm::dvec2(st * size);
    }
    const glm::dvec2 lo = glm::min(uv[0], glm::min(uv[1], uv[2]));
    const glm::dvec2 hi = glm::max(uv[0], glm::max(uv[1], uv[2]));
    // A point samples the 2 x 2 texels around x - 0.5: texel i where i - 0.5 < x < i + 1.5.
    const double x0 = std::floor(lo.x - 1.5), x1 = std::ceil(hi.x + 0.5);
    const double y0 = std::floor(lo.y - 1.5), y1 = std::ceil(hi.y + 0.5);
    if ((x1 - x0) * (y1 - y0) > kOcclusionBoundsTexels) return whole;
    // Barycentric (b1, b2) of a texel-space point: uv = uv0 + E (b1, b2).
    const glm::dmat2 E(uv[1] - uv[0], uv[2] - uv[0]);
    const double det = glm::determinant(E);
    const double scale = glm::length(E[0]) * glm::length(E[1]);
    const bool invertible = scale > 0.0 && std::abs(det) > 1e-9 * scale;
    const glm::dmat2 inverse = invertible ? glm::inverse(E) : glm::dmat2(0.0);
    Aabb box;
    bool any = false;
    for (double y = y0; y < y1; y += 1.0)
        for (double x = x0; x < x1; x += 1.0) {
            if (texelByte(*image, x, y) < need) continue;
            any = true;
            if (!invertible) return whole;
            // The points whose footprint holds texel (x, y): the square (x - 0.5, x + 1.5) of
            // it, a little wider for rounding; its corners in world space bound them (the map
            // from texel space to the triangle's plane is affine).
            for (int c = 0; c < 4; ++c) {
                const glm::dvec2 q((c & 1) ? x + 1.5 + 1e-3 : x - 0.5 - 1e-3,
                                   (c & 2) ? y + 1.5 + 1e-3 : y - 0.5 - 1e-3);
                const glm::dvec2 b = inverse * (q - uv[0]);
                box.extend(glm::vec3(glm::dvec3(p[0]) + b.x * glm::dvec3(p[1] - p[0]) +
                                     b.y * glm::dvec3(p[2] - p[0])));
            }
        }
    if (!any) return Aabb{};
    // Within the triangle's own box, with a margin for the float rounding of the corners and
    // of the points a rasteriser or ray interpolates on the triangle.
    const glm::vec3 magnitude = glm::max(glm::abs(whole.min), glm::abs(whole.max));
    const glm::vec3 margin =
        1e-4f * (whole.max - whole.min) + 1e-5f * magnitude + glm::vec3(1e-6f);
    Aabb out;
    out.min = glm::max(box.min, whole.min) - margin;
    out.max = glm::min(box.max, whole.max) + margin;
    if (out.empty()) return whole; // rounding: keep it conservative
    return out;
}

float surfaceOpacity(const MeshData& mesh, std::uint32_t triangle, glm::vec2 barycentric) {
    if (triangle >= mesh.triangleMaterial.size()) return 1.0f;
    const std::uint32_t m = mesh.triangleMaterial[triangle];
    if (m >= mesh.materials.size() || !isAlphaMasked(mesh.materials[m])) return 1.0f;
    const float alpha = surfaceAlpha(mesh, triangle, barycentric);
    return std::isfinite(alpha) ? std::clamp(alpha, 0.0f, 1.0f) : 1.0f;
}

} // namespace geometry
