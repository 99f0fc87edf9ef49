// Everything the run-time passes and their C++ drivers must agree on about GPU resources: work-group
// size, texture/image/buffer binding points and the structs in every buffer (DESIGN.md §6). Passes:
// the camera G-buffer (shaders/runtime/gbuffer.*, src/cubeao/runtime/camera_gbuffer.cpp), the probe
// projection (runtime/project.comp, probe_projection.cpp), the screen-space baselines
// (common/ssao.glsl, src/cubeao/ssao/ssao_pass.cpp), the blur and the composite (runtime/blur.comp,
// composite.comp; blur.cpp, composite.cpp).
//
// A binding number means one thing in every run-time pass, per kind (texture unit, image unit, shader
// storage buffer), so a buffer left bound by one pass can never be read as another's by mistake.
// GLSL 4.5 accepts these constants in layout qualifiers (constant expressions there are core since
// 4.40, ARB_enhanced_layouts); every pass here compiles on Mesa llvmpipe that way.
#pragma once

#include "glsl_cpp.h"

CUBEAO_KERNEL_BEGIN

// local_size_x = local_size_y of every per-pixel compute pass (project, blur, composite, ssao/*): 64
// invocations, a multiple of every vendor's SIMD width; the C++ side dispatches pixelGroups(n) per axis.
CUBEAO_CONST int kPixelGroupSize = 8;

// Texture units (sampler bindings).
CUBEAO_CONST int kGBufferDepthUnit = 0;   // camera G-buffer: view depth (R32F), 0 = no geometry
CUBEAO_CONST int kGBufferNormalUnit = 1;  // camera G-buffer: view-space normal facing the camera
CUBEAO_CONST int kAoInputUnit = 2;        // blur, composite: the AO to filter or shade with (R32F)
CUBEAO_CONST int kProbeAoUnit = 3;        // projection: probe atlas of AO + confidence (BC5: r = AO, g = confidence)
CUBEAO_CONST int kProbeDistanceUnit = 4;  // projection: probe atlas of distance cubes (value · distanceScale)

// Image units.
CUBEAO_CONST int kAoImageUnit = 0;      // R32F AO written by project, ssao/* and each blur pass
CUBEAO_CONST int kShadedImageUnit = 1;  // RGBA8 colour written by the composite

// Shader storage buffer bindings.
CUBEAO_CONST int kTriangleNormalsBuffer = 0;  // G-buffer: one world-space vec4 normal per triangle (gl/gpu_mesh.h)
CUBEAO_CONST int kPassCountersBuffer = 4;     // project, ssao/*: PassCounters
CUBEAO_CONST int kProbeTableBuffer = 5;       // project: ProbeEntry per probe, in cache order
CUBEAO_CONST int kCandidateBuffer = 6;        // project: K probe indices per grid cell (probe_grid.h), kNoProbe = none

// The counters a pass accumulates over a frame (std430). Fetches are G-buffer and probe texture reads,
// a 64-bit count in two words (a 4K frame at 64 samples passes 2³²; the carry is added by hand).
struct PassCounters {
    uint fetchesLow;
    uint fetchesHigh;
    uint uncovered;  // project: pixels with geometry that no candidate probe saw (AO falls back to 1); ssao: 0
    uint padding;    // to 16 bytes: Mesa rounds the block up to 16 (GL_BUFFER_DATA_SIZE); the buffer must hold it
};

// One probe as the projection reads it (std430; vec3 + float packs into 16 bytes, the array stride).
struct ProbeEntry {
    vec3 position;        // world space
    float distanceScale;  // a distance-atlas value times this is the distance (r16unorm: maxDistance; float formats: 1)
};

// An unused slot of a cell's candidate list (cells in x-fastest order, K slots each, best first).
CUBEAO_CONST uint kNoProbe = 0xffffffffu;

CUBEAO_KERNEL_END

#ifdef __cplusplus
#include <cstddef>

namespace cubeao::kernel {
static_assert(sizeof(PassCounters) == 16 && offsetof(PassCounters, fetchesHigh) == 4 &&
              offsetof(PassCounters, uncovered) == 8);
static_assert(sizeof(ProbeEntry) == 16 && offsetof(ProbeEntry, distanceScale) == 12);

// Work groups that cover n pixels along one axis.
constexpr unsigned pixelGroups(int n) { return unsigned((n + kPixelGroupSize - 1) / kPixelGroupSize); }
}  // namespace cubeao::kernel
#endif
