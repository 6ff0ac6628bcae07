// EGL context creation, GL version/profile, and a clear + read-back through an FBO.
#include "GlTestEnv.h"

#include <gpu/gl/Context.h>
#include <gpu/gl/Debug.h>
#include <gpu/gl/Objects.h>

#include <cstdlib>
#include <optional>
#include <string>

namespace {

class ContextTest : public GlTest {};

TEST_F(ContextTest, CreatesCore45DebugContext) {
    gpu::ContextInfo info = context().info();
    EXPECT_FALSE(info.renderer.empty());
    EXPECT_FALSE(info.version.empty());
    EXPECT_FALSE(info.vendor.empty());

    GLint major = 0, minor = 0, profile = 0, flags = 0;
    glGetIntegerv(GL_MAJOR_VERSION, &major);
    glGetIntegerv(GL_MINOR_VERSION, &minor);
    glGetIntegerv(GL_CONTEXT_PROFILE_MASK, &profile);
    glGetIntegerv(GL_CONTEXT_FLAGS, &flags);
    EXPECT_GE(major * 10 + minor, 45) << info.version;
    EXPECT_TRUE(profile & GL_CONTEXT_CORE_PROFILE_BIT) << "profile mask " << profile;
    EXPECT_TRUE(flags & GL_CONTEXT_FLAG_DEBUG_BIT) << "the shared test context asks for debug";
    EXPECT_TRUE(glIsEnabled(GL_DEBUG_OUTPUT));
    EXPECT_GE(epoxy_gl_version(), 45);
}

TEST_F(ContextTest, ClearAndReadBackSmallFbo) {
    gpu::Texture colour({.width = 8, .height = 4, .format = GL_RGBA32F, .label = "clear-target"});
    gpu::Framebuffer fbo({.attachments = {{GL_COLOR_ATTACHMENT0, &colour}}, .label = "clear"});

    // The classic bind + glClear path, as the passes use it.
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, fbo.id());
    glViewport(0, 0, 8, 4);
    glClearColor(0.25f, 0.5f, 0.75f, 1.0f);
    glClear(GL_COLOR_BUFFER_BIT);
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, 0);
    gpu::checkGl("clear");

    std::vector<float> pixels = colour.readFloat(4);
    ASSERT_EQ(pixels.size(), 8u * 4u * 4u);
    for (std::size_t i = 0; i < pixels.size(); i += 4) {
        // Exact: a float target stores the clear colour unchanged.
        ASSERT_EQ(pixels[i + 0], 0.25f) << "pixel " << i / 4;
        ASSERT_EQ(pixels[i + 1], 0.5f);
        ASSERT_EQ(pixels[i + 2], 0.75f);
        ASSERT_EQ(pixels[i + 3], 1.0f);
    }
}

TEST_F(ContextTest, SecondContextCoexistsWithSharedOne) {
    // An object in the shared context must survive another context's creation and destruction
    // (the EGL display is reference counted, not terminated under our feet).
    gpu::Buffer keep({.size = 16, .label = "survivor"});
    {
        gpu::EglContext other({.debug = false});
        other.makeCurrent();
        EXPECT_FALSE(other.info().renderer.empty());
        GLint flags = 0;
        glGetIntegerv(GL_CONTEXT_FLAGS, &flags);
        EXPECT_FALSE(flags & GL_CONTEXT_FLAG_DEBUG_BIT);
        // Not shared with the first context: the name means nothing here.
        EXPECT_FALSE(glIsBuffer(keep.id()));
    }
    context().makeCurrent();
    EXPECT_TRUE(glIsBuffer(keep.id()));
    EXPECT_FALSE(context().info().renderer.empty());
}

TEST(ContextStandaloneTest, EglDisplayAvailableAgreesWithSharedContext) {
    if (gltest::sharedContext().context) {
        EXPECT_TRUE(gpu::eglDisplayAvailable());
    }
}

// GLFW's X11 backend fails glfwInit deterministically without DISPLAY (and the Wayland one
// without WAYLAND_DISPLAY); the error must say so instead of crashing or returning a null window.
TEST(ContextStandaloneTest, GlfwThrowsClearErrorWithoutDisplay) {
    auto save = [](const char* name) -> std::optional<std::string> {
        const char* v = std::getenv(name);
        return v ? std::optional<std::string>(v) : std::nullopt;
    };
    std::optional<std::string> display = save("DISPLAY");
    std::optional<std::string> wayland = save("WAYLAND_DISPLAY");
    unsetenv("DISPLAY");
    unsetenv("WAYLAND_DISPLAY");

    std::string message;
    try {
        gpu::GlfwContext window({.width = 64, .height = 64, .title = "test"});
        ADD_FAILURE() << "GlfwContext was created without a display";
    } catch (const gpu::ContextError& e) {
        message = e.what();
    }
    if (display) setenv("DISPLAY", display->c_str(), 1);
    if (wayland) setenv("WAYLAND_DISPLAY", wayland->c_str(), 1);
    EXPECT_NE(message.find("GLFW"), std::string::npos) << message;
    EXPECT_NE(message.find("DISPLAY"), std::string::npos) << message;
    // The failed GLFW attempt must not have disturbed the EGL context.
    if (gltest::currentContext()) {
        EXPECT_EQ(glGetError(), static_cast<GLenum>(GL_NO_ERROR));
    }
}

} // namespace
