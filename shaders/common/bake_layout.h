// Everything the bake's compute passes and their C++ drivers must agree on about GPU resources:
// work-group sizes, texture and buffer binding points and the structs in the buffers (DESIGN.md §6).
// Passes: shaders/bake/ao_horizon.comp, ao_traced.comp, hybrid_select.comp, ao_denoise.comp (driven
// by src/cubeao/bake/gpu_bake.cpp), bc5_encode.comp and bc5_error.comp (gpu_bc5.cpp),
// depth_encode.comp (gpu_depth.cpp); the BVH's own bindings are in bvh.h (uploaded by gpu_bvh.cpp).
//
// A binding number means one buffer in every bake pass (the per-texel AO is binding 1 wherever it is
// read or written), so the passes chain without rebinding. GLSL 4.5 accepts these constants in layout
// qualifiers (constant expressions there are core since 4.40, ARB_enhanced_layouts); every pass here
// compiles on Mesa llvmpipe that way.
#pragma once

#include "glsl_cpp.h"

CUBEAO_KERNEL_BEGIN

// Work-group sizes. Per-texel (or per-block) passes over a face: kBakeTileSize² invocations,
// dispatched bakeGroups(res) × bakeGroups(res) × 6 (ao_horizon, bc5_encode, bc5_error, depth_encode
// PASS 0). Passes over a flat list of texels or words: kBakeListGroupSize (ao_traced,
// hybrid_select, depth_encode PASS 1). Both are 64 invocations, a multiple of every vendor's SIMD width.
CUBEAO_CONST int kBakeTileSize = 8;
CUBEAO_CONST int kBakeListGroupSize = 64;

// Texture units.
CUBEAO_CONST int kBakeGBufferUnit = 0;  // the probe's cube G-buffer: sampler2DArray of (normal, distance), 6 layers

// Shader storage buffer bindings.
CUBEAO_CONST int kBakeTriangleNormalsBuffer = 0;  // gbuffer.frag: world-space vec4 normal per triangle (gl/gpu_mesh.h)
CUBEAO_CONST int kBakeAoBuffer = 1;           // vec2 (ao, confidence) per texel, cubeTexelIndex order
CUBEAO_CONST int kBakeTexelListBuffer = 2;    // TexelListHeader, then uint texel indices (hybrid)
CUBEAO_CONST int kBakeBlocksBuffer = 3;       // uvec4 per BC5 block: red (xy), green (zw)
CUBEAO_CONST int kBakeFetchCountBuffer = 4;   // FetchCount of the horizon pass
CUBEAO_CONST int kBakeCoarseBuffer = 5;       // depth_encode: float per coarse texel, cubeTexelIndex order at depthRes
CUBEAO_CONST int kBakeMaxDistanceBuffer = 6;  // depth_encode: uint floatBitsToUint of the largest distance (≥ 0)
CUBEAO_CONST int kBakeDepthWordsBuffer = 7;   // depth_encode: the packed depth cube, 32-bit words
CUBEAO_CONST int kBakeErrorTilesBuffer = 8;   // bc5_error: vec2 (Σ error², texels) per work group
CUBEAO_CONST int kBakeAoSourceBuffer = 9;     // ao_denoise: the AO buffer as it was before the filter

// Uniform block bindings (std140, filled by gl::UniformBlock; numbered apart from the run-time's in
// runtime_layout.h, whose passes share a context with a live bake).
CUBEAO_CONST int kBakeBlock = 8;    // the G-buffer and AO passes (gpu_bake.cpp): BakeBlock
CUBEAO_CONST int kEncodeBlock = 9;  // bc5_encode, bc5_error, depth_encode: EncodeBlock

// G-buffer lookups made by the horizon pass: a 64-bit count in two words (a probe at 512² can pass
// 2³²; the carry is added by hand). Start it at zero.
struct FetchCount {
    uint fetchesLow;
    uint fetchesHigh;
};

// Head of the hybrid's texel list: the indirect-dispatch arguments of ao_traced.comp (TEXEL_LIST)
// followed by the list's length. Start it at (0, 1, 1, 0): hybrid_select raises groupsX to
// ceil(count / kBakeListGroupSize) as it appends.
struct TexelListHeader {
    uint groupsX;
    uint groupsY;
    uint groupsZ;
    uint count;
};

// A probe's bake parameters: what its G-buffer and AO passes read (each pass reads its own members).
struct BakeBlock {
    mat4 clipFromWorld[6];  // gbuffer.geom: every face's (core/cube.h clipFromWorld); gbuffer.vert
                            // (six passes): the face being drawn, in [0]
    vec3 probe;             // world space
    int res;                // texels per face edge
    float radius;           // the AO radius R
    int falloff;            // FALLOFF_NONE | FALLOFF_SMOOTH (falloff.h)
    uint probeKey;          // probe index ^ seed (cubeTexelKey, sampling.h)
    int directions;         // ao_horizon
    int steps;              // ao_horizon
    int spp;                // ao_traced: rays per texel
    float surfaceEpsilon;   // ao_traced: surfaceEpsilonFor(scene), as the Embree twin offsets its rays
    int denoiseRadius;      // ao_denoise: the filter's radius in texels
    float threshold;        // hybrid_select: texels less confident than this are traced
};

// The encoders' parameters.
struct EncodeBlock {
    int res;       // face edge in texels (BC5: a multiple of 4)
    int depthRes;  // depth_encode: the coarse cube's face edge
    int format;    // depth_encode: DepthFormat (kDepthR16Unorm, kDepthR16Float or kDepthR32Float)
};

CUBEAO_KERNEL_END

#ifdef __cplusplus
#include <cstddef>

namespace cubeao::kernel {
static_assert(sizeof(FetchCount) == 8 && offsetof(FetchCount, fetchesHigh) == 4);
// std140 offsets of the blocks (the driver's are checked in tests/runtime/test_runtime_layout.cpp).
static_assert(offsetof(BakeBlock, probe) == 384 && offsetof(BakeBlock, res) == 396 &&
              offsetof(BakeBlock, radius) == 400 && offsetof(BakeBlock, probeKey) == 408 &&
              offsetof(BakeBlock, spp) == 420 && offsetof(BakeBlock, threshold) == 432 && sizeof(BakeBlock) == 436);
static_assert(sizeof(EncodeBlock) == 12 && offsetof(EncodeBlock, format) == 8);
// groupsX..Z are what glDispatchComputeIndirect reads at offset 0; the texel indices follow at 16.
static_assert(sizeof(TexelListHeader) == 16 && offsetof(TexelListHeader, groupsY) == 4 &&
              offsetof(TexelListHeader, groupsZ) == 8 && offsetof(TexelListHeader, count) == 12);

// Work groups that cover n items with groups of `size`.
constexpr unsigned bakeGroups(std::size_t n, int size) { return unsigned((n + std::size_t(size) - 1) / std::size_t(size)); }
}  // namespace cubeao::kernel
#endif
