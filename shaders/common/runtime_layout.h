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
// The coarse tier (probe_atlas.h): every probe at one coarser level of detail, where the budget holds it.
CUBEAO_CONST int kProbeCoarseAoUnit = 5;
CUBEAO_CONST int kProbeCoarseDistanceUnit = 6;

// Image units.
CUBEAO_CONST int kAoImageUnit = 0;           // R32F AO written by project, ssao/* and each blur pass
CUBEAO_CONST int kShadedImageUnit = 1;       // RGBA8 colour written by the composite
CUBEAO_CONST int kDiagnosticsImageUnit = 2;  // RGBA32F diagnostics of project.comp built with PROJECT_DIAGNOSTICS

// Uniform block bindings (std140 blocks of kernel parameters, filled by gl::UniformBlock from their
// C++ mirror; offsets static_asserted beside the struct and checked against the driver in
// tests/runtime/test_runtime_layout.cpp).
// Numbered apart from the bake's (bake_layout.h) and placement's (placement_layout.h) blocks.
CUBEAO_CONST int kProjectBlock = 0;    // project, cell_residency: ProjectBlock (below)
CUBEAO_CONST int kCameraBlock = 2;     // every per-pixel pass but the composite: CameraBlock (camera.h)
CUBEAO_CONST int kSsaoBlock = 3;       // ssao/*, gtao_fill: SsaoBlock
CUBEAO_CONST int kBlurBlock = 4;       // blur: BlurBlock
CUBEAO_CONST int kCompositeBlock = 5;  // composite: CompositeBlock
CUBEAO_CONST int kGBufferBlock = 6;    // the camera G-buffer's vertex and fragment stages: GBufferBlock

// Shader storage buffer bindings.
CUBEAO_CONST int kTriangleNormalsBuffer = 0;  // G-buffer: one world-space vec4 normal per triangle (gl/gpu_mesh.h)
CUBEAO_CONST int kPassCountersBuffer = 4;     // project, ssao/*: PassCounters
CUBEAO_CONST int kProbeTableBuffer = 5;       // project: ProbeEntry per probe, in cache order
CUBEAO_CONST int kCandidateBuffer = 6;        // project: K probe indices per grid cell (probe_grid.h), kNoProbe = none
CUBEAO_CONST int kResidentCandidateBuffer = 9;  // project: the second list, resident probes per coarse cell (nearest_lists.h)
CUBEAO_CONST int kProbeFeedbackBuffer = 16;   // project: per probe, sampled pixels that used or wanted it
CUBEAO_CONST int kCellResidentCountBuffer = 17;  // project, cell_residency: per grid cell, how many of its candidates are resident

// The counters a pass accumulates over a frame (std430). Fetches are G-buffer and probe texture reads,
// a 64-bit count in two words (a 4K frame at 64 samples passes 2³²; the carry is added by hand).
struct PassCounters {
    uint fetchesLow;
    uint fetchesHigh;
    uint uncovered;  // project: pixels with geometry that no resident candidate saw (kUncoveredAo); ssao: 0
    uint fallbackProbe;  // project: covered pixels that passed over a non-resident candidate on the way; ssao: 0
    uint geometry;       // project: pixels with geometry (the base of the shares above); ssao: 0
    uint padding0;       // to 32 bytes: Mesa rounds the block up to 16 (GL_BUFFER_DATA_SIZE); the buffer must hold it
    uint padding1;
    uint padding2;
};

// Passes count into kCounterStripes PassCounters, a work group into stripe (its index mod
// kCounterStripes; pass_counters.glsl), each invocation with its own atomics, and the host sums the
// stripes (sumPassCounters). One counter block reduced in shared memory needs a barrier, and a
// barrier anywhere in a shader makes Mesa llvmpipe run every group as coroutines: 0.04 of a GTAO
// pass at 1080p in the projection (docs/BENCHMARKS.md). Per-invocation atomics on one block instead
// made the CPU's threads fight over its cache line; on stripes, groups that run at once rarely
// share one. (A GPU's compiler merges a warp's atomics on one address into one.)
CUBEAO_CONST uint kCounterStripes = 64u;

