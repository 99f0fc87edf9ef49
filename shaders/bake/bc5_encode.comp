#version 450 core
// BC5 (RGTC2, unsigned) encoder for a probe's (AO, confidence): red = AO, green = confidence, each a
// BC4 block. The block encoder is bc4EncodeBlock of common/bc4.h (format, algorithm and reasons
// there), the one the CPU's bc::encodeBc4Block compiles too, hence the same blocks (tests/cache/test_bc.cpp
// checks this bit for bit). One exception: GLSL leaves comparisons with NaN undefined, so a NaN input
// gives an unspecified level here (C++: 0). This file is only the dispatch framing.
//
// One invocation per block and channel: global id (2·bx + channel, by, face). Block order: faces, then
// block rows bottom-up, then blocks left to right (src/cubeao/cache/bc4.h).
#include "bake_layout.h"
#include "bc4.h"

layout(local_size_x = kBakeTileSize, local_size_y = kBakeTileSize) in;

layout(std430, binding = kBakeAoBuffer) readonly buffer AoIn { vec2 aoConfidence[]; };  // cubeTexelIndex order
layout(std430, binding = kBakeBlocksBuffer) writeonly buffer BlocksOut { uvec4 blocks[]; };  // red (xy), green (zw)

layout(std140, binding = kEncodeBlock) uniform EncodeUniforms { EncodeBlock encode; };

void main() {
    int blocksPerSide = encode.res / 4;
    ivec3 id = ivec3(gl_GlobalInvocationID);
    if (id.x >= 2 * blocksPerSide || id.y >= blocksPerSide) return;
    int bx = id.x >> 1, channel = id.x & 1, by = id.y, face = id.z;
    int q[16];  // this invocation's block, in units
    for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 4; ++x) {
            int texel = (face * encode.res + 4 * by + y) * encode.res + 4 * bx + x;
            q[4 * y + x] = bc4Quantise(aoConfidence[texel][channel]);
        }
    uvec2 words = bc4EncodeBlock(q);
    int block = (face * blocksPerSide + by) * blocksPerSide + bx;
    if (channel == 0)
        blocks[block].xy = words;
    else
        blocks[block].zw = words;
}
