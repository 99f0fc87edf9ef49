// The per-pixel kernel of every screen-space AO estimate: G-buffer bindings, the method's settings,
// the pixel's setup (surface point, projected radius, jitter) and the sample lookup the estimators
// march with. Two frames run it: shaders/common/ssao.glsl (every pixel: the baselines, ssao_pass.h)
// and shaders/ssao/gtao_fill.comp (only the pixels the probe projection left open: gtao_fallback.h),
// so the fallback's GTAO at a pixel is the baseline's GTAO there, bit for bit.
// The including shader defines the estimator:
//   float estimateAo(vec3 p, vec3 n, float radiusPixels, vec2 jitter, inout uint fetches)
// with p, n the pixel's view-space surface point and normal (facing the camera), radiusPixels = R
// projected at p's depth, jitter ∈ [0, 1)² per pixel and frame; it returns AO in [0, 1], 1 = open.
#pragma once

#include "camera.h"
#include "constants.h"
#include "falloff.h"
#include "runtime_layout.h"
#include "sampling.h"

layout(binding = kGBufferDepthUnit) uniform sampler2D gDepth;
layout(binding = kGBufferNormalUnit) uniform sampler2D gNormal;

// The method's settings (runtime_layout.h SsaoBlock); the frame's noise key is camera.frameKey.
layout(std140, binding = kSsaoBlock) uniform SsaoUniforms { SsaoBlock ssao; };

float estimateAo(vec3 p, vec3 n, float radiusPixels, vec2 jitter, inout uint fetches);

ivec2 ssaoPixel = ivec2(0);  // the pixel being shaded (set by ssaoPixelAo before estimateAo)

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

// The view depth of on-screen pixel `pixel` (0 = no geometry), one fetch.
float ssaoDepth(ivec2 pixel, inout uint fetches) {
    fetches += 1u;
    return texelFetch(gDepth, pixel, 0).r;
}

// AO of on-screen pixel `pixel` whose view depth ssaoDepth gave as z: 1 without geometry, as in the
// reference. Reads the G-buffer only.
float ssaoPixelAo(ivec2 pixel, float z, inout uint fetches) {
    ssaoPixel = pixel;
    float ao = 1.0;  // no geometry: open, as in the reference
    if (z > 0.0) {
        fetches += 1u;
        vec3 n = texelFetch(gNormal, pixel, 0).xyz;
        vec3 p = viewPosition(pixel, z);
        float radiusPixels = ssao.radius * focalPixels() / z;
        if (ssao.maxRadiusPixels > 0.0) radiusPixels = min(radiusPixels, ssao.maxRadiusPixels);
        uint key = hashKey(uint(pixel.x), uint(pixel.y), camera.frameKey);
        vec2 jitter = marchJitter(key);
        // Under a pixel the march finds only the pixel itself: nothing to resolve.
        if (radiusPixels >= 1.0) ao = clamp(estimateAo(p, n, radiusPixels, jitter, fetches), 0.0, 1.0);
    }
    return ao;
}
