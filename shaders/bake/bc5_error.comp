#version 450 core
// What BC5 compression cost a probe's AO, measured on the GPU so the bake never reads the
// uncompressed AO back (DESIGN.md §4 "Storage"): per 8×8 tile of blocks, Σ (decoded red − AO)² and
// the number of texels, over the texels that show a surface (G-buffer distance > 0). The CPU twin is
// bc::decodeBc4Block (src/cubeao/cache/bc4.h, where the block format is specified) in cpu_bake.cpp.
// One invocation per block: global id (bx, by, face), the block order of bc5_encode.comp.
layout(local_size_x = 8, local_size_y = 8) in;

layout(binding = 0) uniform sampler2DArray gbuffer;                          // (normal, distance)
layout(std430, binding = 1) readonly buffer AoIn { vec2 aoConfidence[]; };   // cube::texelIndex order
layout(std430, binding = 3) readonly buffer Blocks { uvec4 blocks[]; };      // red (xy), green (zw)
layout(std430, binding = 8) writeonly buffer Partial { vec2 partial[]; };    // per tile: (Σ error², texels)

uniform int res;

shared vec2 tile[64];

// Level `code` of a BC4 block with endpoints red0, red1 (RGTC, OpenGL 4.5 core appendix C.1).
float bc4Level(uint red0, uint red1, uint code) {
    if (code == 0u) return float(red0) / 255.0;
    if (code == 1u) return float(red1) / 255.0;
    if (red0 > red1) return float((8u - code) * red0 + (code - 1u) * red1) / 1785.0;  // 7 · 255
    if (code == 6u) return 0.0;
    if (code == 7u) return 1.0;
    return float((6u - code) * red0 + (code - 1u) * red1) / 1275.0;  // 5 · 255
}

void main() {
    int blocksPerSide = res / 4;
    ivec3 b = ivec3(gl_GlobalInvocationID);
    vec2 sum = vec2(0.0);
    if (b.x < blocksPerSide && b.y < blocksPerSide) {
        uvec2 red = blocks[(b.z * blocksPerSide + b.y) * blocksPerSide + b.x].xy;
        uint red0 = red.x & 0xFFu, red1 = (red.x >> 8) & 0xFFu;
        for (int t = 0; t < 16; ++t) {
            ivec3 texel = ivec3(4 * b.x + (t & 3), 4 * b.y + (t >> 2), b.z);
            if (!(texelFetch(gbuffer, texel, 0).w > 0.0)) continue;
            uint bit = uint(16 + 3 * t);  // the 64-bit block's bits [bit, bit + 3)
            uint code = (bit < 32u ? (red.x >> bit) | (bit > 0u ? red.y << (32u - bit) : 0u) : red.y >> (bit - 32u)) & 7u;
            float e = bc4Level(red0, red1, code) - aoConfidence[(texel.z * res + texel.y) * res + texel.x].x;
            sum += vec2(e * e, 1.0);
        }
    }
    tile[gl_LocalInvocationIndex] = sum;
    barrier();
    for (uint stride = 32u; stride > 0u; stride >>= 1) {
        if (gl_LocalInvocationIndex < stride) tile[gl_LocalInvocationIndex] += tile[gl_LocalInvocationIndex + stride];
        barrier();
    }
    if (gl_LocalInvocationIndex == 0u)
        partial[(gl_WorkGroupID.z * gl_NumWorkGroups.y + gl_WorkGroupID.y) * gl_NumWorkGroups.x + gl_WorkGroupID.x] = tile[0];
}
