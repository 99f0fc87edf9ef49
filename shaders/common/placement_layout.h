// What the GPU coverage count (shaders/placement/coverage_count.comp) and its C++ driver
// (placement/src/gpu_coverage.cpp) must agree on: buffer bindings and the counter struct. The pass
// reads the camera G-buffer at runtime_layout.h's texture units and the BVH at bvh.h's buffer
// bindings, and runs kPixelGroupSize² invocations per work group like every per-pixel pass; its own
// buffers take bindings no run-time pass uses, so nothing a run-time pass leaves bound is misread.
#pragma once

#include "coverage.h"
#include "glsl_cpp.h"

CUBEAO_KERNEL_BEGIN

// Shader storage buffer bindings (runtime_layout.h uses 0 and 4–6, bvh.h 10 and 11).
CUBEAO_CONST int kCoverageProbeBuffer = 7;    // vec4 per probe: xyz = world position, w unused
CUBEAO_CONST int kCoverageCounterBuffer = 8;  // CoverageCounters

// Uniform block binding (runtime_layout.h uses 0).
CUBEAO_CONST int kCoverageBlock = 1;  // CoverageBlock, std140

// Per frame (std140 uniform block, gl::UniformBlock): the criterion, the probes in the probe buffer,
// and how far the ray to a probe starts off the surface (EmbreeScene::surfaceEpsilon of the CPU count).
struct CoverageBlock {
    CoverageParams params;
    uint probeCount;
    float surfaceEpsilon;
};

// Per frame (std430): pixels with geometry, and those of them no probe covers.
struct CoverageCounters {
    uint pixels;
    uint uncovered;
    uint padding0;  // to 16 bytes, as runtime_layout.h's PassCounters: Mesa rounds the block up to 16
    uint padding1;
};

CUBEAO_KERNEL_END

#ifdef __cplusplus
#include <cstddef>

namespace cubeao::kernel {
static_assert(sizeof(CoverageCounters) == 16 && offsetof(CoverageCounters, uncovered) == 4);
static_assert(sizeof(CoverageParams) == 16 && offsetof(CoverageBlock, probeCount) == 16 &&
              offsetof(CoverageBlock, surfaceEpsilon) == 20, "CoverageBlock must keep std140 offsets");
}  // namespace cubeao::kernel
#endif
