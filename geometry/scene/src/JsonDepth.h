// Nesting depth of JSON text, measured before any parser sees it. tinygltf turns "extras" and
// "extensions" into its own Value tree by recursion, and nlohmann's dump() (used in messages)
// recurses too: a file of a few kilobytes of "[[[[..." would exhaust the stack there. Counting
// brackets outside strings is enough for the bound; the parsers still judge everything else.
#pragma once

#include <cstddef>
#include <string_view>

namespace geometry::detail {

struct JsonDepth {
    std::size_t depth = 0;  // deepest nesting of [ and { (0 for a bare scalar)
    std::size_t offset = 0; // byte offset of the first bracket at that depth
};

// Stops counting once `limit` is exceeded (the offset is then that of the first bracket past it).
inline JsonDepth jsonNestingDepth(std::string_view text, std::size_t limit) {
    JsonDepth deepest;
    std::size_t depth = 0;
    bool inString = false, escaped = false;
    for (std::size_t i = 0; i < text.size(); ++i) {
        const char c = text[i];
        if (inString) {
            if (escaped) {
                escaped = false;
            } else if (c == '\\') {
                escaped = true;
            } else if (c == '"') {
                inString = false;
            }
            continue;
        }
        if (c == '"') {
            inString = true;
        } else if (c == '[' || c == '{') {
            if (++depth > deepest.depth) deepest = {depth, i};
            if (depth > limit) break;
        } else if ((c == ']' || c == '}') && depth > 0) {
            --depth;
        }
    }
    return deepest;
}

} // namespace geometry::detail
