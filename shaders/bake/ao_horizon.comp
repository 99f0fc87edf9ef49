#version 450 core
// Horizon AO for every texel of a probe (DESIGN.md §4 "Bake"): ESTIMATOR 0 = horizon-split
// (Oswald ch. 4), 1 = GTAO (paper 002). One invocation per texel, (i, j, face) = global id.
layout(local_size_x = 8, local_size_y = 8) in;

layout(binding = 0) uniform sampler2DArray gbuffer;
vec4 horizonFetch(ivec3 texel) { return texelFetch(gbuffer, texel, 0); }
#include "horizon.glsl"

layout(std430, binding = 1) writeonly buffer AoOut { vec2 aoConfidence[]; };  // cube::texelIndex order
// G-buffer lookups made, as a 64-bit count in two words (a probe at 512² can pass 2³²).
layout(std430, binding = 4) buffer FetchCount { uint fetchesLow, fetchesHigh; };

uniform vec3 probe;
uniform int res;
uniform float radius;
uniform int directions;
uniform int steps;
uniform int falloff;
uniform uint probeKey;  // probe index ^ seed, as texelKey() in src/cubeao/bake/bake_settings.cpp

shared uint groupFetches;

void main() {
    if (gl_LocalInvocationIndex == 0u) groupFetches = 0u;
    barrier();
    ivec3 t = ivec3(gl_GlobalInvocationID);
    uint fetches = 0u;
    if (t.x < res && t.y < res) {
        uint index = (uint(t.z) * uint(res) + uint(t.y)) * uint(res) + uint(t.x);
        vec4 g = texelFetch(gbuffer, t, 0);
        vec2 result = vec2(1.0);  // empty texel: open sky
        if (g.w > 0.0) {
            HorizonParams hp = HorizonParams(probe, res, radius, directions, steps, falloff);
            vec3 p = probe + cubeTexelDirection(t.z, t.xy, res) * g.w;
            uint key = hashKey(uint(t.x), uint(t.z * res + t.y), probeKey);
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
        uint before = atomicAdd(fetchesLow, groupFetches);
        if (before + groupFetches < before) atomicAdd(fetchesHigh, 1u);  // carry
    }
}
