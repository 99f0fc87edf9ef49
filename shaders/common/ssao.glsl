// Frame of every screen-space AO pass (src/cubeao/ssao/ssao_pass.h): one invocation per pixel, the
// AO image and the fetch count. The per-pixel kernel and the estimator it calls are ssao_pixel.glsl.
#pragma once

#include "ssao_pixel.glsl"

layout(local_size_x = kPixelGroupSize, local_size_y = kPixelGroupSize) in;

layout(r32f, binding = kAoImageUnit) writeonly uniform image2D aoOut;
// G-buffer fetches made (counters.uncovered stays 0: every pixel gets an estimate).
layout(std430, binding = kPassCountersBuffer) buffer Counters { PassCounters counters; };

shared uint groupFetches;

void main() {
    if (gl_LocalInvocationIndex == 0u) groupFetches = 0u;
    barrier();
    ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
    uint fetches = 0u;
    if (onScreen(pixel)) {
        float z = ssaoDepth(pixel, fetches);
        imageStore(aoOut, pixel, vec4(ssaoPixelAo(pixel, z, fetches)));
    }
    atomicAdd(groupFetches, fetches);
    barrier();
    if (gl_LocalInvocationIndex == 0u) {
        uint before = atomicAdd(counters.fetchesLow, groupFetches);
        if (before + groupFetches < before) atomicAdd(counters.fetchesHigh, 1u);  // carry
    }
}
