// Render targets shared by the passes of one frame; recreated when the size changes.
#pragma once

#include <gpu/gl/Objects.h>

namespace gpu {

struct Targets {
    // Bytes per pixel of what resize() allocates: depth-stencil (D32F_S8, stored in 8 bytes),
    // position and normal (RGBA32F), albedo (RGBA8), shading normal (RGBA16F), visibility
    // (R32F), image (RGBA8).
    static constexpr std::size_t kBytesPerPixel = 8 + 16 + 16 + 4 + 8 + 4 + 4;
    // The largest format among them, the one a size must fit first.
    static constexpr GLenum kWidestFormat = GL_RGBA32F;


    int width = 0, height = 0;
    // normal: the flat geometric normal every method's visibility reads; shading: the normal n.l
    // uses (interpolated vertex normals where the file has them).
    Texture depthStencil, position, normal, albedo, shading, visibility, image;
    Framebuffer gbuffer, visibilityFbo, imageFbo;

    void resize(int w, int h);
};

} // namespace gpu
