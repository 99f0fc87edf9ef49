// A probe's distance cube (DESIGN.md §4 "Storage"; docs/FORMAT.md "Distance cube"), written once for
// the CPU (src/cubeao/cache/depth_cube.cpp: depth::downsample with Filter::Min, depth::floatToHalf,
// depth::encodeTexel; the measurements behind the choices are in depth_cube.h) and the GPU bake's
// shaders/bake/depth_encode.comp, which give the same bytes (tests/cache/test_depth_cube.cpp; r16unorm
// within one code: GLSL's division is not correctly rounded everywhere).
//
// The fine distances: depthFineDistance(p, texel) returns the distance of fine texel (i, j, face),
// 0 (or anything not > 0) = empty. In GLSL the including shader defines `float depthFineDistance(ivec3
// texel)` (reading its G-buffer), even when it does not downsample: the linker resolves every call in
// the shader; in C++ it reads DepthDownsampleParams' array.
#pragma once

#include "glsl_cpp.h"

#ifdef __cplusplus
#include <cstddef>
#endif

CUBEAO_KERNEL_BEGIN

// Stored texel formats: the values of DepthFormat (src/cubeao/cache/cache_file.h; depth_cube.cpp
// static_asserts that they agree).
CUBEAO_CONST int kDepthR16Unorm = 1;  // distance / maxDistance · 65535
CUBEAO_CONST int kDepthR16Float = 2;  // IEEE half
CUBEAO_CONST int kDepthR32Float = 3;  // IEEE single

struct DepthDownsampleParams {
    int res;       // fine texels per face side
    int depthRes;  // coarse texels per face side, 1..res
#ifdef __cplusplus
    // The fine distances in cubeTexelIndex order (C++ only: the shader reads a sampler): `distances`,
    // or the w of `gbuffer` ((normal, distance) per texel) when fromGbuffer. A constant flag, so that
    // the compiler drops the test from the loops once it inlines them (a test of the pointers stayed
    // and cost the CPU downsample 25-70 %).
    const float* distances;
    const vec4* gbuffer;
    bool fromGbuffer;
#endif
};

#ifdef __cplusplus
inline float depthFineDistance(const DepthDownsampleParams& p, ivec3 texel) {
    // cubeTexelIndex's order, widened: a six-face array at 16K² passes 2³².
    const std::size_t i = (std::size_t(texel.z) * std::size_t(p.res) + std::size_t(texel.y)) * std::size_t(p.res) +
                          std::size_t(texel.x);
    return p.fromGbuffer ? p.gbuffer[i].w : p.distances[i];
}
#else
float depthFineDistance(ivec3 texel);  // the including shader's
float depthFineDistance(DepthDownsampleParams p, ivec3 texel) { return depthFineDistance(texel); }
#endif

// The fine texels [first, end) in one coordinate that coarse coordinate c covers: ⌊c·res/depthRes⌋ to
// ⌊(c+1)·res/depthRes⌋, so any depthRes ≤ res works, not only divisors. Unsigned: exact while
// res² < 2³² (res < 65536).
CUBEAO_FN ivec2 depthCoarseSpan(int c, int res, int depthRes) {
    return ivec2(int(uint(c) * uint(res) / uint(depthRes)), int(uint(c + 1) * uint(res) / uint(depthRes)));
}

// The min filter: coarse texel (I, J, face) = the nearest non-empty fine distance it covers, 0 when
// all are empty (conservative: a point behind any of them is hidden). NaN and negatives count as empty.
CUBEAO_FN float depthCoarseMin(DepthDownsampleParams p, ivec3 coarse) {
    ivec2 si = depthCoarseSpan(coarse.x, p.res, p.depthRes), sj = depthCoarseSpan(coarse.y, p.res, p.depthRes);
    float m = 0.0f;
    for (int j = sj.x; j < sj.y; ++j)
        for (int i = si.x; i < si.y; ++i) {
            float d = depthFineDistance(p, ivec3(i, j, coarse.z));
            if (d > 0.0f && (m == 0.0f || d < m)) m = d;
        }
    return m;
}

// IEEE half with round-to-nearest-even, integer arithmetic only: NaN → 0x7E00, ±inf and
// |f| ≥ 65520 → ±inf. Rounding as in F. Giesen's float_to_half_fast3_rtne, with the subnormal range
// done as an exact power-of-two scale and roundEven instead of a float addition, so both languages
// give the same bits.
CUBEAO_FN uint depthFloatToHalf(float f) {
    uint u = floatBitsToUint(f);
    uint sign = (u >> 16u) & 0x8000u;
    u &= 0x7FFFFFFFu;
    if (u > 0x7F800000u) return sign | 0x7E00u;                                         // NaN
    if (u >= 0x47800000u) return sign | 0x7C00u;                                        // ≥ 65536: inf
    if (u < 0x38800000u) return sign | uint(roundEven(uintBitsToFloat(u) * 16777216.0f));  // < 2^-14: subnormal half
    return sign | ((u + 0xC8000FFFu + ((u >> 13u) & 1u)) >> 13u);  // rebias 127 → 15, round to even
}

// One stored texel (depth::encodeTexel documents the guarantees). 0 stays 0 (empty, also NaN and
// negatives); a positive distance never becomes 0 and a finite one never becomes infinite.
// r16unorm: round-to-nearest-even of distance / maxDistance · 65535, all in float. An unknown
// format stores 0.
CUBEAO_FN uint depthEncodeTexel(float d, int format, float maxDistance) {
    if (!(d > 0.0f)) return 0u;
    if (format == kDepthR16Unorm) {
        if (!(maxDistance > 0.0f)) return 0u;
        return max(uint(roundEven(min(d / maxDistance, 1.0f) * 65535.0f)), 1u);
    }
    if (format == kDepthR16Float) return clamp(depthFloatToHalf(d), 1u, 0x7BFFu);  // > 0, finite
    if (format == kDepthR32Float) return floatBitsToUint(d);
    return 0u;
}

CUBEAO_KERNEL_END
