#version 450 core
// What BC5 compression cost a probe's AO, measured on the GPU so the bake never reads the
// uncompressed AO back (DESIGN.md §4 "Storage"): per 8×8 tile of blocks, Σ (decoded red − AO)² and
// the number of texels, over the texels that show a surface (G-buffer distance > 0). Levels and codes
// come from common/bc4.h (bc4Level, bc4Code), which the CPU twin calls too (bc::decodeBc4Block, through
// bc::decodeBc5Cube in cpu_bake.cpp); the per-tile reduction is this pass's own.
// One invocation per block: global id (bx, by, face), the block order of bc5_encode.comp.
#include "bake_layout.h"
#include "bc4.h"
#include "cube.h"

layout(local_size_x = kBakeTileSize, local_size_y = kBakeTileSize) in;

layout(binding = kBakeGBufferUnit) uniform sampler2DArray gbuffer;                        // (normal, distance)
layout(std430, binding = kBakeAoBuffer) readonly buffer AoIn { vec2 aoConfidence[]; };    // cubeTexelIndex order
layout(std430, binding = kBakeBlocksBuffer) readonly buffer Blocks { uvec4 blocks[]; };   // red (xy), green (zw)
layout(std430, binding = kBakeErrorTilesBuffer) writeonly buffer Partial { vec2 partial[]; };  // per tile: (Σ error², texels)

layout(std140, binding = kEncodeBlock) uniform EncodeUniforms { EncodeBlock encode; };

shared vec2 tile[kBakeTileSize * kBakeTileSize];

void main() {
    int blocksPerSide = encode.res / 4;
    ivec3 b = ivec3(gl_GlobalInvocationID);
    vec2 sum = vec2(0.0);
    if (b.x < blocksPerSide && b.y < blocksPerSide) {
        uvec2 red = blocks[(b.z * blocksPerSide + b.y) * blocksPerSide + b.x].xy;
        int red0 = int(red.x & 0xFFu), red1 = int((red.x >> 8) & 0xFFu);
        for (int t = 0; t < 16; ++t) {
            ivec3 texel = ivec3(4 * b.x + (t & 3), 4 * b.y + (t >> 2), b.z);
            if (!(texelFetch(gbuffer, texel, 0).w > 0.0)) continue;
            float e = bc4Level(red0, red1, bc4Code(red, t)) - aoConfidence[cubeTexelIndex(texel, encode.res)].x;
            sum += vec2(e * e, 1.0);
        }
    }
    tile[gl_LocalInvocationIndex] = sum;
    barrier();
    for (uint stride = uint(kBakeTileSize * kBakeTileSize) / 2u; stride > 0u; stride >>= 1) {
        if (gl_LocalInvocationIndex < stride) tile[gl_LocalInvocationIndex] += tile[gl_LocalInvocationIndex + stride];
        barrier();
    }
    if (gl_LocalInvocationIndex == 0u)
        partial[(gl_WorkGroupID.z * gl_NumWorkGroups.y + gl_WorkGroupID.y) * gl_NumWorkGroups.x + gl_WorkGroupID.x] = tile[0];
}
