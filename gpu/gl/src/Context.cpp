// OpenGL 4.5 core contexts: surfaceless EGL (headless) and GLFW (windowed), both loaded through
// libepoxy, which resolves GL entry points against whichever EGL/GLX context is current.
#include <gpu/gl/Context.h>
#include <gpu/gl/Debug.h>

#include <epoxy/egl.h>
#include <epoxy/gl.h>

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

// AddressSanitizer: GCC defines __SANITIZE_ADDRESS__, clang answers __has_feature.
#if defined(__SANITIZE_ADDRESS__)
#define PENUMBRA_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define PENUMBRA_ASAN 1
#endif
#endif

#if defined(PENUMBRA_ASAN)
#include <dlfcn.h>
#include <link.h>
#endif

#include <cstdio>
#include <map>
#include <mutex>
#include <string>
#include <vector>

namespace gpu {

namespace {

// Under AddressSanitizer only (the sanitizer build, docs/hardening.md, Sanitizers): once a context is made,
// the Mesa driver it loaded (*_dri.so) is marked never to be unloaded. eglTerminate and GLX's
// display teardown dlclose it while its own globals still point at what it allocated, and at exit
// LeakSanitizer, which no longer sees those globals nor knows the unloaded code's name, reports
// those blocks as leaks that no suppression can name. Loaded, its globals keep them reachable.
void keepGlDriversLoaded() {
#if defined(PENUMBRA_ASAN)
    std::vector<std::string> drivers; // dlopen is not called inside the walk of the loader's list
    dl_iterate_phdr(
        [](dl_phdr_info* info, std::size_t, void* out) {
            const std::string name = info->dlpi_name ? info->dlpi_name : "";
            if (name.size() > 7 && name.ends_with("_dri.so")) {
                static_cast<std::vector<std::string>*>(out)->push_back(name);
            }
            return 0;
        },
        &drivers);
    for (const std::string& name : drivers) {
        dlopen(name.c_str(), RTLD_NOW | RTLD_NOLOAD | RTLD_NODELETE); // a reference never closed
    }
#endif
}

const char* eglErrorName(EGLint error) {
    switch (error) {
    case EGL_SUCCESS:
        return "EGL_SUCCESS";
    case EGL_NOT_INITIALIZED:
        return "EGL_NOT_INITIALIZED";
    case EGL_BAD_ACCESS:
        return "EGL_BAD_ACCESS";
    case EGL_BAD_ALLOC:
        return "EGL_BAD_ALLOC";
    case EGL_BAD_ATTRIBUTE:
        return "EGL_BAD_ATTRIBUTE";
    case EGL_BAD_CONFIG:
        return "EGL_BAD_CONFIG";
    case EGL_BAD_CONTEXT:
        return "EGL_BAD_CONTEXT";
    case EGL_BAD_CURRENT_SURFACE:
        return "EGL_BAD_CURRENT_SURFACE";
    case EGL_BAD_DISPLAY:
        return "EGL_BAD_DISPLAY";
    case EGL_BAD_MATCH:
        return "EGL_BAD_MATCH";
    case EGL_BAD_NATIVE_PIXMAP:
        return "EGL_BAD_NATIVE_PIXMAP";
    case EGL_BAD_NATIVE_WINDOW:
        return "EGL_BAD_NATIVE_WINDOW";
    case EGL_BAD_PARAMETER:
        return "EGL_BAD_PARAMETER";
    case EGL_BAD_SURFACE:
        return "EGL_BAD_SURFACE";
    case EGL_CONTEXT_LOST:
        return "EGL_CONTEXT_LOST";
    default:
        return "unknown EGL error";
    }
}

std::string eglFailure(const char* step) {
    EGLint error = eglGetError();
    char code[16];
    std::snprintf(code, sizeof code, "0x%04X", static_cast<unsigned>(error));
    return std::string(step) + " failed: " + eglErrorName(error) + " (" + code + ")";
}

bool hasClientExtension(const char* name) {
    // Client extensions are queried on EGL_NO_DISPLAY; epoxy handles the EGL 1.5 / extension
    // split and a missing EGL_EXT_client_extensions (returns false).
    return epoxy_has_egl_extension(EGL_NO_DISPLAY, name);
}

// eglInitialize/eglTerminate are not reference counted by EGL itself: eglTerminate releases the
// display for every context in the process. The process may hold several EglContexts on the same
// display (e.g. the shared test context plus one created by a test), so we count them here and
// terminate only when the last one goes away.
std::mutex gDisplayMutex;
std::map<EGLDisplay, int> gDisplayRefs;

struct OpenedDisplay {
    EGLDisplay display = EGL_NO_DISPLAY;
    EGLint major = 0, minor = 0;
    std::string platform;
};

// Tries one explicit platform: get the display and initialise it. On failure returns
// EGL_NO_DISPLAY and appends the reason to `errors`.
OpenedDisplay tryPlatform(EGLenum platform, void* nativeDisplay, const char* platformName,
                          std::string& errors) {
    OpenedDisplay out;
    EGLDisplay display = eglGetPlatformDisplayEXT(platform, nativeDisplay, nullptr);
    if (display == EGL_NO_DISPLAY) {
        errors +=
            std::string("\n  ") + platformName + ": " + eglFailure("eglGetPlatformDisplayEXT");
        return out;
    }
    std::lock_guard lock(gDisplayMutex);
    EGLint major = 0, minor = 0;
    // Initialising an already initialised display is a no-op that returns its version, so this
    // is also correct when another EglContext holds the display.
    if (!eglInitialize(display, &major, &minor)) {
        errors += std::string("\n  ") + platformName + ": " + eglFailure("eglInitialize");
        return out;
    }
    ++gDisplayRefs[display];
    out.display = display;
    out.major = major;
    out.minor = minor;
    out.platform = platformName;
    return out;
}

void releaseDisplay(EGLDisplay display) {
    std::lock_guard lock(gDisplayMutex);
    auto it = gDisplayRefs.find(display);
    if (it == gDisplayRefs.end()) return;
    if (--it->second == 0) {
        gDisplayRefs.erase(it);
        eglTerminate(display);
    }
}

// Surfaceless Mesa first (llvmpipe, any Mesa driver without a window system); then the device
// platform with the first enumerated device (NVIDIA's headless EGL). Both are explicit platforms:
// eglGetDisplay(EGL_DEFAULT_DISPLAY) would silently pick X11/Wayland when DISPLAY is set.
OpenedDisplay openDisplay() {
    std::string errors;
    if (!hasClientExtension("EGL_EXT_platform_base")) {
        throw ContextError("EGL: EGL_EXT_platform_base is not supported (no explicit platforms)");
    }
    if (hasClientExtension("EGL_MESA_platform_surfaceless")) {
        OpenedDisplay d = tryPlatform(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY,
                                      "EGL_PLATFORM_SURFACELESS_MESA", errors);
        if (d.display != EGL_NO_DISPLAY) return d;
    } else {
        errors += "\n  EGL_MESA_platform_surfaceless: not supported";
    }
    if (hasClientExtension("EGL_EXT_platform_device") &&
        hasClientExtension("EGL_EXT_device_enumeration")) {
        EGLDeviceEXT device = nullptr;
        EGLint count = 0;
        if (eglQueryDevicesEXT(1, &device, &count) && count > 0) {
            OpenedDisplay d =
                tryPlatform(EGL_PLATFORM_DEVICE_EXT, device, "EGL_PLATFORM_DEVICE_EXT", errors);
            if (d.display != EGL_NO_DISPLAY) return d;
        } else if (count == 0) {
            errors += "\n  EGL_PLATFORM_DEVICE_EXT: eglQueryDevicesEXT found no device";
        } else {
            errors += "\n  EGL_PLATFORM_DEVICE_EXT: " + eglFailure("eglQueryDevicesEXT");
        }
    } else {
        errors += "\n  EGL_EXT_platform_device/EGL_EXT_device_enumeration: not supported";
    }
    throw ContextError("EGL: no display could be initialised:" + errors);
}

std::string glString(GLenum name) {
    const GLubyte* s = glGetString(name);
    return s ? reinterpret_cast<const char*>(s) : "";
}

// Shared by both context kinds: epoxy encodes "4.5" as 45.
void requireGl45(const char* what) {
    int version = epoxy_gl_version();
    if (version < 45 || epoxy_is_desktop_gl() == 0) {
        throw ContextError(std::string(what) + ": OpenGL 4.5 core required, got '" +
                           glString(GL_VERSION) + "' on '" + glString(GL_RENDERER) + "'");
    }
}

} // namespace

ContextInfo Context::info() const {
    return {glString(GL_RENDERER), glString(GL_VERSION), glString(GL_VENDOR)};
}

// ---------------------------------------------------------------------------------------------
// EglContext

EglContext::EglContext(const EglContextDesc& desc) {
    OpenedDisplay opened = openDisplay();
    EGLDisplay display = opened.display;
    mDisplay = display;
    // From here on the display reference must be released if construction fails.
    auto fail = [&](const std::string& message) -> ContextError {
        if (mContext) eglDestroyContext(display, mContext);
        mContext = nullptr;
        releaseDisplay(display);
        mDisplay = nullptr;
        return ContextError("EGL (" + opened.platform + "): " + message);
    };

    if (!epoxy_has_egl_extension(display, "EGL_KHR_no_config_context")) {
        throw fail("EGL_KHR_no_config_context is not supported (needed for a surfaceless "
                   "context without an EGLConfig)");
    }
    if (!eglBindAPI(EGL_OPENGL_API)) throw fail(eglFailure("eglBindAPI(EGL_OPENGL_API)"));

    // EGL 1.5 has the debug flag as its own attribute; EGL 1.4 + KHR_create_context puts it in
    // the flags bitfield. The version/profile attributes share their values across both.
    bool egl15 = opened.major > 1 || (opened.major == 1 && opened.minor >= 5);
    if (!egl15 && !epoxy_has_egl_extension(display, "EGL_KHR_create_context")) {
        throw fail("EGL 1.4 without EGL_KHR_create_context cannot request a 4.5 core context");
    }
    std::vector<EGLint> attribs = {
        EGL_CONTEXT_MAJOR_VERSION_KHR,       4,
        EGL_CONTEXT_MINOR_VERSION_KHR,       5,
        EGL_CONTEXT_OPENGL_PROFILE_MASK_KHR, EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT_KHR,
    };
    if (desc.debug) {
        if (egl15) {
            attribs.insert(attribs.end(), {EGL_CONTEXT_OPENGL_DEBUG, EGL_TRUE});
        } else {
            attribs.insert(attribs.end(),
                           {EGL_CONTEXT_FLAGS_KHR, EGL_CONTEXT_OPENGL_DEBUG_BIT_KHR});
        }
    }
    attribs.push_back(EGL_NONE);

    mContext = eglCreateContext(display, EGL_NO_CONFIG_KHR, EGL_NO_CONTEXT, attribs.data());
    if (mContext == EGL_NO_CONTEXT) {
        mContext = nullptr;
        throw fail(eglFailure("eglCreateContext(OpenGL 4.5 core, no config)"));
    }
    if (!eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, mContext)) {
        throw fail(eglFailure("eglMakeCurrent(EGL_NO_SURFACE)"));
    }
    keepGlDriversLoaded();
    try {
        requireGl45("EglContext");
        if (desc.debug) installDebugOutput();
    } catch (const std::exception& e) {
        eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
        throw fail(e.what());
    }
}

