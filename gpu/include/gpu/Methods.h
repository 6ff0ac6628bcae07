// The visibility methods of the render contract (DESIGN.md §3), in one table: flag parsing,
// --help, report.json and the viewer all read it. A method that is part of the contract but not
// built yet has no factory: asking for it is a clear error, never a silent fallback.
//
// A method may declare parameters (`penumbra-render --param NAME=VALUE`): each a name, a closed
// list of allowed values, a default and one line of help. RenderSettings::parameters carries
// what was given; resolveParameters checks it against the table and fills in the defaults, and
// the method is built from the resolved list (MethodResources::parameters).
#pragma once

#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace gpu {

class VisibilityMethod; // gpu/src/engine/Method.h
struct MethodResources; // gpu/src/engine/Method.h

struct MethodParameter {
    std::string_view name;
    std::span<const std::string_view> values; // the allowed values, in --help order
    std::string_view defaultValue;            // one of `values`
    std::string_view help;                    // one line
};

// A parameter's value, as given (command line, viewer) or resolved.
struct ParameterValue {
    std::string name;
    std::string value;
    bool operator==(const ParameterValue&) const = default;
};

struct MethodInfo {
    std::string_view name;
    std::string_view summary; // one line, for --help and the viewer
    bool usesSamples = false;  // --samples applies (reference methods)
    // Builds the method on the current GL context; null while the method is not implemented.
    std::unique_ptr<VisibilityMethod> (*create)(const MethodResources&) = nullptr;
    std::span<const MethodParameter> parameters{}; // empty: the method takes none
    // Whether the method honours alpha-tested casters (glTF MASK/BLEND: leaf cards cut out by
    // their texture, SceneGeometry / shaders/lib/Material.glsl). A method without it shadows
    // only a scene's opaque objects; the renderer gives the alpha-tested ones to occlusion
    // textures beside it (createAlphaComposite), as `auto` does.
    bool alphaMasks = false;

    bool implemented() const { return create != nullptr; }
};

// Every method of the contract, implemented or not, in --help order.
std::span<const MethodInfo> methodTable();

// The entry for `name`; throws geometry::InputError listing the known names for an unknown one,
// or saying that a known one is not implemented yet (and which are).
const MethodInfo& findMethod(std::string_view name);

// "a, b, c" of the names in the table (all, or implemented only).
std::string methodNameList(bool implementedOnly = false);

// Every parameter of `method`, in the table's order, with its value from `given` or its default.
// Throws geometry::InputError for a name the method does not declare (naming those it has, or
// saying that it has none), a value that is not allowed (naming the allowed ones) or a name
// given twice.
std::vector<ParameterValue> resolveParameters(const MethodInfo& method,
                                              std::span<const ParameterValue> given);

// "NAME=VALUE" (the command line's form); throws geometry::InputError otherwise.
ParameterValue parseParameter(std::string_view text);

// The value of `name` in a resolved list (resolveParameters); empty when it is not there.
std::string_view parameterValue(std::span<const ParameterValue> resolved, std::string_view name);

} // namespace gpu
