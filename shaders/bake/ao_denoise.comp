#version 450 core
// The edge-aware filter of traced AO (shaders/common/ao_denoise.h) on the GPU: every texel, or with
// TEXEL_LIST only the texels hybrid_select.comp listed (dispatched indirectly), as ao_traced.comp.
// Reads the AO from a copy made before the pass (binding kBakeAoSourceBuffer), so every texel sees
// its neighbours unfiltered, and writes the AO of binding kBakeAoBuffer, keeping the confidence.
#include "bake_layout.h"
#include "cube.h"
#include "ao_denoise.h"

layout(local_size_x = kBakeListGroupSize) in;

layout(binding = kBakeGBufferUnit) uniform sampler2DArray gbuffer;
layout(std430, binding = kBakeAoBuffer) buffer AoOut { vec2 aoConfidence[]; };
layout(std430, binding = kBakeAoSourceBuffer) readonly buffer AoSource { vec2 source[]; };
#ifdef TEXEL_LIST
layout(std430, binding = kBakeTexelListBuffer) readonly buffer TexelList { TexelListHeader header; uint texels[]; };
#endif

layout(std140, binding = kBakeBlock) uniform BakeUniforms { BakeBlock bake; };

vec4 denoiseGBuffer(ivec3 texel) { return texelFetch(gbuffer, texel, 0); }
float denoiseAo(ivec3 texel) { return source[cubeTexelIndex(texel, bake.res)].x; }

void main() {
#ifdef TEXEL_LIST
    if (gl_GlobalInvocationID.x >= header.count) return;
    uint index = texels[gl_GlobalInvocationID.x];
#else
    uint index = gl_GlobalInvocationID.x;
    if (index >= uint(kCubeFaces) * uint(bake.res) * uint(bake.res)) return;
#endif
    aoConfidence[index].x =
        aoDenoiseTexel(cubeTexelOfIndex(index, bake.res), bake.res, bake.probe, bake.denoiseRadius, bake.radius);
}
