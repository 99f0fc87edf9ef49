// Frame of every screen-space AO pass (src/cubeao/ssao/ssao_pass.h): one invocation per pixel, the
// AO image and the fetch count. The per-pixel kernel and the estimator it calls are ssao_pixel.glsl.
#pragma once

#include "pass_counters.glsl"
#include "ssao_pixel.glsl"

layout(local_size_x = kPixelGroupSize, local_size_y = kPixelGroupSize) in;

layout(r32f, binding = kAoImageUnit) writeonly uniform image2D aoOut;
// G-buffer fetches made, into the group's counter stripe (pass_counters.glsl; uncovered stays 0:
// every pixel gets an estimate).

void main() {
    ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
    uint fetches = 0u;
    if (onScreen(pixel)) {
        float z = ssaoDepth(pixel, fetches);
        imageStore(aoOut, pixel, vec4(ssaoPixelAo(pixel, z, fetches)));
    }
    countFetches(counterStripe(), fetches);
}
