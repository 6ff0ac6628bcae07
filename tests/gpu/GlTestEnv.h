// Shared environment for GL tests: one surfaceless EGL context per process and the GlTest
// fixture.
// - SetUp makes the context current and clears stale errors; TearDown fails the test on any
//   KHR_debug error or glGetError flag the test left behind.
// - If no context can be created the test FAILS when CI is set or an EGL display exists (a broken
//   driver setup must not pass as "skipped"); it may skip only when no EGL display exists at all.
#pragma once

#include <gpu/gl/Context.h>
#include <gpu/gl/Debug.h>

#include <gtest/gtest.h>

#include <cstdlib>
#include <memory>
#include <string>

namespace gltest {

struct SharedContext {
    gpu::EglContext* context = nullptr;
    std::string error; // why creation failed
};

// Created on first use and deliberately never destroyed: tearing down EGL from a static
// destructor races the driver's own atexit handlers, and the process is ending anyway.
inline SharedContext& sharedContext() {
    static SharedContext shared = [] {
        SharedContext s;
        try {
            s.context = new gpu::EglContext({.debug = true});
        } catch (const std::exception& e) {
            s.error = e.what();
        }
        return s;
    }();
    return shared;
}

// The shared context, current on this thread, or null if it could not be created.
inline gpu::EglContext* currentContext() {
    SharedContext& shared = sharedContext();
    if (shared.context) shared.context->makeCurrent();
    return shared.context;
}

} // namespace gltest

class GlTest : public ::testing::Test {
protected:
    void SetUp() override {
        gpu::EglContext* context = gltest::currentContext();
        if (!context) {
            const std::string& why = gltest::sharedContext().error;
            if (std::getenv("CI") != nullptr) {
                GTEST_FAIL() << "no GL context and CI is set: " << why;
            }
            if (gpu::eglDisplayAvailable()) {
                GTEST_FAIL() << "an EGL display exists but no GL 4.5 context: " << why;
            }
            GTEST_SKIP() << "no EGL display on this machine: " << why;
        }
        // Errors from an earlier failed test must not be blamed on this one.
        gpu::takeDebugErrors();
        while (glGetError() != GL_NO_ERROR) {
        }
    }

    void TearDown() override {
        // A test may have made another context current (or destroyed it); check ours.
        if (!gltest::currentContext()) return;
        std::vector<std::string> errors = gpu::takeDebugErrors();
        std::string joined;
        for (const std::string& e : errors)
            joined += "\n  " + e;
        EXPECT_TRUE(errors.empty()) << "GL debug errors left by the test:" << joined;
        GLenum error = glGetError();
        EXPECT_EQ(error, static_cast<GLenum>(GL_NO_ERROR))
            << "glGetError left set: 0x" << std::hex << error;
        while (glGetError() != GL_NO_ERROR) {
        }
    }

    gpu::EglContext& context() { return *gltest::sharedContext().context; }
};
