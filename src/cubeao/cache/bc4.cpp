// BC4 reference encoder and decoder (format in bc4.h). The block encoder, the levels and the code
// layout are common/bc4.h's (shaders/common/bc4.h, which explains the algorithm), the code that
// shaders/bake/bc5_encode.comp and bc5_error.comp compile too; tests/cache/test_bc.cpp checks that CPU and
// GPU produce identical blocks. Here only the framing: 64-bit blocks, the cube layout, and the
// decoder's loop, which has no GPU twin (a GPU samples BC5 textures in its texture unit).
#include "cubeao/cache/bc4.h"

#include <stdexcept>
#include <string>

#include "common/bc4.h"

namespace cubeao::bc {

namespace {

bool validRes(int res) { return res > 0 && res <= kMaxRes && res % kBlockSize == 0; }

void checkRes(int res) {
    if (!validRes(res))
        throw std::invalid_argument("BC5 cube: face resolution " + std::to_string(res) + " is not a multiple of 4 in [4, " +
                                    std::to_string(kMaxRes) + "]");
}

}  // namespace

std::uint64_t encodeBc4Block(const float values[16]) {
    int q[kernel::kBc4Texels];
    for (int t = 0; t < kernel::kBc4Texels; ++t) q[t] = kernel::bc4Quantise(values[t]);
    const glm::uvec2 words = kernel::bc4EncodeBlock(q);
    return kernel::joinWords(words.x, words.y);
}

void decodeBc4Block(std::uint64_t block, float out[16]) {
    const glm::uvec2 words(std::uint32_t(block), std::uint32_t(block >> 32));
    const int red0 = int(block & 0xFF), red1 = int(block >> 8 & 0xFF);
    float levels[8];
    for (int code = 0; code < 8; ++code) levels[code] = kernel::bc4Level(red0, red1, code);
    for (int t = 0; t < kernel::kBc4Texels; ++t) out[t] = levels[kernel::bc4Code(words, t)];
}

std::size_t bc5Size(int res) {
    checkRes(res);
    const std::size_t blocksPerSide = std::size_t(res / kBlockSize);
    return 6 * blocksPerSide * blocksPerSide * kBc5Bytes;
}

std::vector<std::uint8_t> encodeBc5Cube(const std::vector<glm::vec2>& aoConfidence, int res) {
    const std::size_t size = bc5Size(res), texels = 6 * std::size_t(res) * std::size_t(res);
    if (aoConfidence.size() != texels)
        throw std::invalid_argument("BC5 cube: " + std::to_string(aoConfidence.size()) + " texels given, " +
                                    std::to_string(texels) + " expected for res " + std::to_string(res));
    std::vector<std::uint8_t> out(size);
    std::uint8_t* dst = out.data();
    const int blocksPerSide = res / kBlockSize;
    for (int face = 0; face < 6; ++face)
        for (int by = 0; by < blocksPerSide; ++by)
            for (int bx = 0; bx < blocksPerSide; ++bx) {
                float red[16], green[16];
                for (int y = 0; y < 4; ++y)
                    for (int x = 0; x < 4; ++x) {
                        const glm::vec2 v = aoConfidence[(std::size_t(face) * std::size_t(res) + std::size_t(4 * by + y)) *
                                                             std::size_t(res) + std::size_t(4 * bx + x)];
                        red[4 * y + x] = v.x;
                        green[4 * y + x] = v.y;
                    }
                for (const std::uint64_t block : {encodeBc4Block(red), encodeBc4Block(green)})
                    for (int b = 0; b < 8; ++b) *dst++ = std::uint8_t(block >> (8 * b));
            }
    return out;
}

bool decodeBc5Cube(const std::uint8_t* data, std::size_t size, int res, std::vector<glm::vec2>& out) {
    if (!validRes(res) || data == nullptr || size != bc5Size(res)) return false;
    out.resize(6 * std::size_t(res) * std::size_t(res));
    const int blocksPerSide = res / kBlockSize;
    const std::uint8_t* src = data;
    for (int face = 0; face < 6; ++face)
        for (int by = 0; by < blocksPerSide; ++by)
            for (int bx = 0; bx < blocksPerSide; ++bx) {
                float channels[2][16];
                for (float* channel : channels) {
                    std::uint64_t block = 0;
                    for (int b = 0; b < 8; ++b) block |= std::uint64_t(*src++) << (8 * b);
                    decodeBc4Block(block, channel);
                }
                for (int y = 0; y < 4; ++y)
                    for (int x = 0; x < 4; ++x)
                        out[(std::size_t(face) * std::size_t(res) + std::size_t(4 * by + y)) * std::size_t(res) +
                            std::size_t(4 * bx + x)] = {channels[0][4 * y + x], channels[1][4 * y + x]};
            }
    return true;
}

bool decodeAoCube(std::span<const std::uint8_t> section, int res, AoFormat format, std::vector<glm::vec2>& out) {
    if (format == AoFormat::Bc5) return decodeBc5Cube(section.data(), section.size(), res, out);
    if (format != AoFormat::Bc4 || !validRes(res) || section.size() != bc5Size(res) / 2) return false;
    const std::vector<std::uint8_t> bc5 = convertAoSection(section, std::uint32_t(res), AoFormat::Bc4, AoFormat::Bc5);
    return decodeBc5Cube(bc5.data(), bc5.size(), res, out);
}

}  // namespace cubeao::bc
