// Frame of every screen-space AO pass (src/cubeao/ssao/ssao_pass.h): bindings, per-pixel setup and
// fetch counting. The including shader (shaders/ssao/*.comp) defines the estimator:
//   float estimateAo(vec3 p, vec3 n, float radiusPixels, vec2 jitter, inout uint fetches)
// with p, n the pixel's view-space surface point and normal (facing the camera), radiusPixels = R
// projected at p's depth, jitter ∈ [0, 1)² per pixel and frame; it returns AO in [0, 1], 1 = open.
#pragma once

#include "camera.h"
#include "constants.h"
#include "falloff.h"
#include "runtime_layout.h"
#include "sampling.h"

layout(local_size_x = kPixelGroupSize, local_size_y = kPixelGroupSize) in;

layout(binding = kGBufferDepthUnit) uniform sampler2D gDepth;
layout(binding = kGBufferNormalUnit) uniform sampler2D gNormal;
layout(r32f, binding = kAoImageUnit) writeonly uniform image2D aoOut;
// G-buffer fetches made (counters.uncovered stays 0: every pixel gets an estimate).
layout(std430, binding = kPassCountersBuffer) buffer Counters { PassCounters counters; };

uniform float radius;           // R, world units
uniform int falloff;            // FALLOFF_NONE | FALLOFF_SMOOTH (falloff.h)
uniform int directions;         // N_d
uniform int steps;              // N_s
uniform float maxRadiusPixels;  // 0 = no clamp
uniform uint frameKey;          // frame index ^ seed

float estimateAo(vec3 p, vec3 n, float radiusPixels, vec2 jitter, inout uint fetches);

ivec2 ssaoPixel = ivec2(0);  // the pixel being shaded (set by main before estimateAo)

// The surface point the G-buffer shows at continuous pixel position `at`: false (and no fetch) off
// screen, on the shaded pixel itself, or where no geometry is.
bool samplePoint(vec2 at, out vec3 q, inout uint fetches) {
    ivec2 texel = ivec2(floor(at));
    q = vec3(0.0);
    if (!onScreen(texel) || texel == ssaoPixel) return false;
    ++fetches;
    float z = texelFetch(gDepth, texel, 0).r;
    if (!(z > 0.0)) return false;
    q = viewPosition(texel, z);
    return true;
}

// Whether the offset v from the shaded point rises above its tangent plane by more than an elevation
// of 1e-3 (0.06°). Neighbours on the same plane land on texel centres slightly off the march
// direction; without this test their rounding would read as occlusion on every flat surface.
bool aboveTangentPlane(vec3 v, vec3 n) { return dot(v, n) > 1e-3 * length(v); }

shared uint groupFetches;

void main() {
    if (gl_LocalInvocationIndex == 0u) groupFetches = 0u;
    barrier();
    ssaoPixel = ivec2(gl_GlobalInvocationID.xy);
    uint fetches = 0u;
    if (onScreen(ssaoPixel)) {
        fetches += 1u;
        float z = texelFetch(gDepth, ssaoPixel, 0).r;
        float ao = 1.0;  // no geometry: open, as in the reference
        if (z > 0.0) {
            fetches += 1u;
            vec3 n = texelFetch(gNormal, ssaoPixel, 0).xyz;
            vec3 p = viewPosition(ssaoPixel, z);
            float radiusPixels = radius * focalPixels() / z;
            if (maxRadiusPixels > 0.0) radiusPixels = min(radiusPixels, maxRadiusPixels);
            uint key = hashKey(uint(ssaoPixel.x), uint(ssaoPixel.y), frameKey);
            vec2 jitter = marchJitter(key);
            // Under a pixel the march finds only the pixel itself: nothing to resolve.
            if (radiusPixels >= 1.0) ao = clamp(estimateAo(p, n, radiusPixels, jitter, fetches), 0.0, 1.0);
        }
        imageStore(aoOut, ssaoPixel, vec4(ao));
    }
    atomicAdd(groupFetches, fetches);
    barrier();
    if (gl_LocalInvocationIndex == 0u) {
        uint before = atomicAdd(counters.fetchesLow, groupFetches);
        if (before + groupFetches < before) atomicAdd(counters.fetchesHigh, 1u);  // carry
    }
}
