// KHR_debug error capture, glGetError checks, debug groups and GL_TIMESTAMP pass timers.
#include <gpu/gl/Debug.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <mutex>
#include <utility>

namespace gpu {

namespace {

// The callback may run on a driver thread when output is asynchronous (we ask for synchronous,
// but a context created elsewhere may not), so the record is guarded.
std::mutex gDebugMutex;
std::vector<std::string> gDebugErrors;
std::size_t gDroppedErrors = 0;
// A broken pass inside a frame loop can report the same error thousands of times; keep the first
// ones (the cause) and count the rest.
constexpr std::size_t kMaxRecordedErrors = 256;

const char* sourceName(GLenum source) {
    switch (source) {
    case GL_DEBUG_SOURCE_API:
        return "API";
    case GL_DEBUG_SOURCE_WINDOW_SYSTEM:
        return "WINDOW_SYSTEM";
    case GL_DEBUG_SOURCE_SHADER_COMPILER:
        return "SHADER_COMPILER";
    case GL_DEBUG_SOURCE_THIRD_PARTY:
        return "THIRD_PARTY";
    case GL_DEBUG_SOURCE_APPLICATION:
        return "APPLICATION";
    case GL_DEBUG_SOURCE_OTHER:
        return "OTHER";
    default:
        return "UNKNOWN_SOURCE";
    }
}

const char* typeName(GLenum type) {
    switch (type) {
    case GL_DEBUG_TYPE_ERROR:
        return "ERROR";
    case GL_DEBUG_TYPE_DEPRECATED_BEHAVIOR:
        return "DEPRECATED_BEHAVIOR";
    case GL_DEBUG_TYPE_UNDEFINED_BEHAVIOR:
        return "UNDEFINED_BEHAVIOR";
    case GL_DEBUG_TYPE_PORTABILITY:
        return "PORTABILITY";
    case GL_DEBUG_TYPE_PERFORMANCE:
        return "PERFORMANCE";
    case GL_DEBUG_TYPE_MARKER:
        return "MARKER";
    case GL_DEBUG_TYPE_PUSH_GROUP:
        return "PUSH_GROUP";
    case GL_DEBUG_TYPE_POP_GROUP:
        return "POP_GROUP";
    case GL_DEBUG_TYPE_OTHER:
        return "OTHER";
    default:
        return "UNKNOWN_TYPE";
    }
}

const char* severityName(GLenum severity) {
    switch (severity) {
    case GL_DEBUG_SEVERITY_HIGH:
        return "HIGH";
    case GL_DEBUG_SEVERITY_MEDIUM:
        return "MEDIUM";
    case GL_DEBUG_SEVERITY_LOW:
        return "LOW";
    case GL_DEBUG_SEVERITY_NOTIFICATION:
        return "NOTIFICATION";
    default:
        return "UNKNOWN_SEVERITY";
    }
}

const char* glErrorName(GLenum error) {
    switch (error) {
    case GL_NO_ERROR:
        return "GL_NO_ERROR";
    case GL_INVALID_ENUM:
        return "GL_INVALID_ENUM";
    case GL_INVALID_VALUE:
        return "GL_INVALID_VALUE";
    case GL_INVALID_OPERATION:
        return "GL_INVALID_OPERATION";
    case GL_INVALID_FRAMEBUFFER_OPERATION:
        return "GL_INVALID_FRAMEBUFFER_OPERATION";
    case GL_OUT_OF_MEMORY:
        return "GL_OUT_OF_MEMORY";
    case GL_STACK_UNDERFLOW:
        return "GL_STACK_UNDERFLOW";
    case GL_STACK_OVERFLOW:
        return "GL_STACK_OVERFLOW";
    case GL_CONTEXT_LOST:
        return "GL_CONTEXT_LOST";
    default:
        return "unknown GL error";
    }
}

void GLAPIENTRY debugCallback(GLenum source, GLenum type, GLuint id, GLenum severity,
                              GLsizei length, const GLchar* message, const void* /*user*/) {
    if (severity == GL_DEBUG_SEVERITY_NOTIFICATION) return;
    // Compile and link failures are reported by ShaderLoader with file:line mapping; recording
    // Mesa's copy too would make a viewer's failed hot reload fail the next checkGl().
    if (source == GL_DEBUG_SOURCE_SHADER_COMPILER) return;
    std::string text = std::string("[") + sourceName(source) + " " + typeName(type) + " " +
                       severityName(severity) + " id=" + std::to_string(id) + "] " +
                       (length >= 0 ? std::string(message, static_cast<std::size_t>(length))
                                    : std::string(message));
    while (!text.empty() && (text.back() == '\n' || text.back() == '\r'))
        text.pop_back();

    bool isError = type == GL_DEBUG_TYPE_ERROR || type == GL_DEBUG_TYPE_UNDEFINED_BEHAVIOR ||
                   severity == GL_DEBUG_SEVERITY_HIGH;
    if (!isError) {
        // Performance/portability hints are noise on llvmpipe; opt in when chasing them.
        static const bool verbose = std::getenv("PENUMBRA_GL_DEBUG_VERBOSE") != nullptr;
        if (verbose) std::fprintf(stderr, "GL debug: %s\n", text.c_str());
        return;
    }
    std::lock_guard lock(gDebugMutex);
    if (gDebugErrors.size() < kMaxRecordedErrors) {
        gDebugErrors.push_back(std::move(text));
    } else {
        ++gDroppedErrors;
    }
}

} // namespace

void installDebugOutput() {
    glEnable(GL_DEBUG_OUTPUT);
    // Synchronous: the callback runs inside the offending call, so a breakpoint there shows the
    // culprit's stack, and checkGl() right after a pass sees every error of that pass.
    glEnable(GL_DEBUG_OUTPUT_SYNCHRONOUS);
    glDebugMessageCallback(debugCallback, nullptr);
    // Push/pop group and marker notifications would otherwise be generated for every pass.
    glDebugMessageControl(GL_DONT_CARE, GL_DONT_CARE, GL_DEBUG_SEVERITY_NOTIFICATION, 0, nullptr,
                          GL_FALSE);
}

std::vector<std::string> takeDebugErrors() {
    std::lock_guard lock(gDebugMutex);
    std::vector<std::string> out;
    out.swap(gDebugErrors);
    if (gDroppedErrors > 0) {
        out.push_back("... and " + std::to_string(gDroppedErrors) + " more debug errors");
        gDroppedErrors = 0;
    }
    return out;
}

void checkGl(std::string_view where) {
    std::vector<std::string> problems;
    // glGetError returns one flag per call; a lost context keeps returning GL_CONTEXT_LOST, so
    // the loop is bounded.
    for (int i = 0; i < 16; ++i) {
        GLenum error = glGetError();
        if (error == GL_NO_ERROR) break;
        problems.push_back(glErrorName(error));
    }
    std::vector<std::string> debug = takeDebugErrors();
    if (problems.empty() && debug.empty()) return;

    std::string message = "GL error at " + std::string(where) + ":";
    for (const std::string& p : problems)
        message += " " + p;
    for (const std::string& d : debug)
        message += "\n  " + d;
    throw GlError(message);
}

// ---------------------------------------------------------------------------------------------

DebugGroup::DebugGroup(std::string_view name) {
    // Message length must stay below GL_MAX_DEBUG_MESSAGE_LENGTH (>= 1 in the spec, 4096 on
    // Mesa and NVIDIA); pass names are short, clamp anyway.
    GLsizei length = static_cast<GLsizei>(std::min<std::size_t>(name.size(), 255));
    glPushDebugGroup(GL_DEBUG_SOURCE_APPLICATION, 0, length, name.data());
}

DebugGroup::~DebugGroup() {
    glPopDebugGroup();
}

// ---------------------------------------------------------------------------------------------
// GpuTimers: each slot is a pair of GL_TIMESTAMP queries. Timestamps (rather than
// GL_TIME_ELAPSED) allow nesting, since only one TIME_ELAPSED query can be active at a time.
// queries[1] stays 0 until end() is called.

GpuTimers::GpuTimers() = default;

GpuTimers::~GpuTimers() {
    for (const PendingFrame& f : mPending)
        for (const Slot& slot : f.slots)
            for (GLuint q : slot.queries)
                if (q) mPool.push_back(q);
    for (const Slot& slot : mSlots) {
        for (GLuint q : slot.queries) {
            if (q) mPool.push_back(q);
        }
    }
    if (!mPool.empty()) glDeleteQueries(static_cast<GLsizei>(mPool.size()), mPool.data());
}

GLuint GpuTimers::acquire() {
    if (!mPool.empty()) {
        GLuint q = mPool.back();
        mPool.pop_back();
        return q;
    }
    GLuint q = 0;
    glCreateQueries(GL_TIMESTAMP, 1, &q);
    return q;
}

int GpuTimers::begin(std::string_view name) {
    Slot slot{std::string(name), {acquire(), 0}};
    glQueryCounter(slot.queries[0], GL_TIMESTAMP);
    mSlots.push_back(std::move(slot));
    return static_cast<int>(mSlots.size()) - 1;
}

void GpuTimers::end(int slot) {
    if (slot < 0 || slot >= static_cast<int>(mSlots.size())) return;
    Slot& s = mSlots[static_cast<std::size_t>(slot)];
    if (s.queries[1] != 0) return; // ended twice: keep the first end
    s.queries[1] = acquire();
    glQueryCounter(s.queries[1], GL_TIMESTAMP);
}

void GpuTimers::closeOpenSlots() {
    for (Slot& slot : mSlots) {
        // A pass left open (an exception skipped its end) is closed here rather than dropped, so
        // the pool stays balanced; its time then runs to the end of the frame.
        if (slot.queries[1] == 0) {
            slot.queries[1] = acquire();
            glQueryCounter(slot.queries[1], GL_TIMESTAMP);
        }
    }
}

bool GpuTimers::available(const std::vector<Slot>& slots) const {
    for (const Slot& slot : slots)
        for (GLuint q : slot.queries) {
            GLuint ready = GL_FALSE;
            glGetQueryObjectuiv(q, GL_QUERY_RESULT_AVAILABLE, &ready);
            if (!ready) return false;
        }
    return true;
}

std::vector<PassTime> GpuTimers::collect(std::vector<Slot>& slots) {
    std::vector<PassTime> out;
    for (Slot& slot : slots) {
        // GL_QUERY_RESULT blocks until the GPU has passed the counter.
        GLuint64 t0 = 0, t1 = 0;
        glGetQueryObjectui64v(slot.queries[0], GL_QUERY_RESULT, &t0);
        glGetQueryObjectui64v(slot.queries[1], GL_QUERY_RESULT, &t1);
        double ms = t1 > t0 ? static_cast<double>(t1 - t0) * 1e-6 : 0.0;
        auto it = std::find_if(out.begin(), out.end(),
                               [&](const PassTime& p) { return p.name == slot.name; });
        if (it != out.end()) {
            it->ms += ms;
        } else {
            out.push_back({slot.name, ms});
        }
        mPool.push_back(slot.queries[0]);
        mPool.push_back(slot.queries[1]);
    }
    slots.clear();
    return out;
}

std::vector<PassTime> GpuTimers::resolve() {
    closeOpenSlots();
    // Frames left pending by resolveDeferred are older than this one: drop their times.
    for (PendingFrame& f : mPending) collect(f.slots);
    mPending.clear();
    ++mFrameIndex;
    return collect(mSlots);
}

std::optional<GpuTimers::Deferred> GpuTimers::resolveDeferred(std::size_t maxInFlight) {
    closeOpenSlots();
    const std::uint64_t current = mFrameIndex++;
    mPending.push_back({std::move(mSlots), current});
    mSlots.clear();
    std::optional<Deferred> latest;
    while (!mPending.empty()) {
        PendingFrame& oldest = mPending.front();
        if (!available(oldest.slots) && mPending.size() <= std::max<std::size_t>(maxInFlight, 1))
            break;
        latest = Deferred{collect(oldest.slots), static_cast<int>(current - oldest.index),
                          oldest.index};
        mPending.pop_front();
    }
    return latest;
}

// ---------------------------------------------------------------------------------------------

ScopedPass::ScopedPass(GpuTimers* timers, std::string_view name)
    : mTimers(timers), mName(name), mGroup(name) {
    // Started after the debug group is pushed so the timer brackets only the pass's own work.
    if (mTimers) mSlot = mTimers->begin(mName);
}

ScopedPass::~ScopedPass() {
    if (!mTimers) return;
    try {
        mTimers->end(mSlot);
    } catch (...) {
        // A destructor may run during unwinding; losing one timing beats std::terminate.
    }
}

} // namespace gpu
