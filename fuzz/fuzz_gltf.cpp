// libFuzzer target: arbitrary bytes as a .gltf / .glb (geometry::parseGltf, in memory, with no
// folder: every external URI is refused, nothing on disk is read). Any InputError is a correct
// answer; anything else (a sanitizer report, another exception, a hang, an allocation past
// -rss_limit_mb) is a finding. A model that loads must also satisfy what the rest of the
// engine relies on (checked below; a violation traps).
#include <geometry/core/Error.h>
#include <geometry/scene/GltfLoader.h>
#include <geometry/core/Limits.h>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <span>

namespace {

void require(bool ok) {
    if (!ok) __builtin_trap();
}

void checkMesh(const geometry::MeshData& mesh) {
    require(mesh.triangles.size() <= geometry::kMaxSceneTriangles);
    require(!mesh.triangles.empty());
    require(mesh.triangleMaterial.size() == mesh.triangles.size());
    require(mesh.texcoords.empty() || mesh.texcoords.size() == mesh.positions.size());
    require(mesh.normals.empty() || mesh.normals.size() == mesh.positions.size());
    for (const auto& n : mesh.normals)
        require(std::isfinite(n.x) && std::isfinite(n.y) && std::isfinite(n.z));
    for (const glm::vec3& p : mesh.positions) {
        for (int a = 0; a < 3; ++a)
            require(std::isfinite(p[a]) && std::abs(p[a]) <= geometry::kMaxCoordinate);
    }
    for (const glm::uvec3& t : mesh.triangles) {
        for (int a = 0; a < 3; ++a)
            require(t[a] < mesh.positions.size());
    }
    for (std::uint32_t m : mesh.triangleMaterial)
        require(m < mesh.materials.size());
    for (const geometry::Material& m : mesh.materials) {
        require(m.baseColorTexture < int(mesh.textures.size()));
    }
    for (const geometry::TextureImage& t : mesh.textures) {
        require(t.width > 0 && t.height > 0);
        require(t.rgba8.size() == std::size_t(t.width) * std::size_t(t.height) * 4);
    }
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    try {
        const geometry::GltfContents contents =
            geometry::parseGltf(std::span<const unsigned char>(data, size), {}, "fuzz.gltf");
        checkMesh(contents.mesh);
        for (const geometry::GltfCamera& c : contents.cameras) {
            require(std::isfinite(c.camera.fovYDeg) && c.camera.fovYDeg > 0.0f &&
                    c.camera.fovYDeg < 180.0f);
        }
    } catch (const geometry::InputError&) {
        // The expected answer to bad input.
    }
    return 0;
}
