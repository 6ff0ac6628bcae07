// What lets a header of shaders/shared/ compile both as GLSL 4.50 (the shader loader includes it)
// and as C++20 (the CPU tests and the engine include it through geometry's headers): the GPU's
// arithmetic is written once, and the CPU runs the very statements the GPU runs.
//
// The headers use the common subset of the two languages: glm's vec2/vec3/vec4/ivec2/mat4 and
// its dot, cross, normalize, length, min, max, abs, clamp, sqrt, asin, isinf stand for GLSL's;
// float literals carry an `f` (a float in both; without it C++ would compute in double); no
// swizzles beyond .x .y .z .w; struct members without initialisers; array initialisers as
// brace lists (GLSL 4.20); read-only array parameters `const` (an in parameter in GLSL, a
// pointer to const in C++). Three macros cover what differs:
//   SHARED_FN          before every function definition: `inline` in C++ (one definition
//                      across translation units), nothing in GLSL;
//   SHARED_INOUT(T)    an in-out parameter: `inout T` in GLSL, `T&` in C++;
//   SHARED_OUT(T)      an out parameter: `out T` in GLSL, `T&` in C++.
// In C++ everything lives in namespace `shader` (SHARED_BEGIN / SHARED_END around a header's
// body). C++ must include <glm/glm.hpp> before any of these headers (the shader loader accepts
// only quoted includes, so this prelude names no library header itself).
#ifndef PENUMBRA_SHARED_PRELUDE_H
#define PENUMBRA_SHARED_PRELUDE_H

#ifdef __cplusplus

namespace shader {
using glm::abs;
using glm::asin;
using glm::clamp;
using glm::cross;
using glm::dot;
using glm::floor;
using glm::isinf;
using glm::atan;
using glm::cos;
using glm::ivec2;
using glm::length;
using glm::mat4;
using glm::max;
using glm::min;
using glm::normalize;
using glm::sin;
using glm::sqrt;
using glm::vec2;
using glm::vec3;
using glm::vec4;
using uint = unsigned int;
static_assert(sizeof(uint) == 4, "GLSL's uint is 32 bits");
} // namespace shader

#define SHARED_FN inline
#define SHARED_INOUT(T) T&
#define SHARED_OUT(T) T&
#define SHARED_BEGIN namespace shader {
#define SHARED_END }

#else

#define SHARED_FN
#define SHARED_INOUT(T) inout T
#define SHARED_OUT(T) out T
#define SHARED_BEGIN
#define SHARED_END

#endif

#endif // PENUMBRA_SHARED_PRELUDE_H
