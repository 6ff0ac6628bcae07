// The visibility methods of the render contract (DESIGN.md §3), in one table: flag parsing,
// --help, report.json and the viewer all read it. A method that is part of the contract but not
// built yet has no factory: asking for it is a clear error, never a silent fallback.
#pragma once

#include <memory>
#include <span>
#include <string>
#include <string_view>

namespace gpu {

class VisibilityMethod; // gpu/src/Method.h
struct MethodResources; // gpu/src/Method.h

struct MethodInfo {
    std::string_view name;
    std::string_view summary; // one line, for --help and the viewer
    bool usesSamples = false;  // --samples applies (reference methods)
    // Builds the method on the current GL context; null while the method is not implemented.
    std::unique_ptr<VisibilityMethod> (*create)(const MethodResources&) = nullptr;

    bool implemented() const { return create != nullptr; }
};

// Every method of the contract, implemented or not, in --help order.
std::span<const MethodInfo> methodTable();

// The entry for `name`; throws geometry::InputError listing the known names for an unknown one,
// or saying that a known one is not implemented yet (and which are).
const MethodInfo& findMethod(std::string_view name);

// "a, b, c" of the names in the table (all, or implemented only).
std::string methodNameList(bool implementedOnly = false);

} // namespace gpu
