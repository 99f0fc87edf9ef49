#version 450 core
// Hybrid bake: list the texels whose horizon confidence is below the threshold, for ao_traced.comp
// (TEXEL_LIST) to trace. The list's header doubles as the indirect-dispatch arguments:
// TexelListHeader (bake_layout.h), groupsX = ceil(count / kBakeListGroupSize) kept by atomicMax.
#include "bake_layout.h"
#include "cube.h"

layout(local_size_x = kBakeListGroupSize) in;

layout(binding = kBakeGBufferUnit) uniform sampler2DArray gbuffer;
layout(std430, binding = kBakeAoBuffer) readonly buffer AoIn { vec2 aoConfidence[]; };
layout(std430, binding = kBakeTexelListBuffer) buffer TexelList { TexelListHeader header; uint texels[]; };

layout(std140, binding = kBakeBlock) uniform BakeUniforms { BakeBlock bake; };

void main() {
    uint index = gl_GlobalInvocationID.x;
    if (index >= uint(kCubeFaces) * uint(bake.res) * uint(bake.res)) return;
    if (aoConfidence[index].y >= bake.threshold) return;
    ivec3 t = cubeTexelOfIndex(index, bake.res);
    if (!(texelFetch(gbuffer, t, 0).w > 0.0)) return;
    uint slot = atomicAdd(header.count, 1u);
    texels[slot] = index;
    atomicMax(header.groupsX, slot / uint(kBakeListGroupSize) + 1u);
}
