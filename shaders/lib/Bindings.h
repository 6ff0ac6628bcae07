// Binding slots and uniform-block layouts shared by C++ (gpu/src) and GLSL (shaders/).
// Valid as both languages: the C++ side gets structs with static_asserts on their std140 sizes,
// the GLSL side gets the uniform blocks, so the two cannot drift apart.
#ifndef PENUMBRA_BINDINGS_H
#define PENUMBRA_BINDINGS_H

#define BINDING_FRAME_UBO 0

#define TEXUNIT_POSITION 0
#define TEXUNIT_NORMAL 1
#define TEXUNIT_ALBEDO 2
#define TEXUNIT_VISIBILITY 3

#ifdef __cplusplus
// C++ side: included through gpu/src/ShaderBindings.h, which includes glm first (the GLSL
// loader resolves every #include itself, so this file includes nothing).
namespace gpu::shader {
using mat4 = glm::mat4;
using vec4 = glm::vec4;
#define PENUMBRA_UBO_BEGIN(Name, slot) struct Name {
#define PENUMBRA_UBO_END(Name, instance) };
#else
#define PENUMBRA_UBO_BEGIN(Name, slot) layout(std140, binding = slot) uniform Name {
#define PENUMBRA_UBO_END(Name, instance) } instance;
#endif

// Per-frame constants. Only vec4/mat4 members so std140 and C++ layouts agree trivially.
PENUMBRA_UBO_BEGIN(FrameUniforms, BINDING_FRAME_UBO)
    mat4 viewProj;    // reversed-Z, infinite far plane (gpu/src/Camera math in Renderer.cpp)
    vec4 eye;         // xyz camera position
    vec4 lightCenter; // xyz centre of the rectangular light
    vec4 lightU;      // xyz half-axis u
    vec4 lightV;      // xyz half-axis v
    vec4 params;      // x: ambient term, y: accumulation weight, z: exposure, w: unused
PENUMBRA_UBO_END(FrameUniforms, frame)

#ifdef __cplusplus
static_assert(sizeof(FrameUniforms) == 64 + 5 * 16, "FrameUniforms must match std140");
} // namespace gpu::shader
#endif

#endif