// One probe as the projection reads it (std430, 32 bytes: vec3 + float pack into 16, then four words).
// Indexed by probe id (the cache's order, then probes added at run time); a removed probe keeps its
// entry with slot = kNoSlot and appears in no cell.
struct ProbeEntry {
    vec3 position;        // world space
    float distanceScale;  // a distance-atlas value times this is the distance (r16unorm: maxDistance; float formats: 1)
    uint slot;            // atlas slot holding its texels (probe_residency.h), kNoSlot = not resident
    uint tile;            // where its texels lie (packAtlasTile) in the atlases of `level`, kNoSlot = neither
    uint level;           // 0: the full-resolution atlases (slot's tile); else the coarse tier's, at that level
    float qualityScale;   // multiplies its quality: 1, or less while its full resolution fades in (probe_atlas.h)
};

// ProbeEntry::slot of a probe whose texels are not on the GPU.
CUBEAO_CONST uint kNoSlot = 0xffffffffu;

// ProbeEntry::tile: the slot's tile column x, row y and page p (probe_residency.h ProbeAtlasLayout)
// packed as x | y << 11 | p << 22, so that the projection finds a texel with shifts and masks. Working
// it out from the slot number takes three integer divisions by the atlas' shape, and a vector integer
// division is a scalar loop on CPU SIMD: on llvmpipe that was a third of the projection pass. Columns
// and rows below kMaxAtlasTiles, pages below 1024 (6 · pages layers; GL allows 2048 on llvmpipe and
// NVIDIA), so no tile packs to kNoSlot.
CUBEAO_CONST int kMaxAtlasTiles = 2048;
CUBEAO_FN uint packAtlasTile(int x, int y, int page) { return uint(x) | (uint(y) << 11u) | (uint(page) << 22u); }

// Texel corner (x, y) and first layer (6 faces from there) of a packed tile in an atlas of size² tiles.
CUBEAO_FN ivec3 atlasTileCorner(uint tile, int size) {
    return ivec3(int(tile & 0x7ffu) * size, int((tile >> 11u) & 0x7ffu) * size, 6 * int(tile >> 22u));
}

// An unused slot of a cell's candidate list (cells in x-fastest order, K slots each, best first).
CUBEAO_CONST uint kNoProbe = 0xffffffffu;

// Raw AO the projection writes where no resident candidate probe sees the pixel's surface: not an AO
// value (those lie in [0, 1]) but a request to the screen-space fallback (runtime/ao_pass.h
// AoFallback), which replaces it before the blur. Any value below 0 means the same.
CUBEAO_CONST float kUncoveredAo = -1.0f;

// The screen-space fallback for those pixels (shaders/ssao/gtao_fill.comp, src/cubeao/ssao/gtao_fallback.cpp).
// Three dispatches: mark sets a bit per uncovered pixel in its 8 × 8 tile's mask (FallbackTile) and
// lists the tiles within kFallbackBlendPixels of one (a FallbackList of tile indices); select, a work
// group per listed tile, lists the pixels that take GTAO (a FallbackList of packed pixels,
// fallbackWorkItem) deciding from the masks alone, never from the AO image; fill runs GTAO for those
// pixels only, 64 to a work group, and writes each pixel's own texel.
CUBEAO_CONST int kFallbackTileBuffer = 12;      // gtao_fill: FallbackTile per tile, tiles in x-fastest order
CUBEAO_CONST int kFallbackCountersBuffer = 13;  // gtao_fill: FallbackCounters
CUBEAO_CONST int kFallbackTileListBuffer = 14;  // gtao_fill: FallbackList, then a uint tile index per listed tile
CUBEAO_CONST int kFallbackWorkBuffer = 15;      // gtao_fill: FallbackList, then a uint work item per pixel to fill
// The blend band: a covered pixel at distance d (pixels, Euclidean) from the nearest uncovered one
// takes mix(its AO, GTAO, max(0, 1 − d / kFallbackBlendPixels)). At most kPixelGroupSize (the band
// around a tile lies in its 8 neighbours).
CUBEAO_CONST int kFallbackBlendPixels = 2;

// One 8 × 8 tile of the frame (std430, 16 bytes).
struct FallbackTile {
    uint mask0;    // its uncovered pixels (x, y) in rows 0–3: bit 8·y + x
    uint mask1;    // rows 4–7: bit 8·(y − 4) + x
    uint listed;   // 1 once the tile is in the list of tiles to fill
    uint padding;
};

