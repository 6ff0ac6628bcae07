// Alpha-masked (alpha-tested) materials: glTF `alphaMode: MASK`, and `BLEND` treated as MASK at
// a cutoff of 0.5 (DESIGN.md §3: foliage). A surface point occludes when its alpha — the
// material's base-colour factor alpha times its base-colour texture's alpha at the point's UV —
// is at least the cutoff. This is the rule every path agrees on: `raytrace` (an Embree filter),
// the G-buffer and the occlusion textures' slicing pass (the GPU samples the same texture,
// bilinear with repeat, as sampleAlpha does).
#pragma once

#include <geometry/core/Types.h>

#include <cstdint>

namespace geometry {

// MASK or BLEND: some of the material may be cut away.
bool isAlphaMasked(const Material& material);
// MASK: its alphaCutoff; BLEND: 0.5; OPAQUE: 0 (everything occludes).
float effectiveAlphaCutoff(const Material& material);
// Does any triangle of the mesh use an alpha-masked material?
bool hasAlphaMask(const MeshData& mesh);

// Texture alpha at uv: bilinear between texel centres of the base level, wrapped as the
// image's sampler says (glTF default REPEAT), rows top to bottom as stored (glTF: v = 0 is the
// image's top row). 1 for an empty image. (The GPU samples with mipmaps: at a distance its
// alpha is the average of a texel footprint, a difference of filtering, not of rule.)
float sampleAlpha(const TextureImage& image, glm::vec2 uv);

// Alpha of triangle `triangle` of `mesh` at barycentric (u, v) (the point (1-u-v) p0 + u p1 +
// v p2): base-colour factor alpha × texture alpha at the interpolated texcoord (through the
// material's KHR_texture_transform); 1 for a triangle
// without a material.
float surfaceAlpha(const MeshData& mesh, std::uint32_t triangle, glm::vec2 barycentric);
// The point's opacity under the transmittance rule (a ray passing it keeps 1 - opacity of its
// light; raytrace transmittance=on and deep-sm): 1 for an opaque material (glTF OPAQUE ignores
// alpha) or a triangle without one, the alpha clamped to [0, 1] for MASK and BLEND, no cutoff.
float surfaceOpacity(const MeshData& mesh, std::uint32_t triangle, glm::vec2 barycentric);
// Whether that point occludes (alpha >= the material's effective cutoff).
bool surfaceOccludes(const MeshData& mesh, std::uint32_t triangle, glm::vec2 barycentric);

// Which points of a surface hide light: those that occlude under the alpha test
// (surfaceOccludes), or, under the transmittance rule (surfaceOpacity), every point of
// opacity above 0.
enum class AlphaRule { Cutoff, Transmittance };

// A box holding every point of triangle `triangle` of `mesh` that hides light under `rule`,
// empty where none can. The triangle's own box for an opaque material; for an alpha-tested one,
// only the parts whose bilinear footprint (sampleAlpha) reaches a texel that counts (at or over
// the cutoff; above 0 for the transmittance rule): a light beam or flame card whose opaque
// texels cover a few percent of it is boxed around those. The triangle's box where its UVs span
// more than kOcclusionBoundsTexels texels (a texture repeated over a wall) or map it to a line.
inline constexpr double kOcclusionBoundsTexels = 1 << 18;
Aabb occlusionBounds(const MeshData& mesh, std::uint32_t triangle,
                     AlphaRule rule = AlphaRule::Cutoff);

} // namespace geometry
