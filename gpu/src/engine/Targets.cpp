#include "engine/Targets.h"

namespace gpu {

void Targets::resize(int w, int h) {
    width = w;
    height = h;
    depthStencil = Texture({.width = w, .height = h, .format = GL_DEPTH32F_STENCIL8,
                            .label = "depth-stencil"});
    position = Texture({.width = w, .height = h, .format = GL_RGBA32F, .label = "g-position"});
    normal = Texture({.width = w, .height = h, .format = GL_RGBA32F, .label = "g-normal"});
    albedo = Texture({.width = w, .height = h, .format = GL_RGBA8, .label = "g-albedo"});
    shading = Texture({.width = w, .height = h, .format = GL_RGBA16F, .label = "g-shading"});
    visibility = Texture({.width = w, .height = h, .format = GL_R32F, .label = "visibility"});
    image = Texture({.width = w, .height = h, .format = GL_RGBA8, .label = "image"});
    gbuffer = Framebuffer({.attachments = {{GL_COLOR_ATTACHMENT0, &position},
                                           {GL_COLOR_ATTACHMENT1, &normal},
                                           {GL_COLOR_ATTACHMENT2, &albedo},
                                           {GL_COLOR_ATTACHMENT3, &shading},
                                           {GL_DEPTH_STENCIL_ATTACHMENT, &depthStencil}},
                           .label = "gbuffer"});
    visibilityFbo = Framebuffer({.attachments = {{GL_COLOR_ATTACHMENT0, &visibility},
                                                 {GL_DEPTH_STENCIL_ATTACHMENT, &depthStencil}},
                                 .label = "visibility"});
    imageFbo = Framebuffer({.attachments = {{GL_COLOR_ATTACHMENT0, &image}}, .label = "image"});
}

} // namespace gpu
