// glTF 2.0 / GLB loading with tinygltf: every mesh primitive of every node of the default scene
// (or all root nodes), node transforms applied, triangles only (strips/fans converted; points and
// lines rejected with a clear error). Materials keep alphaMode, alphaCutoff (0.5 for BLEND),
// doubleSided, baseColorFactor and the base-colour texture (decoded to RGBA8, with its sampler's
// wrap modes and KHR_texture_transform) for alpha-tested shadows (the occlusion-texture path).
// An alpha-tested texture read through TEXCOORD_1+ or missing its TEXCOORD_0 is an InputError.
// NORMAL (float VEC3, one per POSITION) becomes MeshData::normals for shading, transformed by
// the inverse transpose and renormalised; a zero normal means "use the face's"; a NaN or
// infinite normal, another type or another count is an InputError.
// Cameras: every node of the same walk with a perspective `camera` becomes a GltfCamera (see
// there); orthographic cameras are skipped and counted.
// Not read: vertex colours (COLOR_0 alpha would also scale alpha), sampler filters, camera
// aspect ratio and clip planes.
#pragma once

#include <geometry/core/Types.h>

#include <filesystem>
#include <span>
#include <string>
#include <vector>

namespace geometry {

// All primitives merged into one MeshData (world space = glTF scene space * `transform`).
// Throws InputError: missing/unreadable file, parse error, a .glb without the GLB magic, no
// meshes, no triangles, NaN/Inf positions or world coordinates beyond +-kMaxCoordinate
// (geometry/core/Limits.h), more than kMaxSceneTriangles triangles, out-of-range indices or indices
// of a wrong type, accessor counts beyond the triangle budget's vertices, a node hierarchy
// deeper than 1000 levels or a node reached twice (listed by two parents, or twice by one), JSON
// nested deeper than 256 levels, GLB chunk lengths that do not fit the file, and a buffer or
// image URI that is neither a data: URI nor a relative path to a regular file staying inside the
// file's folder once "..", percent escapes and symlinks are resolved (those files are never
// opened; nor is a FIFO or device inside it).
MeshData loadGltf(const std::filesystem::path& path, const glm::mat4& transform = glm::mat4(1.0f));

// A perspective glTF camera placed by its node's world transform (the meshes' transform chain,
// `transform` included): eye = the node's world origin, target = eye + the node's world -Z
// (normalised), up = its world +Y (normalised), fovYDeg = yfov in degrees. A mirroring or
// non-uniformly scaling transform is not reproduced (the view stays a right-handed look-at).
struct GltfCamera {
    std::string name; // the node's name, or "camera N" (N = index in the list) when it has none
    Camera camera;
    int node = -1; // glTF node index
};

struct GltfContents {
    MeshData mesh;
    std::vector<GltfCamera> cameras; // perspective cameras, in node (file) order
    int orthographicCameras = 0;     // camera nodes skipped because they are orthographic
};

// Mesh and cameras from one parse. Throws what loadGltf throws, and InputError naming the node
// for a camera node with a missing camera, a non-finite or degenerate placement (zero or parallel
// forward/up directions) or a yfov outside (0, pi).
GltfContents loadGltfWithCameras(const std::filesystem::path& path,
                                 const glm::mat4& transform = glm::mat4(1.0f));

// Cameras only: no mesh is read (a file without meshes is fine). Same camera errors.
std::vector<GltfCamera> loadGltfCameras(const std::filesystem::path& path,
                                        const glm::mat4& transform = glm::mat4(1.0f));

// loadGltfWithCameras on a file's bytes already in memory (a .gltf's JSON or a GLB, told by the
// content). `name` stands for the file in messages and names the mesh (its stem); a name ending
// in .glb must hold a GLB, as a file would. External buffer and image URIs resolve against
// `folder` under the same confinement as a file in that folder; with an empty `folder` every
// external URI is refused (only data: URIs and the GLB's own BIN chunk are read), so nothing
// outside `bytes` is touched. Throws what loadGltfWithCameras throws.
GltfContents parseGltf(std::span<const unsigned char> bytes, const std::filesystem::path& folder,
                       const std::string& name = "<glTF>",
                       const glm::mat4& transform = glm::mat4(1.0f));

} // namespace geometry
