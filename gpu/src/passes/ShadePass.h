// The image from the G-buffer and V: albedo * (ambient + (1 - ambient) * V * n.l).
#pragma once

#include "engine/Targets.h"
#include "passes/FullscreenPass.h"

namespace gpu {

class ShadePass {
public:
    explicit ShadePass(const ShaderLoader& shaders);
    void execute(const Targets& t) const;

private:
    FullscreenPass mPass;
};

} // namespace gpu
