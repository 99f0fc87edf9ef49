// The bridge that lets one header in shaders/common/ compile both as GLSL 4.5 (through the shader
// loader, src/cubeao/gl/shader.h) and as C++20 with GLM, so a kernel, constant, binding or GPU struct
// exists once and the CPU twin cannot drift from the shader (DESIGN.md §6; the style of XeGTAO.h).
//
// Rules for a shared header (each keeps both languages happy):
// - Start with `#pragma once` and `#include "glsl_cpp.h"`; put everything between CUBEAO_KERNEL_BEGIN
//   and CUBEAO_KERNEL_END (namespace cubeao::kernel in C++, nothing in GLSL).
// - Functions: `CUBEAO_FN float f(...)` (inline in C++). Parameters: plain `T x` for inputs,
//   `CUBEAO_OUT(T) x` and `CUBEAO_INOUT(T) x` for out/inout (references in C++).
// - Constants: `CUBEAO_CONST float kName = 1.0f;`. Float literals always carry `f`: GLSL accepts it,
//   and C++ needs it (GLM does not mix float and double).
// - Structs: no constructors, no bool members in GPU-visible ones; build them as `S(a, b, c)` (a GLSL
//   constructor, a C++20 parenthesised aggregate). GPU-visible structs get static_asserts on size and
//   offsets in an `#ifdef __cplusplus` block after them.
// - No swizzles beyond .x .y .z .w (GLM's need GLM_FORCE_SWIZZLE), no GLSL array constructors.
// - C++-only code goes in `#ifdef __cplusplus ... #endif` (the shader loader drops it, includes and
//   all; `#ifndef __cplusplus` keeps GLSL-only code from C++). Resources (samplers, images, buffers)
//   are declared by the shaders, never here. A kernel reads its inputs through arguments, or through
//   functions the shader defines and C++ supplies otherwise: a C++-only member of the kernel's
//   params struct (horizon.h, depth_encode.h: one array), or a reader object that a C++ template
//   takes (projection.h: several textures per probe).
#pragma once

#ifdef __cplusplus
#include <cmath>
#include <cstdint>

#include <glm/glm.hpp>

namespace cubeao::kernel {
using namespace glm;
using uint = std::uint32_t;
// GLSL's roundEven for a float, as one instruction: GLM's emulation (fract, round, parity) costs the
// CPU depth encoder ~60 % more time; std::nearbyint rounds half to even in the default rounding mode,
// which is also the only one GLSL has. The using keeps GLM's vector overloads beside it.
using glm::roundEven;
inline float roundEven(float x) { return std::nearbyint(x); }
// A 64-bit count or word that a shader keeps as two 32-bit halves (fetch counters, BC4 blocks).
inline std::uint64_t joinWords(uint low, uint high) { return std::uint64_t(high) << 32 | low; }
}  // namespace cubeao::kernel

#define CUBEAO_KERNEL_BEGIN namespace cubeao::kernel {
#define CUBEAO_KERNEL_END }
#define CUBEAO_FN inline
#define CUBEAO_CONST inline constexpr
#define CUBEAO_OUT(T) T&
#define CUBEAO_INOUT(T) T&
#else
#define CUBEAO_KERNEL_BEGIN
#define CUBEAO_KERNEL_END
#define CUBEAO_FN
#define CUBEAO_CONST const
#define CUBEAO_OUT(T) out T
#define CUBEAO_INOUT(T) inout T
#endif
