#version 450 core
// Hybrid bake: list the texels whose horizon confidence is below the threshold, for ao_traced.comp
// (TEXEL_LIST) to trace. The list's header doubles as the indirect-dispatch arguments:
// (groups x, 1, 1, count), groups x = ceil(count / 64) kept by atomicMax. Start it at (0, 1, 1, 0).
layout(local_size_x = 64) in;

layout(binding = 0) uniform sampler2DArray gbuffer;
layout(std430, binding = 1) readonly buffer AoIn { vec2 aoConfidence[]; };
layout(std430, binding = 2) buffer TexelList { uvec4 header; uint texels[]; };

uniform int res;
uniform float threshold;

void main() {
    uint index = gl_GlobalInvocationID.x;
    if (index >= 6u * uint(res) * uint(res)) return;
    if (aoConfidence[index].y >= threshold) return;
    uint faceSize = uint(res) * uint(res);
    ivec3 t = ivec3(int(index % uint(res)), int((index % faceSize) / uint(res)), int(index / faceSize));
    if (!(texelFetch(gbuffer, t, 0).w > 0.0)) return;
    uint slot = atomicAdd(header.w, 1u);
    texels[slot] = index;
    atomicMax(header.x, slot / 64u + 1u);
}
