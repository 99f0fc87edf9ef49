#version 450 core
// A probe's distance cube for the cache (DESIGN.md §4 "Storage"; docs/FORMAT.md "Distance cube").
// The kernels (the Min filter, the half conversion, the texel encoding) are common/depth_encode.h's,
// which src/cubeao/cache/depth_cube.cpp compiles too, so both give the same bytes (r16unorm: within
// one code, GLSL division is not correctly rounded everywhere). This file is the dispatch framing:
// the largest distance as an atomicMax on the bits (depth::maxDistance's value: non-negative floats
// order like their bits) and the packing of 16-bit texels into words.
//   PASS 0: coarse texel (I, J, face) = the smallest non-zero G-buffer distance of the fine texels it
//           covers, 0 when all are empty; the largest coarse value → maxBits (the r16unorm scale).
//   PASS 1: one output word per r32float texel, or per two r16 texels (texel 2k in the low half:
//           little-endian u16s). 6·depthRes² is even, so pairs never straddle the end.
#include "bake_layout.h"
#include "depth_encode.h"

// Declared in both passes: the linker resolves depth_encode.h's call of depthFineDistance, although
// only PASS 0 makes it.
layout(binding = kBakeGBufferUnit) uniform sampler2DArray gbuffer;  // (normal, distance) per texel, 6 layers
float depthFineDistance(ivec3 texel) { return texelFetch(gbuffer, texel, 0).w; }
layout(std140, binding = kEncodeBlock) uniform EncodeUniforms { EncodeBlock encode; };

#if PASS == 0
layout(local_size_x = kBakeTileSize, local_size_y = kBakeTileSize) in;
#else
layout(local_size_x = kBakeListGroupSize) in;
#endif

layout(std430, binding = kBakeCoarseBuffer) buffer Coarse { float coarse[]; };  // cubeTexelIndex order at depthRes
layout(std430, binding = kBakeMaxDistanceBuffer) buffer MaxDistance { uint maxBits; };  // floatBitsToUint of a value ≥ 0
layout(std430, binding = kBakeDepthWordsBuffer) writeonly buffer Words { uint words[]; };


#if PASS == 0
shared uint groupMax;

void main() {
    if (gl_LocalInvocationIndex == 0u) groupMax = 0u;
    barrier();
    ivec3 c = ivec3(gl_GlobalInvocationID);
    if (c.x < encode.depthRes && c.y < encode.depthRes) {
        float m = depthCoarseMin(DepthDownsampleParams(encode.res, encode.depthRes), c);
        coarse[(c.z * encode.depthRes + c.y) * encode.depthRes + c.x] = m;
        atomicMax(groupMax, floatBitsToUint(m));  // non-negative floats order like their bits
    }
    barrier();
    if (gl_LocalInvocationIndex == 0u) atomicMax(maxBits, groupMax);
}

#else
void main() {
    uint k = gl_GlobalInvocationID.x;
    uint texels = 6u * uint(encode.depthRes * encode.depthRes);
    float maxDistance = uintBitsToFloat(maxBits);
    if (encode.format == kDepthR32Float) {
        if (k < texels) words[k] = depthEncodeTexel(coarse[k], encode.format, maxDistance);
    } else if (2u * k < texels) {
        words[k] = depthEncodeTexel(coarse[2u * k], encode.format, maxDistance) |
                   depthEncodeTexel(coarse[2u * k + 1u], encode.format, maxDistance) << 16;
    }
}
#endif
