#version 450 core
// One pass of the separable edge-aware AO blur (src/cubeao/runtime/blur.h): 2·radius + 1 taps along
// the block's axis, the spatial times the bilateral weight of common/bilateral.h for each tap. Twin: blurAoCpu in
// blur.cpp (same weights; its tap loop reads an Image instead of textures).
#include "bilateral.h"
#include "camera.h"
#include "runtime_layout.h"

layout(local_size_x = kPixelGroupSize, local_size_y = kPixelGroupSize) in;

layout(binding = kGBufferDepthUnit) uniform sampler2D gDepth;
layout(binding = kGBufferNormalUnit) uniform sampler2D gNormal;
layout(binding = kAoInputUnit) uniform sampler2D aoIn;
layout(r32f, binding = kAoImageUnit) writeonly uniform image2D aoOut;

layout(std140, binding = kBlurBlock) uniform BlurUniforms { BlurBlock blur; };

void main() {
    ivec2 c = ivec2(gl_GlobalInvocationID.xy);
    if (!onScreen(c)) return;
    float ao = texelFetch(aoIn, c, 0).r;
    float zc = texelFetch(gDepth, c, 0).r;
    if (zc > 0.0) {
        vec3 nc = texelFetch(gNormal, c, 0).xyz;
        vec3 pc = viewPosition(c, zc);
        float sum = ao, weights = 1.0;
        for (int i = -blur.radius; i <= blur.radius; ++i) {
            ivec2 s = c + i * blur.axis;
            if (i == 0 || !onScreen(s)) continue;
            float zs = texelFetch(gDepth, s, 0).r;
            if (!(zs > 0.0)) continue;
            float w = bilateralSpatialWeight(i, blur.radius) *
                      bilateralWeight(nc, pc, zc, texelFetch(gNormal, s, 0).xyz, viewPosition(s, zs),
                                      blur.normalPower, blur.depthTolerance);
            sum += w * texelFetch(aoIn, s, 0).r;
            weights += w;
        }
        ao = sum / weights;
    }
    imageStore(aoOut, c, vec4(ao));
}
