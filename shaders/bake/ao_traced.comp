#version 450 core
// Traced AO for probe texels: SPP cosine-weighted rays from the texel's surface point through the
// whole scene (BVH in SSBOs), the same rays as ambientOcclusion() in
// src/cubeao/reference/ao_reference.cpp traces for the same texelKey. TEXEL_LIST: only the texels
// listed by hybrid_select.comp (dispatched indirectly); otherwise every texel, index = global id.
#include "bake_layout.h"
#include "bvh.glsl"
#include "cube.h"
#include "falloff.h"
#include "sampling.h"

layout(local_size_x = kBakeListGroupSize) in;

layout(binding = kBakeGBufferUnit) uniform sampler2DArray gbuffer;
layout(std430, binding = kBakeAoBuffer) buffer AoOut { vec2 aoConfidence[]; };
#ifdef TEXEL_LIST
layout(std430, binding = kBakeTexelListBuffer) readonly buffer TexelList { TexelListHeader header; uint texels[]; };
#endif

layout(std140, binding = kBakeBlock) uniform BakeUniforms { BakeBlock bake; };

void main() {
#ifdef TEXEL_LIST
    if (gl_GlobalInvocationID.x >= header.count) return;
    uint index = texels[gl_GlobalInvocationID.x];
#else
    uint index = gl_GlobalInvocationID.x;
    if (index >= uint(kCubeFaces) * uint(bake.res) * uint(bake.res)) return;
#endif
    ivec3 t = cubeTexelOfIndex(index, bake.res);
    vec4 g = texelFetch(gbuffer, t, 0);
    if (!(g.w > 0.0)) {
        aoConfidence[index] = vec2(1.0);
        return;
    }
    vec3 n = g.xyz;
    vec3 org = bake.probe + cubeTexelDirection(t.z, t.xy, bake.res) * g.w + bake.surfaceEpsilon * n;
    uint key = cubeTexelKey(t, bake.res, bake.probeKey);
    float occlusion = 0.0;
    for (int k = 0; k < bake.spp; ++k) {
        vec3 dir = cosineHemisphere(rotatedHammersley(uint(k), uint(bake.spp), key), n);
        if (bake.falloff == FALLOFF_NONE) {
            occlusion += bvhOccluded(org, dir, 0.0, bake.radius) ? 1.0 : 0.0;
        } else {
            float hitT;
            uint triangle;
            if (bvhIntersect(org, dir, 0.0, bake.radius, hitT, triangle))
                occlusion += occlusionWeight(bake.falloff, hitT, bake.radius);
        }
    }
#ifdef TEXEL_LIST
    aoConfidence[index].x = 1.0 - occlusion / float(bake.spp);  // keep the horizon pass's confidence
#else
    aoConfidence[index] = vec2(1.0 - occlusion / float(bake.spp), 1.0);
#endif
}
