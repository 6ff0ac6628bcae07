// The method table (gpu/Methods.h): the one list of method names.
#include <gpu/Methods.h>

#include <geometry/Error.h>

#include "Method.h"

#include <array>

namespace gpu {

namespace {

const std::array<MethodInfo, 9> kMethods = {{
    {"hard", "z-fail stencil shadow volumes from the light centre", false, createHardMethod},
    {"reference", "average of N hard-shadow passes from stratified light points (GPU)", true,
     createReferenceMethod},
    {"raytrace", "N stratified Embree rays per pixel to the light (CPU)", true,
     createRaytraceMethod},
    {"wedges-additive", "penumbra wedges, coverage summed (Assarsson & Akenine-Moller 2003)",
     false, createAdditiveWedgesMethod},
    {"wedges-blend", "per-silhouette visibility buffers blended (Forest et al. 2006)", false,
     createBlendWedgesMethod},
    {"wedges-multiply", "per-silhouette visibility buffers multiplied (independent occluders)",
     false, createMultiplyWedgesMethod},
    {"occlusion", "occlusion textures (Eisemann & Decoret 2006)", false, nullptr},
    {"pcss", "percentage-closer soft shadows", false, nullptr},
    {"auto", "per-object choice, composed in one frame", false, nullptr},
}};

} // namespace

std::span<const MethodInfo> methodTable() { return kMethods; }

std::string methodNameList(bool implementedOnly) {
    std::string list;
    for (const MethodInfo& m : kMethods) {
        if (implementedOnly && !m.implemented()) continue;
        if (!list.empty()) list += ", ";
        list += m.name;
    }
    return list;
}

const MethodInfo& findMethod(std::string_view name) {
    for (const MethodInfo& m : kMethods) {
        if (m.name != name) continue;
        if (!m.implemented())
            throw geometry::InputError("method '" + std::string(name) +
                                       "' is part of the render contract but not implemented "
                                       "yet; implemented: " +
                                       methodNameList(true));
        return m;
    }
    throw geometry::InputError("unknown method '" + std::string(name) +
                               "' (known: " + methodNameList() + ")");
}

} // namespace gpu
