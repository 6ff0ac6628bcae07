// Render targets shared by the passes of one frame; recreated when the size changes.
#pragma once

#include <gpu/gl/Objects.h>

namespace gpu {

struct Targets {
    // Bytes per pixel of what resize() allocates: depth-stencil (D32F_S8, stored in 8 bytes),
    // position and normal (RGBA32F), albedo (RGBA8), visibility (R32F), image (RGBA8).
    static constexpr std::size_t kBytesPerPixel = 8 + 16 + 16 + 4 + 4 + 4;
    // The largest format among them, the one a size must fit first.
    static constexpr GLenum kWidestFormat = GL_RGBA32F;


    int width = 0, height = 0;
    Texture depthStencil, position, normal, albedo, visibility, image;
    Framebuffer gbuffer, visibilityFbo, imageFbo;

    void resize(int w, int h);
};

} // namespace gpu
