#version 450 core
// The screen-space fallback of the probe projection (src/cubeao/ssao/gtao_fallback.h, DESIGN.md §4
// "Run time that grows"): pixels whose raw AO is below 0 (kUncoveredAo: no resident probe sees them)
// take the GTAO value, and covered pixels within kFallbackBlendPixels of one take GTAO in part, so
// the two estimators meet without a seam. The GTAO per pixel is the baseline's own kernel
// (ssao_pixel.glsl + gtao_march.glsl): at any pixel it equals the gtao pass, bit for bit.
//
// Three dispatches of this file (GTAO_FILL_PASS 0, 1, 2), because the AO image is rewritten in place:
// a group that read its neighbours' "uncovered" state from the image could find a hole pixel that
// another group (run earlier, in any order) had already filled, and stop blending towards it. So
//   0 mark (an invocation per tile row): each uncovered pixel sets its bit in its 8 × 8 tile's mask,
//     and every tile within the blend band of one is listed, once (runtime_layout.h FallbackTile,
//     FallbackList); the image is only read;
//   1 select (indirect, a group per listed tile): from the masks alone, which nothing changes any
//     more, each pixel finds its distance to the nearest uncovered pixel and, within the band, puts
//     itself on the work list; nothing reads or writes the image;
//   2 fill (indirect, 64 work items a group): GTAO from the G-buffer only, then each item reads (to
//     blend) and writes its own pixel, which no other invocation touches.
// Cost: mark reads each pixel once and does nothing more where it is covered; select runs only for
// tiles that hold or border a hole; GTAO runs only for the pixels that take it, packed densely, so a
// SIMD batch (llvmpipe) or warp does not march for one pixel while the rest of its tile idles: with
// 1 % of the pixels uncovered in blobs of 2–6 pixels that took the fallback from about 0.17 to 0.11 ×
// a full gtao pass (llvmpipe, 1080p). No shared memory or barriers: a barrier anywhere in a shader
// makes Mesa llvmpipe run every group as coroutines, which cost idle groups more than the whole mark
// dispatch (1080p, measured).
#include "camera.h"
#include "gtao_march.glsl"
#include "runtime_layout.h"

layout(local_size_x = kPixelGroupSize, local_size_y = kPixelGroupSize) in;

layout(std430, binding = kFallbackTileBuffer) buffer Tiles { FallbackTile tiles[]; };
layout(std430, binding = kFallbackTileListBuffer) buffer TileList {
    FallbackList tileList;
    uint listedTiles[];
};
layout(std430, binding = kFallbackWorkBuffer) buffer WorkList {
    FallbackList workList;
    uint workItems[];
};

// Pixels beyond this from every uncovered pixel (per axis) are outside the blend band.
const int kApron = kFallbackBlendPixels - 1;
const int kBandSquared = kFallbackBlendPixels * kFallbackBlendPixels;
const uint kGroupInvocations = uint(kPixelGroupSize * kPixelGroupSize);

// Tiles (8 × 8 pixels, the work groups of select) per axis.
ivec2 tileCount() { return (camera.frameSize + kPixelGroupSize - 1) / kPixelGroupSize; }
bool tileOnScreen(ivec2 tile) { return all(greaterThanEqual(tile, ivec2(0))) && all(lessThan(tile, tileCount())); }
uint tileIndex(ivec2 tile) { return uint(tile.y * tileCount().x + tile.x); }

#if GTAO_FILL_PASS == 0

layout(r32f, binding = kAoImageUnit) readonly uniform image2D aoImage;

// Puts a tile on the tile list, once (the plain read only spares the atomic).
void listTile(ivec2 tile) {
    if (!tileOnScreen(tile)) return;
    uint t = tileIndex(tile);
    if (tiles[t].listed != 0u || atomicExchange(tiles[t].listed, 1u) != 0u) return;
    listedTiles[atomicAdd(tileList.entries, 1u)] = t;
    atomicAdd(tileList.groupsX, 1u);
}

// One invocation per row of a tile (8 pixels), a group per 8 tiles side by side: the dispatch has an
// eighth of the groups of a per-pixel one, which on llvmpipe, where every group has a fixed cost, made
// a frame without holes 3–5 times cheaper (1080p; the row loop costs nothing there).
void main() {
    ivec2 tile = ivec2(gl_WorkGroupID.x * uint(kPixelGroupSize) + gl_LocalInvocationID.x, gl_WorkGroupID.y);
    int row = int(gl_LocalInvocationID.y);
    int y = tile.y * kPixelGroupSize + row;
    if (!tileOnScreen(tile) || y >= camera.frameSize.y) return;
    uint bits = 0u;  // bit x: pixel x of the row is uncovered
    for (int x = 0; x < kPixelGroupSize; ++x) {
        ivec2 pixel = ivec2(tile.x * kPixelGroupSize + x, y);
        if (pixel.x < camera.frameSize.x && imageLoad(aoImage, pixel).r < 0.0) bits |= 1u << uint(x);
    }
    if (bits == 0u) return;
    uint t = tileIndex(tile);
    if (row < 4) atomicOr(tiles[t].mask0, bits << uint(8 * row));
    else atomicOr(tiles[t].mask1, bits << uint(8 * (row - 4)));
    // This tile and each neighbour whose nearest pixel lies within the band (distance < B) of one of
    // the row's uncovered pixels: the leftmost one for the tiles on the left, the rightmost for the right.
    int leftmost = findLSB(bits), rightmost = findMSB(bits);
    for (int j = -1; j <= 1; ++j) {
        int dy = j < 0 ? row + 1 : j > 0 ? kPixelGroupSize - row : 0;
        for (int i = -1; i <= 1; ++i) {
            int dx = i < 0 ? leftmost + 1 : i > 0 ? kPixelGroupSize - rightmost : 0;
            if (dx * dx + dy * dy < kBandSquared) listTile(tile + ivec2(i, j));
        }
    }
}

