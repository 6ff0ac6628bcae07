// Image sizes are checked before the frame's targets are allocated (Renderer::renderFrame): the
// GL limits, a proxy texture of the widest target format and a memory budget over every
// per-pixel target, each a geometry::InputError giving the limit; a refused size leaves the
// renderer as it was.
#include "GlTestEnv.h"
#include "RenderTestUtil.h"
#include "TestErrors.h"

#include <geometry/core/Error.h>
#include <geometry/reference/Framing.h>
#include <geometry/scene/Primitives.h>

#include <epoxy/gl.h>

#include <algorithm>
#include <string>

namespace {

class ImageSize : public GlTest {};

// The InputError's message renderFrame throws for `s`, or "" when it renders.
std::string refusal(gpu::Renderer& renderer, const gpu::RenderSettings& s) {
    try {
        renderer.renderFrame(s);
    } catch (const geometry::InputError& e) {
        return e.what();
    }
    return {};
}

TEST_F(ImageSize, BeyondTheGlLimitsIsRefused) {
    const geometry::Scene scene = geometry::loadScene(testutil::dataPath("plates-three.json"));
    gpu::ShaderLoader shaders(gpu::defaultShaderDir());
    gpu::Renderer renderer(scene, shaders);
    GLint maxTexture = 0;
    glGetIntegerv(GL_MAX_TEXTURE_SIZE, &maxTexture);
    gpu::RenderSettings s;
    s.width = 32;
    s.height = 32;
    renderer.renderFrame(s);

    s.width = maxTexture + 1;
    s.height = 16;
    const std::string msg = refusal(renderer, s);
    EXPECT_NE(msg.find("image size " + std::to_string(maxTexture + 1) +
                       "x16 exceeds the largest render target of this GL implementation"),
              std::string::npos)
        << msg;
    EXPECT_NE(msg.find("GL_MAX_TEXTURE_SIZE " + std::to_string(maxTexture)), std::string::npos)
        << msg;
    s.width = 0;
    EXPECT_NE(refusal(renderer, s).find("at least 1x1"), std::string::npos);

    // Nothing changed: the last frame is still there, and the old size still renders.
    EXPECT_EQ(renderer.visibility().width, 32);
    s.width = 32;
    s.height = 32;
    EXPECT_EQ(refusal(renderer, s), "");
}

// A material texture wider than GL_MAX_TEXTURE_SIZE (a scene built in code; the glTF loader
// refuses any over geometry::kMaxTextureSide first) is bad input naming the limit, not a GL
// error inside the upload.
TEST_F(ImageSize, TextureBeyondTheGlLimitIsRefused) {
    GLint maxTexture = 0;
    glGetIntegerv(GL_MAX_TEXTURE_SIZE, &maxTexture);
    geometry::Scene scene = geometry::loadScene(testutil::dataPath("plates-three.json"));
    geometry::MeshData card = geometry::makeQuad({0, 1, 0}, {1, 0, 0}, {0, 0, 1});
    card.texcoords = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    geometry::TextureImage texture;
    texture.width = maxTexture + 1;
    texture.height = 1;
    texture.rgba8.assign(std::size_t(texture.width) * 4, 255);
    card.textures.push_back(std::move(texture));
    geometry::Material leaf;
    leaf.name = "leaf";
    leaf.alphaMode = geometry::AlphaMode::Mask;
    leaf.baseColorTexture = 0;
    card.materials.push_back(leaf);
    card.triangleMaterial.assign(card.triangles.size(), 0);
    scene.objects.push_back({"wide card", geometry::ShadowMethod::Auto, std::move(card)});
    gpu::ShaderLoader shaders(gpu::defaultShaderDir());
    const auto msg = testutil::errorOf<geometry::InputError>([&] {
        gpu::Renderer renderer(scene, shaders);
        gpu::RenderSettings s;
        s.width = s.height = 32;
        renderer.renderFrame(s);
    });
    ASSERT_TRUE(msg) << "a texture past GL_MAX_TEXTURE_SIZE rendered";
    EXPECT_NE(msg->find("object 'wide card': texture 0 is " + std::to_string(maxTexture + 1) +
                        "x1 pixels; this GL implementation's textures are " +
                        std::to_string(maxTexture) +
                        " pixels on a side at most (GL_MAX_TEXTURE_SIZE)"),
              std::string::npos)
        << *msg;
    EXPECT_EQ(glGetError(), GLenum(GL_NO_ERROR));
}

// The budget covers the method's own targets: 64x64 fits hard's 64 bytes a pixel (the frame's
// targets and the error view's reference) in 270,000 bytes, not wedges-blend's with 8 parts of
// 16 bits (64 + 240).
TEST_F(ImageSize, MemoryBudgetCountsTheMethodsTargets) {
    const geometry::Scene scene = geometry::loadScene(testutil::dataPath("plates-three.json"));
    gpu::ShaderLoader shaders(gpu::defaultShaderDir());
    gpu::RenderSettings s;
    s.width = s.height = 64;
    s.targetMemoryBudget = 270'000;
    {
        gpu::Renderer renderer(scene, shaders);
        EXPECT_EQ(refusal(renderer, s), "");
        s.width = s.height = 128; // 1,048,576 bytes
        const std::string msg = refusal(renderer, s);
        EXPECT_NE(msg.find("image size 128x128 needs about 1.0 MiB of render targets (64 bytes "
                           "per pixel with method 'hard'), more than the budget of 263.7 KiB "
                           "(RenderSettings::targetMemoryBudget); the largest square size within "
                           "it is 64x64"),
                  std::string::npos)
            << msg;
    }
    gpu::Renderer renderer(scene, shaders);
    s.width = s.height = 64;
    s.method = "wedges-blend";
    s.parameters = {{"parts", "8"}, {"bits", "16"}};
    const std::string msg = refusal(renderer, s);
    EXPECT_NE(msg.find("(304 bytes per pixel with method 'wedges-blend')"), std::string::npos)
        << msg;
    EXPECT_NE(msg.find("the largest square size within it is 29x29"), std::string::npos) << msg;
    s.width = s.height = 29;
    EXPECT_EQ(refusal(renderer, s), "");
}

// Where the GL implementation cannot create a target of the widest format at its maximum side
// (llvmpipe: textures over about 1.5 GiB, although GL_MAX_TEXTURE_SIZE is 16384), that size is
// refused by its proxy query, naming the largest square it accepts, before any allocation.
TEST_F(ImageSize, ProxyRefusalNamesTheLargestSquare) {
    GLint maxTexture = 0;
    glGetIntegerv(GL_MAX_TEXTURE_SIZE, &maxTexture);
    glTexImage2D(GL_PROXY_TEXTURE_2D, 0, GL_RGBA32F, maxTexture, maxTexture, 0, GL_RGBA, GL_FLOAT,
                 nullptr);
    GLint accepted = 0;
    glGetTexLevelParameteriv(GL_PROXY_TEXTURE_2D, 0, GL_TEXTURE_WIDTH, &accepted);
    const std::string renderer = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
    if (renderer.find("llvmpipe") != std::string::npos) {
        ASSERT_EQ(accepted, 0) << "llvmpipe accepts a " << maxTexture << "^2 RGBA32F texture now";
    }
    if (accepted != 0) return; // this implementation can: nothing to refuse here

    const geometry::Scene scene = geometry::loadScene(testutil::dataPath("plates-three.json"));
    gpu::ShaderLoader shaders(gpu::defaultShaderDir());
    gpu::Renderer r(scene, shaders);
    gpu::RenderSettings s;
    s.width = s.height = maxTexture;
    s.targetMemoryBudget = std::size_t(1) << 62; // only the proxy speaks
    const std::string msg = refusal(r, s);
    const std::string size = std::to_string(maxTexture) + "x" + std::to_string(maxTexture);
    EXPECT_NE(msg.find("image size " + size + ": this GL implementation (" + renderer +
                       ") cannot create a " + size + " RGBA32F render target"),
              std::string::npos)
        << msg;
    const auto at = msg.find("the largest square size it accepts is ");
    ASSERT_NE(at, std::string::npos) << msg;
    const int largest = std::stoi(msg.substr(at + 38));
    EXPECT_GT(largest, 0);
    EXPECT_LT(largest, maxTexture);
    // That square is accepted by the proxy, one more is not.
    for (int side : {largest, largest + 1}) {
        glTexImage2D(GL_PROXY_TEXTURE_2D, 0, GL_RGBA32F, side, side, 0, GL_RGBA, GL_FLOAT,
                     nullptr);
        GLint w = 0;
        glGetTexLevelParameteriv(GL_PROXY_TEXTURE_2D, 0, GL_TEXTURE_WIDTH, &w);
        EXPECT_EQ(w != 0, side == largest) << side;
    }
}

} // namespace
