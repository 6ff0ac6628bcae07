// Render targets shared by the passes of one frame; recreated when the size changes.
#pragma once

#include <gpu/Objects.h>

namespace gpu {

struct Targets {
    int width = 0, height = 0;
    Texture depthStencil, position, normal, albedo, visibility, image;
    Framebuffer gbuffer, visibilityFbo, imageFbo;

    void resize(int w, int h);
};

} // namespace gpu