#elif GTAO_FILL_PASS == 1

// The uncovered-pixel mask of the tile at `tile` (0 off screen): .x rows 0–3, .y rows 4–7.
uvec2 tileMask(ivec2 tile) {
    if (!tileOnScreen(tile)) return uvec2(0u);
    uint t = tileIndex(tile);
    return uvec2(tiles[t].mask0, tiles[t].mask1);
}

// Row r (0–7) of a tile mask: bit x = pixel x.
uint maskRow(uvec2 mask, int r) { return ((r < 4 ? mask.x : mask.y) >> uint(8 * (r & 3))) & 0xffu; }

void main() {
    uint t = listedTiles[gl_WorkGroupID.x];
    ivec2 tile = ivec2(int(t) % tileCount().x, int(t) / tileCount().x);
    // The 3 × 3 tiles around this one, (dx + 1) + 3 (dy + 1).
    uvec2 masks[9];
    for (int j = -1; j <= 1; ++j)
        for (int i = -1; i <= 1; ++i) masks[(i + 1) + 3 * (j + 1)] = tileMask(tile + ivec2(i, j));

    // Squared distance to the nearest uncovered pixel within kApron per axis (0: this one): per row,
    // the 24 bits of the three tiles side by side and the set bits nearest this pixel's column.
    ivec2 local = ivec2(gl_LocalInvocationID.xy);
    int nearest = kBandSquared;  // = none within the band
    for (int dy = -kApron; dy <= kApron; ++dy) {
        int y = local.y + dy;  // −kApron … 7 + kApron
        int base = 3 * (y < 0 ? 0 : y < kPixelGroupSize ? 1 : 2);
        int r = y & (kPixelGroupSize - 1);
        uint row = maskRow(masks[base], r) | (maskRow(masks[base + 1], r) << 8u) | (maskRow(masks[base + 2], r) << 16u);
        int column = local.x + kPixelGroupSize;
        uint atOrLeft = row & ((2u << uint(column)) - 1u);
        uint atOrRight = row >> uint(column);
        int dx = kApron + 1;
        if (atOrLeft != 0u) dx = column - findMSB(atOrLeft);
        if (atOrRight != 0u) dx = min(dx, findLSB(atOrRight));
        if (dx <= kApron) nearest = min(nearest, dx * dx + dy * dy);
    }

    ivec2 pixel = tile * kPixelGroupSize + local;
    if (!onScreen(pixel) || nearest >= kBandSquared) return;
    uint slot = atomicAdd(workList.entries, 1u);
    workItems[slot] = fallbackWorkItem(pixel.x, pixel.y, nearest);
    if (slot % kGroupInvocations == 0u) atomicAdd(workList.groupsX, 1u);  // ⌈entries / 64⌉ groups
}

#else

// Read and written at the item's own texel only (see above).
layout(r32f, binding = kAoImageUnit) uniform image2D aoImage;
layout(std430, binding = kFallbackCountersBuffer) buffer Counters { FallbackCounters counters; };

void main() {
    uint index = gl_WorkGroupID.x * kGroupInvocations + gl_LocalInvocationIndex;
    if (index >= workList.entries) return;
    uint item = workItems[index];
    ivec2 pixel = ivec2(int(item & 0x1fffu), int((item >> 13u) & 0x1fffu));
    int nearest = int(item >> 26u);
    // Counters by plain atomics (no shared-memory sum: no barrier, above).
    uint fetches = 0u;
    float z = ssaoDepth(pixel, fetches);
    if (nearest == 0) {
        imageStore(aoImage, pixel, vec4(ssaoPixelAo(pixel, z, fetches)));
        atomicAdd(counters.filled, 1u);
    } else if (z > 0.0) {  // a pixel without geometry keeps its value (1)
        float weight = 1.0 - sqrt(float(nearest)) / float(kFallbackBlendPixels);  // > 0 in the band
        float probeAo = imageLoad(aoImage, pixel).r;
        imageStore(aoImage, pixel, vec4(mix(probeAo, ssaoPixelAo(pixel, z, fetches), weight)));
        atomicAdd(counters.blended, 1u);
    }
    uint before = atomicAdd(counters.fetchesLow, fetches);
    if (before + fetches < before) atomicAdd(counters.fetchesHigh, 1u);  // carry
}

#endif
