#version 450 core
// Horizon AO for every texel of a probe (DESIGN.md §4 "Bake"): ESTIMATOR 0 = horizon-split
// (Oswald ch. 4), 1 = GTAO (paper 002). One invocation per texel, (i, j, face) = global id.
#include "bake_layout.h"
#include "horizon.h"

layout(local_size_x = kBakeTileSize, local_size_y = kBakeTileSize) in;

layout(binding = kBakeGBufferUnit) uniform sampler2DArray gbuffer;
vec4 horizonFetch(ivec3 texel) { return texelFetch(gbuffer, texel, 0); }

layout(std430, binding = kBakeAoBuffer) writeonly buffer AoOut { vec2 aoConfidence[]; };  // cubeTexelIndex order
layout(std430, binding = kBakeFetchCountBuffer) buffer FetchCountBuffer { FetchCount counter; };

layout(std140, binding = kBakeBlock) uniform BakeUniforms { BakeBlock bake; };

shared uint groupFetches;

void main() {
    if (gl_LocalInvocationIndex == 0u) groupFetches = 0u;
    barrier();
    ivec3 t = ivec3(gl_GlobalInvocationID);
    uint fetches = 0u;
    if (t.x < bake.res && t.y < bake.res) {
        uint index = cubeTexelIndex(t, bake.res);
        vec4 g = texelFetch(gbuffer, t, 0);
        vec2 result = vec2(1.0);  // empty texel: open sky
        if (g.w > 0.0) {
            HorizonParams hp =
                HorizonParams(bake.probe, bake.res, bake.radius, bake.directions, bake.steps, bake.falloff);
            vec3 p = bake.probe + cubeTexelDirection(t.z, t.xy, bake.res) * g.w;
            uint key = cubeTexelKey(t, bake.res, bake.probeKey);
#if ESTIMATOR == 0
            result = horizonSplitAo(hp, p, g.xyz, key, fetches);
#else
            result = gtaoAo(hp, p, g.xyz, key, fetches);
#endif
        }
        aoConfidence[index] = result;
    }
    atomicAdd(groupFetches, fetches);
    barrier();
    if (gl_LocalInvocationIndex == 0u) {
        uint before = atomicAdd(counter.fetchesLow, groupFetches);
        if (before + groupFetches < before) atomicAdd(counter.fetchesHigh, 1u);  // carry
    }
}
