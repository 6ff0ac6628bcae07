#include "engine/SceneGeometry.h"

#include "engine/ShaderBindings.h"

#include <geometry/core/Error.h>

#include <cstddef>
#include <cstdio>

namespace gpu {

namespace {

struct SceneVertex {
    glm::vec3 position;
    glm::vec3 normal;  // flat, per triangle: the surface every method's visibility sees
    glm::vec3 shading; // the file's vertex normal on the triangle's side, else `normal`
    glm::vec3 albedo; // the material's base colour (linear)
    glm::vec2 texcoord;
};

GLenum glWrap(geometry::TextureWrap w) {
    switch (w) {
    case geometry::TextureWrap::ClampToEdge:
        return GL_CLAMP_TO_EDGE;
    case geometry::TextureWrap::MirroredRepeat:
        return GL_MIRRORED_REPEAT;
    case geometry::TextureWrap::Repeat:
        break;
    }
    return GL_REPEAT;
}

int mipLevels(int w, int h) {
    int levels = 1;
    while ((w | h) >> levels) ++levels;
    return levels;
}

} // namespace

SceneGeometry::SceneGeometry(const geometry::Scene& scene) : mVao("scene") {
    std::vector<SceneVertex> vertices;
    vertices.reserve(3 * scene.triangleCount());
    mRanges.resize(scene.objects.size());
    mObjectAlpha.assign(scene.objects.size(), false);
    GLint maxTextureSide = 0;
    glGetIntegerv(GL_MAX_TEXTURE_SIZE, &maxTextureSide);
    for (std::size_t o = 0; o < scene.objects.size(); ++o) {
        const geometry::SceneObject& object = scene.objects[o];
        const geometry::MeshData& mesh = object.mesh;
        const int textureBase = static_cast<int>(mTextures.size());
        for (const geometry::TextureImage& image : mesh.textures) {
            // The loader caps sides at geometry::kMaxTextureSide, the least GL 4.5 offers; an
            // implementation may still offer less, or a scene may be built in code.
            if (image.width <= 0 || image.height <= 0 || image.width > maxTextureSide ||
                image.height > maxTextureSide)
                throw geometry::InputError(
                    "object '" + object.name + "': texture " +
                    std::to_string(&image - mesh.textures.data()) + " is " +
                    std::to_string(image.width) + "x" + std::to_string(image.height) +
                    " pixels; this GL implementation's textures are " +
                    std::to_string(maxTextureSide) + " pixels on a side at most "
                    "(GL_MAX_TEXTURE_SIZE)");
            if (image.rgba8.size() != std::size_t(image.width) * std::size_t(image.height) * 4)
                throw geometry::InputError("object '" + object.name + "': texture " +
                                           std::to_string(&image - mesh.textures.data()) +
                                           " holds " + std::to_string(image.rgba8.size()) +
                                           " bytes, not width x height x 4");
            Texture& t = mTextures.emplace_back(TextureDesc{
                .width = image.width, .height = image.height, .format = GL_SRGB8_ALPHA8,
                .levels = mipLevels(image.width, image.height),
                .minFilter = GL_LINEAR_MIPMAP_LINEAR, .magFilter = GL_LINEAR,
                .wrap = glWrap(image.wrapS), .label = "material-texture"});
            glTextureParameteri(t.id(), GL_TEXTURE_WRAP_T, static_cast<GLint>(glWrap(image.wrapT)));
            // Rows come top first; glTF's texcoord origin is the image's top-left, GL's the
            // first row uploaded: uploading top first maps (0, 0) to the top-left texel. (RGBA8
            // rows are 4-byte aligned: the default unpack alignment holds.)
            glTextureSubImage2D(t.id(), 0, 0, 0, image.width, image.height, GL_RGBA,
                                GL_UNSIGNED_BYTE, image.rgba8.data());
            glGenerateTextureMipmap(t.id());
        }
        const int materialBase = static_cast<int>(mMaterials.size());
        for (const geometry::Material& m : mesh.materials) {
            GpuMaterial g;
            g.alphaTested = m.alphaTested();
            g.alphaCutoff = m.alphaCutoff;
            g.alpha = m.baseColor.a;
            g.texture = m.baseColorTexture >= 0 ? textureBase + m.baseColorTexture : -1;
            g.uvTransform = m.baseColorUvTransform;
            mMaterials.push_back(g);
            if (m.alphaMode == geometry::AlphaMode::Blend)
                std::fprintf(stderr,
                             "warning: %s: material \"%s\" has alphaMode BLEND; the G-buffer "
                             "and the shadows test it as MASK at alpha 0.5 (but deep-sm's and "
                             "raytrace's with transmittance=on, which let 1 - alpha through)\n",
                             object.name.c_str(), m.name.c_str());
        }

        // Triangles by material, in order (ranges of one material are contiguous).
        const bool perTriangle = !mesh.triangleMaterial.empty() && !mesh.materials.empty();
        const std::size_t materialCount = perTriangle ? mesh.materials.size() : 1;
        for (std::size_t mat = 0; mat < materialCount; ++mat) {
            const GLint first = static_cast<GLint>(vertices.size());
            const geometry::Material* material = perTriangle ? &mesh.materials[mat] : nullptr;
            const glm::vec3 albedo = material ? glm::vec3(material->baseColor) : glm::vec3(0.8f);
            for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
                if (perTriangle && mesh.triangleMaterial[t] != mat) continue;
                const glm::uvec3 tri = mesh.triangles[t];
                const glm::vec3 a = mesh.positions[tri.x], b = mesh.positions[tri.y],
                                c = mesh.positions[tri.z];
                const glm::vec3 n = glm::cross(b - a, c - a);
                const float len = glm::length(n);
                if (!(len > 0.0f)) continue; // zero area: rasterises nothing, has no normal
                const glm::vec3 face = n / len;
                for (int k = 0; k < 3; ++k) {
                    const glm::vec2 uv =
                        mesh.texcoords.empty() ? glm::vec2(0.0f) : mesh.texcoords[tri[k]];
                    // A vertex normal on the far side of its triangle's winding (files whose
                    // normals disagree with it) is turned over, so the G-buffer's flip to the
                    // viewer's side turns both together.
                    glm::vec3 shading = mesh.normals.empty() ? glm::vec3(0.0f) : mesh.normals[tri[k]];
                    if (shading == glm::vec3(0.0f)) shading = face;
                    if (glm::dot(shading, face) < 0.0f) shading = -shading;
                    vertices.push_back({mesh.positions[tri[k]], face, shading, albedo, uv});
                }
            }
            const GLsizei count = static_cast<GLsizei>(vertices.size()) - first;
            if (count == 0) continue;
            const int index = material ? materialBase + static_cast<int>(mat) : -1;
            mRanges[o].push_back({first, count, index});
            if (index >= 0 && mMaterials[index].alphaTested) mObjectAlpha[o] = true;
        }
    }
    mVertices = Buffer({.size = vertices.size() * sizeof(SceneVertex),
                        .data = vertices.empty() ? nullptr : vertices.data(), .flags = 0,
                        .label = "scene-vertices"});
    if (!vertices.empty()) mVao.vertexBuffer(0, mVertices, 0, sizeof(SceneVertex));
    mVao.attribute(0, 0, 3, GL_FLOAT, offsetof(SceneVertex, position));
    mVao.attribute(1, 0, 3, GL_FLOAT, offsetof(SceneVertex, normal));
    mVao.attribute(2, 0, 3, GL_FLOAT, offsetof(SceneVertex, albedo));
    mVao.attribute(3, 0, 2, GL_FLOAT, offsetof(SceneVertex, texcoord));
    mVao.attribute(4, 0, 3, GL_FLOAT, offsetof(SceneVertex, shading));
}

