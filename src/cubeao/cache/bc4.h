// BC4 / BC5 (RGTC1 / RGTC2, unsigned) blocks for probe caches: AO in red, confidence in green,
// 1 byte per texel. CPU reference encoder and the decoder; the GPU encoder that a bake uses is
// shaders/bake/bc5_encode.comp (driver: src/cubeao/bake/gpu_bc5.h), which produces the same bytes:
// both compile the block encoder of shaders/common/bc4.h ("common/bc4.h").
//
// Format: EXT_texture_compression_rgtc, "RGTC Compressed Texture Image Formats" (= OpenGL 4.5 core,
// appendix C.1). A BC4 block is 64 bits, little-endian: bits 0-7 red_0, bits 8-15 red_1, then 16
// 3-bit codes, texel (x, y) of the block at bits 16 + 3·(4y + x). With R0 = red_0/255, R1 = red_1/255:
//   red_0 >  red_1: code 0 → R0, 1 → R1, i = 2..7 → ((8−i)·R0 + (i−1)·R1) / 7   (8 levels)
//   red_0 <= red_1: code 0 → R0, 1 → R1, i = 2..5 → ((6−i)·R0 + (i−1)·R1) / 5, 6 → 0, 7 → 1
// A BC5 block is 16 bytes: the red BC4 block, then the green one.
//
// Cube layout (encodeBc5Cube / decodeBc5Cube): faces in order; per face the (res/4)² blocks in rows
// of blocks bottom-up, blocks left to right; block (bx, by) holds texels i = 4bx + x, j = 4by + y
// (cube::texelIndex, rows bottom-up). Face f is therefore exactly the data that
// glCompressedTextureSubImage3D(..., zoffset f, ..., GL_COMPRESSED_RG_RGTC2, ...) takes for layer f
// of a 2D array texture (texel row 0 first in memory).
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include <glm/vec2.hpp>

#include "common/bc4.h"
#include "cubeao/cache/cache_file.h"

namespace cubeao::bc {

constexpr int kBlockSize = kernel::kBc4BlockSize;  // texels per block side: 4
constexpr std::size_t kBc4Bytes = 8;
constexpr std::size_t kBc5Bytes = 16;
constexpr int kMaxRes = 1 << 16;     // larger faces are rejected (keeps every size far from overflow)

// The block that minimises, over the candidates tried, the squared error of the decoded block
// against values[] (16 texels, row-major: values[4y + x]). Values are clamped to [0, 1] (NaN
// counts as 0). Tries both modes; endpoints start from the block's range, are refined by least
// squares on the current codes and then by a descent over ±1 steps (details in common/bc4.h).
// Deterministic, and integer-exact after quantising inputs to 1/8925: bc5_encode.comp returns
// identical blocks.
std::uint64_t encodeBc4Block(const float values[16]);

// Decodes per the formulas above, as float: each value is the nearest float to the exact rational.
// (Mesa decodes to 8 bits first; its results may differ from these by < 1/255.)
void decodeBc4Block(std::uint64_t block, float out[16]);

// Bytes of a BC5 cube of res × res faces: 6 · (res/4)² · 16. Throws std::invalid_argument unless
// res is a multiple of 4 in [4, kMaxRes] (every res the bake produces is; partial blocks are not
// supported).
std::size_t bc5Size(int res);

// aoConfidence: 6·res² pairs in cube::texelIndex order (x = AO → red, y = confidence → green).
// Returns bc5Size(res) bytes. Throws std::invalid_argument for a bad res or size.
std::vector<std::uint8_t> encodeBc5Cube(const std::vector<glm::vec2>& aoConfidence, int res);

// Decodes a BC5 cube into out (resized to 6·res², texel index order). Returns false, touching
// neither data beyond `size` bytes nor out, when res is invalid or size != bc5Size(res). Any bytes of
// the right size decode to values in [0, 1]: BC5 has no invalid blocks.
bool decodeBc5Cube(const std::uint8_t* data, std::size_t size, int res, std::vector<glm::vec2>& out);

// Decodes a cache's AO section in either format (CacheParams::aoFormat) as decodeBc5Cube does; a BC4
// section decodes with confidence 1 in every texel, as the run time reads it. False as above.
bool decodeAoCube(std::span<const std::uint8_t> section, int res, AoFormat format, std::vector<glm::vec2>& out);

}  // namespace cubeao::bc
