#version 450 core
// Preview composite (src/cubeao/runtime/composite.h): i = i_s · [(1 − α) + α · ao], i_s = Lambert under
// one directional light plus ambient. Twin: compositePixel in composite.cpp.
layout(local_size_x = 8, local_size_y = 8) in;

layout(binding = 0) uniform sampler2D gDepth;
layout(binding = 1) uniform sampler2D gNormal;
layout(binding = 2) uniform sampler2D aoIn;
layout(rgba8, binding = 0) writeonly uniform image2D shaded;

uniform ivec2 frameSize;
uniform vec3 light;  // view space, towards the light
uniform float alpha;
uniform float ambient;
uniform float diffuse;
uniform vec3 albedo;
uniform vec3 sky;

void main() {
    ivec2 c = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(c, frameSize))) return;
    vec3 colour = sky;
    if (texelFetch(gDepth, c, 0).r > 0.0) {
        vec3 n = texelFetch(gNormal, c, 0).xyz;
        vec3 direct = albedo * (ambient + diffuse * max(0.0, dot(n, light)));
        colour = direct * ((1.0 - alpha) + alpha * texelFetch(aoIn, c, 0).r);
    }
    imageStore(shaded, c, vec4(clamp(colour, 0.0, 1.0), 1.0));
}