void SceneGeometry::bindMaterial(int material, const Programs& programs) const {
    // Uniforms of the program (lib/Material.glsl's explicit locations).
    const bool alphaTested = !plain(material) && mMaterials[material].alphaTested;
    glUseProgram(alphaTested ? programs.alphaTested.id() : programs.opaque.id());
    if (!alphaTested && !programs.opaqueReadsMaterial) return;
    if (plain(material)) {
        glUniform4f(UNIFORM_MATERIAL, -1.0f, 1.0f, 0.0f, 0.0f);
        return;
    }
    const GpuMaterial& m = mMaterials[material];
    glUniform4f(UNIFORM_MATERIAL, m.alphaTested ? m.alphaCutoff : -1.0f, m.alpha,
                m.texture >= 0 ? 1.0f : 0.0f, 0.0f);
    glUniformMatrix3fv(UNIFORM_MATERIAL_UV, 1, GL_FALSE, &m.uvTransform[0][0]);
    if (m.texture >= 0) glBindTextureUnit(TEXUNIT_MATERIAL, mTextures[m.texture].id());
}

void SceneGeometry::drawObject(std::size_t object, const Programs& programs) const {
    glBindVertexArray(mVao.id());
    for (const Range& r : mRanges[object]) {
        bindMaterial(r.material, programs);
        glDrawArrays(GL_TRIANGLES, r.first, r.count);
    }
}

void SceneGeometry::drawAll(const Programs& programs) const {
    glBindVertexArray(mVao.id());
    GLint runFirst = 0;
    GLsizei runCount = 0; // a pending run of plain ranges
    auto flush = [&] {
        if (runCount == 0) return;
        bindMaterial(-1, programs);
        glDrawArrays(GL_TRIANGLES, runFirst, runCount);
        runCount = 0;
    };
    for (const auto& ranges : mRanges)
        for (const Range& r : ranges) {
            if (plain(r.material)) {
                if (runCount > 0 && runFirst + runCount == r.first) {
                    runCount += r.count;
                } else {
                    flush();
                    runFirst = r.first;
                    runCount = r.count;
                }
                continue;
            }
            flush();
            bindMaterial(r.material, programs);
            glDrawArrays(GL_TRIANGLES, r.first, r.count);
        }
    flush();
}

} // namespace gpu
