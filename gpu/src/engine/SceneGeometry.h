// The scene's meshes on the GPU as surfaces are drawn (not welded: texture coordinates kept),
// uploaded once, for every pass that rasterises the scene itself: the G-buffer and the slicing
// pass of occlusion textures.
// - Vertices expanded per triangle (flat normal, the material's base colour, texcoord), grouped
//   per object and, within it, per material: one draw range each.
// - Materials: base colour, the base-colour texture (sRGB, mipmapped, its sampler's wraps) and
//   the alpha test (glTF MASK; BLEND tested as MASK at 0.5, with one warning per material on
//   stderr). shaders/lib/Material.glsl reads what bindMaterial sets.
#pragma once

#include <geometry/scene/Scene.h>
#include <gpu/gl/Objects.h>

#include <glm/glm.hpp>

#include <cstddef>
#include <span>
#include <vector>

namespace gpu {

class SceneGeometry {
public:
    // Needs a current GL context.
    explicit SceneGeometry(const geometry::Scene& scene);

    const VertexArray& vertexArray() const { return mVao; }
    // Whether any triangle of the object is alpha-tested.
    bool alphaTested(std::size_t object) const { return mObjectAlpha[object]; }

    // The two variants of a pass's program: `alphaTested` (compiled with ALPHA_TEST: it may
    // discard, which costs early depth tests) draws the alpha-tested ranges, `opaque` the rest.
    struct Programs {
        const Program& opaque;
        const Program& alphaTested;
        bool opaqueReadsMaterial = true; // false: `opaque` has no material uniforms (GL would
                                         // reject setting uniforms it optimised out)
    };
    // Draws one object's triangles, setting each range's program and material.
    void drawObject(std::size_t object, const Programs& programs) const;
    // Draws every object; adjacent ranges of plain (untextured, opaque) materials in one draw.
    void drawAll(const Programs& programs) const;

private:
    struct GpuMaterial {
        bool alphaTested = false;
        float alphaCutoff = 0.5f;
        float alpha = 1.0f; // baseColor.a
        int texture = -1;   // into mTextures
        glm::mat3 uvTransform{1.0f};
        bool plain() const { return !alphaTested && texture < 0; }
    };
    struct Range {
        GLint first = 0;
        GLsizei count = 0;
        int material = -1; // into mMaterials; -1: the default (plain)
    };
    void bindMaterial(int material, const Programs& programs) const;
    bool plain(int material) const { return material < 0 || mMaterials[material].plain(); }

    Buffer mVertices;
    VertexArray mVao;
    std::vector<GpuMaterial> mMaterials;
    std::vector<Texture> mTextures;
    std::vector<std::vector<Range>> mRanges; // per scene object
    std::vector<bool> mObjectAlpha;
};

} // namespace gpu