// The head of a list the fallback builds on the GPU (std430): glDispatchComputeIndirect's command for
// the dispatch that consumes it, then the number of entries, which follow at byte 16. The C++ side
// resets it to {0, 1, 1, 0} every frame.
struct FallbackList {
    uint groupsX;  // tile list: one group per entry; work list: ⌈entries / 64⌉
    uint groupsY;
    uint groupsZ;
    uint entries;
};

// A pixel that takes GTAO: x, y (13 bits each: frames up to 8192 pixels a side) and its squared
// distance to the nearest uncovered pixel (6 bits; 0 = uncovered itself, < kFallbackBlendPixels²).
CUBEAO_CONST int kFallbackMaxFrameSide = 8192;
CUBEAO_FN uint fallbackWorkItem(int x, int y, int squaredDistance) {
    return uint(x) | (uint(y) << 13u) | (uint(squaredDistance) << 26u);
}

// What the fallback did in a frame (std430).
struct FallbackCounters {
    uint filled;       // pixels that were uncovered (raw AO < 0) and took the GTAO value
    uint blended;      // covered pixels with geometry that took part of it (0 < weight < 1)
    uint fetchesLow;   // G-buffer fetches of the GTAO runs, 64-bit in two words as in PassCounters
    uint fetchesHigh;
};

// The projection's resolved settings (src/cubeao/runtime/projection.h ProjectSettings) and the probes'
// resolutions: AO texels per face side, distance-cube texels per face side.
struct ProjectionParams {
    float depthTolerance;
    float depthSlope;
    float minFacing;
    int res;
    int depthRes;
    float depthOffset;  // the depth test's lift off the surface, in coarse texel widths (depth_test.h)
};

// project.comp's fixed parameters, one std140 uniform block at kProjectBlock: the candidate grid
// (probe_grid.h), the second list (nearest_lists.h), what an uncovered pixel gets, and the
// projection's settings. The two pads put params at a multiple of 16 (std140 aligns a struct
// member so), the same offset in C++. cell_residency.comp reads the grid's part.
struct ProjectBlock {
    vec3 gridOrigin;
    float cellSize;
    ivec3 gridDims;
    int candidatesPerCell;
    vec3 residentOrigin;     // the second list: per coarse cell the resident probes nearest it,
    float residentCellSize;  // residentPerCell of them (0: no second list)
    ivec3 residentDims;
    int residentPerCell;
    float uncoveredAo;
    uint cellCount;  // gridDims' product
    float pad1;
    float pad2;
    ProjectionParams params;
};

// The screen-space estimators' settings (ssao_pixel.glsl; SsaoSettings, ssao_pass.h), fixed for a
// pass's lifetime. Alchemy alone reads the last four.
struct SsaoBlock {
    float radius;           // R, world units
    int falloff;            // FALLOFF_NONE | FALLOFF_SMOOTH (falloff.h)
    int directions;         // N_d
    int steps;              // N_s
    float maxRadiusPixels;  // 0 = no clamp
    float intensity;        // alchemy: σ
    float contrast;         // alchemy: k
    float bias;             // alchemy: β
    float epsilon;          // alchemy: ε / R²
};

// The bilateral blur's settings (blur.h BlurSettings) and the axis of the pass being run.
struct BlurBlock {
    ivec2 axis;  // (1, 0) horizontal, (0, 1) vertical
    int radius;
    float normalPower;
    float depthTolerance;
};

// The composite's shading (composite.h CompositeSettings) and the frame's light and size.
struct CompositeBlock {
    vec3 light;  // view space, towards the light
    float alpha;
    vec3 albedo;
    float ambient;
    vec3 sky;
    float diffuse;
    ivec2 frameSize;
};

// The camera G-buffer's transforms (camera_gbuffer.cpp); the fragment stage rotates the triangle
// normals by mat3(viewFromWorld).
struct GBufferBlock {
    mat4 viewFromWorld;
    mat4 clipFromView;
};

CUBEAO_KERNEL_END

#ifdef __cplusplus
#include <cstddef>

