// glTF 2.0 / GLB loading with tinygltf: every mesh primitive of every node of the default scene
// (or all root nodes), node transforms applied, triangles only (strips/fans converted; points and
// lines rejected with a clear error). Materials keep alphaMode, alphaCutoff (0.5 for BLEND),
// doubleSided, baseColorFactor and the base-colour texture (decoded to RGBA8, with its sampler's
// wrap modes and KHR_texture_transform) for alpha-tested shadows (the occlusion-texture path).
// An alpha-tested texture read through TEXCOORD_1+ or missing its TEXCOORD_0 is an InputError.
// Not read: vertex colours (COLOR_0 alpha would also scale alpha), sampler filters.
#pragma once

#include <geometry/Types.h>

#include <filesystem>

namespace geometry {

// All primitives merged into one MeshData (world space = glTF scene space * `transform`).
// Throws InputError: missing/unreadable file, parse error, no meshes, no triangles, NaN/Inf
// positions, out-of-range indices.
MeshData loadGltf(const std::filesystem::path& path, const glm::mat4& transform = glm::mat4(1.0f));

} // namespace geometry
