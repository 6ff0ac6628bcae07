// libFuzzer target: arbitrary bytes as a scene JSON (geometry::parseScene, then validateScene as
// loadScene does). Relative "file" paths of gltf objects resolve against fuzz/assets (a small
// triangle.gltf is there), or $PENUMBRA_FUZZ_ASSETS. Any InputError is a correct answer;
// anything else is a finding. A scene that loads must satisfy the budgets it promises.
#include <geometry/core/Error.h>
#include <geometry/core/Limits.h>
#include <geometry/scene/Scene.h>

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <string>

namespace {

void require(bool ok) {
    if (!ok) __builtin_trap();
}

const std::filesystem::path& assets() {
    static const std::filesystem::path dir = [] {
        const char* env = std::getenv("PENUMBRA_FUZZ_ASSETS");
        return std::filesystem::path(env && *env ? env : PENUMBRA_FUZZ_ASSETS_DIR);
    }();
    return dir;
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    try {
        const std::string text(reinterpret_cast<const char*>(data), size);
        const geometry::Scene scene = geometry::parseScene(text, assets(), "fuzz.json");
        geometry::validateScene(scene);
        require(!scene.objects.empty());
        require(scene.triangleCount() <= geometry::kMaxSceneTriangles);
        for (const geometry::SceneObject& o : scene.objects) {
            for (const glm::uvec3& t : o.mesh.triangles) {
                for (int a = 0; a < 3; ++a)
                    require(t[a] < o.mesh.positions.size());
            }
        }
    } catch (const geometry::InputError&) {
        // The expected answer to bad input.
    }
    return 0;
}