namespace cubeao::kernel {
static_assert(sizeof(PassCounters) == 32 && offsetof(PassCounters, fetchesHigh) == 4 &&
              offsetof(PassCounters, uncovered) == 8 && offsetof(PassCounters, fallbackProbe) == 12 &&
              offsetof(PassCounters, geometry) == 16);
static_assert(sizeof(ProbeEntry) == 32 && offsetof(ProbeEntry, distanceScale) == 12 && offsetof(ProbeEntry, slot) == 16 &&
              offsetof(ProbeEntry, tile) == 20 && offsetof(ProbeEntry, level) == 24 &&
              offsetof(ProbeEntry, qualityScale) == 28);
static_assert(sizeof(FallbackTile) == 16 && offsetof(FallbackTile, mask1) == 4 &&
              offsetof(FallbackTile, listed) == 8);
static_assert(sizeof(FallbackList) == 16 && offsetof(FallbackList, groupsZ) == 8 &&
              offsetof(FallbackList, entries) == 12);
static_assert(sizeof(FallbackCounters) == 16 && offsetof(FallbackCounters, blended) == 4 &&
              offsetof(FallbackCounters, fetchesLow) == 8 && offsetof(FallbackCounters, fetchesHigh) == 12);
static_assert(offsetof(ProjectBlock, cellSize) == 12 && offsetof(ProjectBlock, gridDims) == 16 &&
              offsetof(ProjectBlock, candidatesPerCell) == 28 && offsetof(ProjectBlock, residentOrigin) == 32 &&
              offsetof(ProjectBlock, residentCellSize) == 44 && offsetof(ProjectBlock, residentDims) == 48 &&
              offsetof(ProjectBlock, residentPerCell) == 60 && offsetof(ProjectBlock, uncoveredAo) == 64 &&
              offsetof(ProjectBlock, cellCount) == 68 &&
              offsetof(ProjectBlock, params) == 80 && sizeof(ProjectionParams) == 24,
              "ProjectBlock must keep std140 offsets (project.comp reads it as a uniform block)");
// std140 offsets of the blocks above (each block holds one of these structs; the driver's offsets
// are checked in tests/runtime/test_runtime_layout.cpp).
static_assert(sizeof(SsaoBlock) == 36 && offsetof(SsaoBlock, maxRadiusPixels) == 16 &&
              offsetof(SsaoBlock, epsilon) == 32);
static_assert(sizeof(BlurBlock) == 20 && offsetof(BlurBlock, radius) == 8 && offsetof(BlurBlock, depthTolerance) == 16);
static_assert(sizeof(CompositeBlock) == 56 && offsetof(CompositeBlock, alpha) == 12 &&
              offsetof(CompositeBlock, albedo) == 16 && offsetof(CompositeBlock, ambient) == 28 &&
              offsetof(CompositeBlock, sky) == 32 && offsetof(CompositeBlock, diffuse) == 44 &&
              offsetof(CompositeBlock, frameSize) == 48);
static_assert(sizeof(GBufferBlock) == 128 && offsetof(GBufferBlock, clipFromView) == 64);
static_assert(kFallbackBlendPixels >= 1 && kFallbackBlendPixels <= kPixelGroupSize);  // d² < 64: 6 bits

// What one PassCounters would hold had every group counted into it: the sum of the stripes.
struct PassCountTotals {
    std::uint64_t fetches = 0, uncovered = 0, fallbackProbe = 0, geometry = 0;
};
inline PassCountTotals sumPassCounters(const PassCounters* stripes) {
    PassCountTotals t;
    for (uint i = 0; i < kCounterStripes; ++i) {
        const PassCounters& c = stripes[i];
        t.fetches += joinWords(c.fetchesLow, c.fetchesHigh);
        t.uncovered += c.uncovered, t.fallbackProbe += c.fallbackProbe, t.geometry += c.geometry;
    }
    return t;
}
constexpr std::size_t kPassCounterBytes = kCounterStripes * sizeof(PassCounters);  // one pass's counter buffer

// Work groups that cover n pixels along one axis.
constexpr unsigned pixelGroups(int n) { return unsigned((n + kPixelGroupSize - 1) / kPixelGroupSize); }
}  // namespace cubeao::kernel
#endif
