#include "passes/ShadePass.h"

#include "engine/ShaderBindings.h"

namespace gpu {

ShadePass::ShadePass(const ShaderLoader& shaders)
    : mPass(shaders, "shade.frag", "shade", PipelineState{}) {}

void ShadePass::execute(const Targets& t) const {
    glBindTextureUnit(TEXUNIT_POSITION, t.position.id());
    glBindTextureUnit(TEXUNIT_SHADING, t.shading.id());
    glBindTextureUnit(TEXUNIT_ALBEDO, t.albedo.id());
    glBindTextureUnit(TEXUNIT_VISIBILITY, t.visibility.id());
    mPass.execute(t.imageFbo, t.width, t.height);
}

} // namespace gpu
