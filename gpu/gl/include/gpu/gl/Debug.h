// GL error reporting and per-pass instrumentation.
// - KHR_debug output: messages of type ERROR (and any HIGH severity message) are recorded; tests
//   fail on them and apps print them. glGetError is checked after each pass as well.
// - DebugGroup: RAII glPushDebugGroup/glPopDebugGroup (names show in apitrace/RenderDoc).
// - GpuTimers: per-pass GPU time with GL_TIMESTAMP query pairs (nesting allowed), resolved once
//   per frame; ScopedPass = debug group + timer.
#pragma once

#include <epoxy/gl.h>

#include <cstdint>
#include <deque>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace gpu {

class GlError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

// Installs the debug callback on the current context (needs a debug context for full output).
void installDebugOutput();
// Errors recorded since the last call, cleared on return.
std::vector<std::string> takeDebugErrors();
// Throws GlError naming `where` if glGetError reports anything or debug errors were recorded.
void checkGl(std::string_view where);

class DebugGroup {
public:
    explicit DebugGroup(std::string_view name);
    ~DebugGroup();
    DebugGroup(const DebugGroup&) = delete;
    DebugGroup& operator=(const DebugGroup&) = delete;
};

struct PassTime {
    std::string name;
    double ms = 0.0;
};

class GpuTimers {
public:
    GpuTimers();
    ~GpuTimers();
    GpuTimers(const GpuTimers&) = delete;
    GpuTimers& operator=(const GpuTimers&) = delete;

    // Returns a slot id; end(slot) closes it. Same name twice in a frame: times are summed.
    int begin(std::string_view name);
    void end(int slot);
    // Waits for the queries of this frame, returns the times in begin order (names merged), and
    // starts a new frame.
    std::vector<PassTime> resolve();

    // The same without waiting (an interactive loop): closes this frame's queries and keeps them
    // in a ring; returns the times of the newest earlier frame whose queries have all completed,
    // with `lag` = how many frames ago it was (0 = this one), or nothing when none has completed
    // yet. With more than `maxInFlight` frames pending, the oldest is waited for.
    struct Deferred {
        std::vector<PassTime> passes;
        int lag = 0;
        std::uint64_t frame = 0; // which frame (counting every resolve and resolveDeferred)
    };
    std::optional<Deferred> resolveDeferred(std::size_t maxInFlight = 3);

private:
    struct Slot {
        std::string name;
        GLuint queries[2];
    };
    struct PendingFrame {
        std::vector<Slot> slots;
        std::uint64_t index = 0;
    };
    void closeOpenSlots();
    bool available(const std::vector<Slot>& slots) const;
    std::vector<PassTime> collect(std::vector<Slot>& slots); // blocks until available
    std::vector<Slot> mSlots;
    std::deque<PendingFrame> mPending;
    std::uint64_t mFrameIndex = 0;
    std::vector<GLuint> mPool;
    GLuint acquire();
};

// Debug group + timer for one pass. (Passes call checkGl() themselves: destructors must not throw.)
class ScopedPass {
public:
    ScopedPass(GpuTimers* timers, std::string_view name);
    ~ScopedPass();
    ScopedPass(const ScopedPass&) = delete;
    ScopedPass& operator=(const ScopedPass&) = delete;

private:
    GpuTimers* mTimers;
    int mSlot = -1;
    std::string mName;
    DebugGroup mGroup;
};

} // namespace gpu
