// Expected exceptions whose message a test checks: errorOf runs the code and hands back what the
// exception says, so the test asserts that it was thrown and then checks the message.
#pragma once

#include <optional>
#include <string>
#include <utility>

namespace testutil {

// The message of the E that `f` throws; nullopt when it returns normally. Any other exception
// propagates (and fails the test as it would have without this).
template <class E, class F> std::optional<std::string> errorOf(F&& f) {
    try {
        std::forward<F>(f)();
    } catch (const E& e) {
        return std::string(e.what());
    }
    return std::nullopt;
}

} // namespace testutil
