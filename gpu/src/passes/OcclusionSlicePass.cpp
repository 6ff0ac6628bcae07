#include "passes/OcclusionSlicePass.h"

#include "engine/ShaderBindings.h"

#include <string>
#include <vector>

namespace gpu {

namespace {

Program load(const ShaderLoader& shaders, int slices, bool alphaTested) {
    std::vector<std::string> defines = {"SLICES " + std::to_string(slices)};
    if (alphaTested) defines.push_back("ALPHA_TEST");
    return shaders.load({.stages = {{GL_VERTEX_SHADER, "occlusion-slice.vert"},
                                    {GL_FRAGMENT_SHADER, "occlusion-slice.frag"}},
                         .defines = std::move(defines),
                         .label = alphaTested ? "occlusion-slice-alpha-test" : "occlusion-slice"});
}

} // namespace

OcclusionSlicePass::OcclusionSlicePass(const ShaderLoader& shaders, int slices)
    : mTargets((slices + 3) / 4), mOpaque(load(shaders, slices, false)),
      mAlphaTested(load(shaders, slices, true)) {}

void OcclusionSlicePass::execute(const Framebuffer& target, int resolution,
                                 const SceneGeometry& geometry,
                                 std::span<const Caster> casters) const {
    applyState(kState);
    glBindFramebuffer(GL_FRAMEBUFFER, target.id());
    glViewport(0, 0, resolution, resolution);
    const float empty[4] = {0, 0, 0, 0};
    for (int i = 0; i < mTargets; ++i) glClearNamedFramebufferfv(target.id(), GL_COLOR, i, empty);
    const SceneGeometry::Programs programs{mOpaque, mAlphaTested, false};
    for (const Caster& c : casters) {
        for (const Program* p : {&mOpaque, &mAlphaTested})
            glProgramUniform1i(p->id(), UNIFORM_SLICE_LEAKFIX, static_cast<GLint>(c.leakFix));
        geometry.drawObject(c.object, programs);
    }
}

} // namespace gpu
