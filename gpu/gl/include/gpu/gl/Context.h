// OpenGL 4.5 core contexts behind one interface: a surfaceless EGL context for headless rendering
// (tests, penumbra-render, penumbra-bench; works on Mesa llvmpipe and NVIDIA's EGL) and a GLFW
// window for the viewer. Both load GL through libepoxy and can enable KHR_debug output.
#pragma once

#include <memory>
#include <stdexcept>
#include <string>

struct GLFWwindow;

namespace gpu {

class ContextError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

struct ContextInfo {
    std::string renderer; // GL_RENDERER, e.g. "llvmpipe (LLVM 15.0.6, 256 bits)"
    std::string version;  // GL_VERSION
    std::string vendor;   // GL_VENDOR
};

class Context {
public:
    virtual ~Context() = default;
    virtual void makeCurrent() = 0;
    ContextInfo info() const; // queries the current context
};

struct EglContextDesc {
    bool debug = true; // create a debug context and route KHR_debug errors (gpu/gl/Debug.h)
};

// Surfaceless EGL (EGL_MESA_platform_surfaceless, else EGL_EXT_platform_device), no config,
// OpenGL core 4.5. Throws ContextError with the EGL error name on failure. The constructor makes
// the context current; destroying the current context leaves none current on this thread. The
// EGL display is shared and reference counted across EglContexts (terminated with the last).
class EglContext final : public Context {
public:
    explicit EglContext(const EglContextDesc& desc = {});
    ~EglContext() override;
    EglContext(const EglContext&) = delete;
    EglContext& operator=(const EglContext&) = delete;
    void makeCurrent() override;

private:
    void* mDisplay = nullptr;
    void* mContext = nullptr;
};

// True if some EGL display can be initialised at all (tests may skip only when this is false,
// and never when the environment variable CI is set).
bool eglDisplayAvailable();

struct GlfwContextDesc {
    int width = 1280;
    int height = 720;
    const char* title = "penumbra";
    bool debug = true;
};

class GlfwContext final : public Context {
public:
    explicit GlfwContext(const GlfwContextDesc& desc = {});
    ~GlfwContext() override;
    GlfwContext(const GlfwContext&) = delete;
    GlfwContext& operator=(const GlfwContext&) = delete;
    void makeCurrent() override;
    GLFWwindow* window() const { return mWindow; }
    bool shouldClose() const;
    void swapBuffers();

private:
    GLFWwindow* mWindow = nullptr;
};

} // namespace gpu
