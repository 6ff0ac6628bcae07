// Error capture (glGetError + KHR_debug), debug groups and GPU pass timers.
#include "GlTestEnv.h"

#include <gpu/gl/Debug.h>
#include <gpu/gl/Objects.h>

#include <string>

namespace {

class DebugTest : public GlTest {};

bool contains(const std::string& haystack, const std::string& needle) {
    return haystack.find(needle) != std::string::npos;
}

// Not a texture target: Mesa (and the spec) raise GL_INVALID_ENUM.
constexpr GLenum kBogusTarget = 0x1234;

TEST_F(DebugTest, CheckGlPassesWhenClean) {
    EXPECT_NO_THROW(gpu::checkGl("nothing"));
}

TEST_F(DebugTest, CheckGlThrowsNamingWhereAndError) {
    glBindTexture(kBogusTarget, 0);
    try {
        gpu::checkGl("bogus-bind");
        FAIL() << "GL error not reported";
    } catch (const gpu::GlError& e) {
        std::string what = e.what();
        EXPECT_TRUE(contains(what, "bogus-bind")) << what;
        EXPECT_TRUE(contains(what, "GL_INVALID_ENUM")) << what;
    }
    // checkGl consumed both the error flag and the recorded debug message.
    EXPECT_EQ(glGetError(), static_cast<GLenum>(GL_NO_ERROR));
    EXPECT_TRUE(gpu::takeDebugErrors().empty());
}

TEST_F(DebugTest, DebugCallbackRecordsErrors) {
    glBindTexture(kBogusTarget, 0);
    std::vector<std::string> errors = gpu::takeDebugErrors();
    ASSERT_EQ(errors.size(), 1u);
    EXPECT_TRUE(contains(errors[0], "API")) << errors[0];
    EXPECT_TRUE(contains(errors[0], "ERROR")) << errors[0];
    EXPECT_TRUE(gpu::takeDebugErrors().empty()) << "take clears the record";
    EXPECT_EQ(glGetError(), static_cast<GLenum>(GL_INVALID_ENUM));

    // Application messages of low severity are not errors.
    glDebugMessageInsert(GL_DEBUG_SOURCE_APPLICATION, GL_DEBUG_TYPE_MARKER, 1,
                         GL_DEBUG_SEVERITY_LOW, -1, "just a marker");
    EXPECT_TRUE(gpu::takeDebugErrors().empty());
    // ... but high-severity ones are, whatever their type.
    glDebugMessageInsert(GL_DEBUG_SOURCE_APPLICATION, GL_DEBUG_TYPE_OTHER, 2,
                         GL_DEBUG_SEVERITY_HIGH, -1, "app says this is bad");
    errors = gpu::takeDebugErrors();
    ASSERT_EQ(errors.size(), 1u);
    EXPECT_TRUE(contains(errors[0], "app says this is bad")) << errors[0];
}

TEST_F(DebugTest, DebugGroupsPushAndPopBalanced) {
    auto depth = [] {
        GLint d = -1;
        glGetIntegerv(GL_DEBUG_GROUP_STACK_DEPTH, &d);
        return d;
    };
    GLint base = depth();
    {
        gpu::DebugGroup outer("outer");
        EXPECT_EQ(depth(), base + 1);
        {
            gpu::DebugGroup inner(std::string(1000, 'x')); // long names are clamped
            EXPECT_EQ(depth(), base + 2);
        }
        EXPECT_EQ(depth(), base + 1);
        gpu::ScopedPass pass(nullptr, "untimed");
        EXPECT_EQ(depth(), base + 2);
    }
    EXPECT_EQ(depth(), base);
}

TEST_F(DebugTest, GpuTimersMergeRepeatedNamesInBeginOrder) {
    gpu::Texture target({.width = 64, .height = 64, .format = GL_RGBA8});
    gpu::Framebuffer fbo({.attachments = {{GL_COLOR_ATTACHMENT0, &target}}});
    const float colour[4] = {0.1f, 0.2f, 0.3f, 1.0f};
    auto work = [&] { glClearNamedFramebufferfv(fbo.id(), GL_COLOR, 0, colour); };

    gpu::GpuTimers timers;
    for (int frame = 0; frame < 3; ++frame) {
        int a = timers.begin("shadow");
        work();
        timers.end(a);
        {
            gpu::ScopedPass outer(&timers, "wedges");
            gpu::ScopedPass nested(&timers, "wedges/blend"); // nesting: timestamps, not elapsed
            work();
        }
        {
            gpu::ScopedPass again(&timers, "shadow"); // same name: merged into the first entry
            work();
        }
        std::vector<gpu::PassTime> times = timers.resolve();
        ASSERT_EQ(times.size(), 3u) << "frame " << frame;
        EXPECT_EQ(times[0].name, "shadow");
        EXPECT_EQ(times[1].name, "wedges");
        EXPECT_EQ(times[2].name, "wedges/blend");
        for (const gpu::PassTime& t : times) {
            EXPECT_GE(t.ms, 0.0) << t.name;
            EXPECT_LT(t.ms, 10'000.0) << t.name; // sanity: nanoseconds were scaled to ms
        }
    }
    EXPECT_TRUE(timers.resolve().empty()) << "resolve starts a new, empty frame";
    gpu::checkGl("timers");
}

TEST_F(DebugTest, GpuTimersCloseAPassLeftOpen) {
    gpu::GpuTimers timers;
    timers.begin("left-open");
    std::vector<gpu::PassTime> times = timers.resolve();
    ASSERT_EQ(times.size(), 1u);
    EXPECT_EQ(times[0].name, "left-open");
    EXPECT_GE(times[0].ms, 0.0);
}

} // namespace
