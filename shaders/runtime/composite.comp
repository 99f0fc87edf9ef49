#version 450 core
// Preview composite (src/cubeao/runtime/composite.h): common/composite.h's compositeColour per pixel
// with geometry, the sky colour elsewhere. Twin: compositePixel in composite.cpp.
#include "composite.h"
#include "runtime_layout.h"

layout(local_size_x = kPixelGroupSize, local_size_y = kPixelGroupSize) in;

layout(binding = kGBufferDepthUnit) uniform sampler2D gDepth;
layout(binding = kGBufferNormalUnit) uniform sampler2D gNormal;
layout(binding = kAoInputUnit) uniform sampler2D aoIn;
layout(rgba8, binding = kShadedImageUnit) writeonly uniform image2D shaded;

layout(std140, binding = kCompositeBlock) uniform CompositeUniforms { CompositeBlock composite; };

void main() {
    ivec2 c = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(c, composite.frameSize))) return;
    vec3 colour = clamp(composite.sky, 0.0, 1.0);
    if (texelFetch(gDepth, c, 0).r > 0.0)
        colour = compositeColour(texelFetch(gNormal, c, 0).xyz, composite.light, texelFetch(aoIn, c, 0).r,
                                 composite.albedo, composite.ambient, composite.diffuse, composite.alpha);
    imageStore(shaded, c, vec4(colour, 1.0));
}
