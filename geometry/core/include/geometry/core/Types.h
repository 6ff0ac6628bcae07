// Plain data shared by every part of penumbra: camera, rectangular light, triangle meshes.
// Nothing here includes GL or OpenMesh; the GPU side consumes these through spans.
#pragma once

#include <glm/glm.hpp>

#include <cstdint>
#include <limits>
#include <string>
#include <vector>

namespace geometry {

struct Camera {
    glm::vec3 eye{0.0f, 4.0f, 8.0f};
    glm::vec3 target{0.0f};
    glm::vec3 up{0.0f, 1.0f, 0.0f};
    float fovYDeg = 50.0f;

    bool operator==(const Camera&) const = default; // exact: "has it changed?"
};

// The light is the set center + s*u + t*v for s, t in [-1, 1] (DESIGN.md §2).
struct RectLight {
    glm::vec3 center{0.0f, 6.0f, 0.0f};
    glm::vec3 u{0.5f, 0.0f, 0.0f};
    glm::vec3 v{0.0f, 0.0f, 0.5f};

    glm::vec3 normal() const { return glm::normalize(glm::cross(u, v)); }
    float area() const { return 4.0f * glm::length(glm::cross(u, v)); }
    // Point of the light at (s, t) in [-1, 1]^2.
    glm::vec3 point(float s, float t) const { return center + s * u + t * v; }

    bool operator==(const RectLight&) const = default; // exact: "has it changed?"
};

struct Aabb {
    glm::vec3 min{std::numeric_limits<float>::max()};
    glm::vec3 max{std::numeric_limits<float>::lowest()};

    void extend(const glm::vec3& p) {
        min = glm::min(min, p);
        max = glm::max(max, p);
    }
    void extend(const Aabb& b) {
        min = glm::min(min, b.min);
        max = glm::max(max, b.max);
    }
    bool empty() const { return min.x > max.x; }
    glm::vec3 center() const { return 0.5f * (min + max); }
    glm::vec3 extent() const { return max - min; }
    // Corner i (0..7): bit 0 picks max.x, bit 1 max.y, bit 2 max.z.
    glm::vec3 corner(int i) const {
        return {(i & 1) ? max.x : min.x, (i & 2) ? max.y : min.y, (i & 4) ? max.z : min.z};
    }
};

// A surface a ray crosses: its distance along the ray (in units of the ray's direction) and its
// opacity under the transmittance rule (geometry/scene/AlphaMask.h surfaceAlpha: 1 for opaque
// materials, the fractional alpha of MASK and BLEND ones), and the surface's plane.
struct SurfaceHit {
    float t = 0.0f;
    float alpha = 1.0f;
    glm::vec3 normal{0.0f}; // the triangle's geometric normal (not normalised)
};

// How an object casts shadows (scene JSON "method").
enum class ShadowMethod { Auto, Wedges, Occlusion, None };

// glTF alphaMode, kept for the occlusion-texture path (foliage).
enum class AlphaMode { Opaque, Mask, Blend };

// glTF sampler wrap modes (the texture's sampler; REPEAT without one).
enum class TextureWrap { Repeat, ClampToEdge, MirroredRepeat };

struct TextureImage {
    int width = 0;
    int height = 0;
    std::vector<std::uint8_t> rgba8; // width * height * 4, rows top to bottom
    TextureWrap wrapS = TextureWrap::Repeat;
    TextureWrap wrapT = TextureWrap::Repeat;
};

struct Material {
    std::string name;
    AlphaMode alphaMode = AlphaMode::Opaque;
    float alphaCutoff = 0.5f;
    bool doubleSided = false;
    glm::vec4 baseColor{1.0f};
    int baseColorTexture = -1; // index into MeshData::textures, -1 = none
    // KHR_texture_transform of the base-colour texture (identity without it): the texture is
    // read at (baseColorUvTransform * vec3(texcoord, 1)).xy.
    glm::mat3 baseColorUvTransform{1.0f};
    // Alpha-tested: alphaMode MASK, and BLEND treated as MASK at 0.5 (the loader sets that cutoff;
    // shadows here have no partial coverage). Texels with base-colour alpha (texture alpha times
    // baseColor.a) below alphaCutoff are cut out.
    bool alphaTested() const { return alphaMode != AlphaMode::Opaque; }
};

// A triangle mesh in world space. Vertices are *not* welded: glTF splits them by UV/normal.
// Welding by position happens in Topology (geometry/shadow/Topology.h).
struct MeshData {
    std::string name;
    std::vector<glm::vec3> positions;
    std::vector<glm::vec2> texcoords; // empty, or one per position
    // Shading normals: empty, or one per position (world space, unit length, or zero where the
    // file gives none: shading then uses the triangle's own normal). Only the image's n.l reads
    // them; visibility and every method's geometry use the triangles' planes.
    std::vector<glm::vec3> normals;
    std::vector<glm::uvec3> triangles;
    std::vector<std::uint32_t> triangleMaterial; // empty, or one per triangle (index into materials)
    std::vector<Material> materials;
    std::vector<TextureImage> textures;

    Aabb bounds() const {
        Aabb b;
        for (const auto& p : positions) b.extend(p);
        return b;
    }
};

} // namespace geometry