EglContext::~EglContext() {
    if (!mDisplay) return;
    // Only release the context if it is ours: another EglContext may be current on this thread
    // and must stay current.
    if (mContext && eglGetCurrentContext() == mContext) {
        eglMakeCurrent(mDisplay, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    }
    if (mContext) eglDestroyContext(mDisplay, mContext);
    releaseDisplay(mDisplay);
}

void EglContext::makeCurrent() {
    if (!eglMakeCurrent(mDisplay, EGL_NO_SURFACE, EGL_NO_SURFACE, mContext)) {
        throw ContextError("EGL: " + eglFailure("eglMakeCurrent"));
    }
}

bool eglDisplayAvailable() {
    try {
        OpenedDisplay d = openDisplay();
        releaseDisplay(d.display);
        return true;
    } catch (const ContextError&) {
        return false;
    }
}

// ---------------------------------------------------------------------------------------------
// GlfwContext

namespace {

// GLFW reports failures through a global callback, not return values: keep the last message so
// that ContextError can say why (e.g. "X11: The DISPLAY environment variable is missing").
std::mutex gGlfwMutex;
std::string gGlfwLastError;
int gGlfwRefs = 0;

void glfwErrorCallback(int code, const char* description) {
    std::lock_guard lock(gGlfwMutex);
    char buf[32];
    std::snprintf(buf, sizeof buf, " (0x%05X)", static_cast<unsigned>(code));
    gGlfwLastError = std::string(description ? description : "unknown error") + buf;
}

std::string takeGlfwError() {
    std::lock_guard lock(gGlfwMutex);
    std::string e = gGlfwLastError.empty() ? "no error reported" : gGlfwLastError;
    gGlfwLastError.clear();
    return e;
}

void releaseGlfw() {
    if (--gGlfwRefs == 0) glfwTerminate();
}

} // namespace

GlfwContext::GlfwContext(const GlfwContextDesc& desc) {
    glfwSetErrorCallback(glfwErrorCallback);
    // glfwInit is idempotent while initialised; glfwTerminate destroys every window, so the
    // library is terminated only with the last GlfwContext.
    if (!glfwInit()) throw ContextError("GLFW: glfwInit failed: " + takeGlfwError());
    ++gGlfwRefs;

    glfwDefaultWindowHints();
    glfwWindowHint(GLFW_CLIENT_API, GLFW_OPENGL_API);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 4);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 5);
    glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
    glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
    glfwWindowHint(GLFW_OPENGL_DEBUG_CONTEXT, desc.debug ? GLFW_TRUE : GLFW_FALSE);
    mWindow = glfwCreateWindow(desc.width, desc.height, desc.title ? desc.title : "penumbra",
                               nullptr, nullptr);
    if (!mWindow) {
        std::string why = takeGlfwError();
        releaseGlfw();
        throw ContextError("GLFW: glfwCreateWindow (OpenGL 4.5 core) failed: " + why);
    }
    glfwMakeContextCurrent(mWindow);
    keepGlDriversLoaded();
    try {
        requireGl45("GlfwContext");
        if (desc.debug) installDebugOutput();
    } catch (const std::exception& e) {
        glfwMakeContextCurrent(nullptr);
        glfwDestroyWindow(mWindow);
        mWindow = nullptr;
        releaseGlfw();
        throw ContextError(e.what());
    }
}

GlfwContext::~GlfwContext() {
    if (!mWindow) return;
    if (glfwGetCurrentContext() == mWindow) glfwMakeContextCurrent(nullptr);
    glfwDestroyWindow(mWindow);
    releaseGlfw();
}

void GlfwContext::makeCurrent() {
    glfwMakeContextCurrent(mWindow);
}

bool GlfwContext::shouldClose() const {
    return glfwWindowShouldClose(mWindow) != 0;
}

void GlfwContext::swapBuffers() {
    glfwSwapBuffers(mWindow);
}

} // namespace gpu
