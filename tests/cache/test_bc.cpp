// The BC4/BC5 probe codec (src/cubeao/cache/bc4.h) and its GPU twin (shaders/bake/bc5_encode.comp):
// the decoder against blocks made by hand from the RGTC spec, the encoder on test images with PSNR
// floors measured here, the GPU encoder bit for bit against the CPU one, both against libsquish,
// the block layout against Mesa's own RGTC2 decoder, and wrong-size, truncated and random input.
#include <gtest/gtest.h>
#include <squish.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <functional>
#include <limits>
#include <random>
#include <stdexcept>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "cubeao/bake/bake.h"
#include "cubeao/bake/bake_settings.h"
#include "cubeao/core/cube.h"
#include "cubeao/bake/gpu_bc5.h"
#include "cubeao/cache/bc4.h"
#include "cubeao/gl/handles.h"
#include "cubeao/gl/timer.h"
#include "cubeao/reference/embree_scene.h"
#include "cubeao/scene/builtin.h"
#include "bake_test_settings.h"
#include "gl_fixture.h"

namespace cubeao {
namespace {

using Cube = std::vector<glm::vec2>;  // (AO, confidence) per texel, cube::texelIndex order
using Bytes = std::vector<std::uint8_t>;

constexpr float kInf = std::numeric_limits<float>::infinity();

std::uint64_t fromBytes(const std::array<std::uint8_t, 8>& b) {
    std::uint64_t block = 0;
    for (int i = 0; i < 8; ++i) block |= std::uint64_t(b[i]) << (8 * i);
    return block;
}

std::array<float, 16> decoded(std::uint64_t block) {
    std::array<float, 16> out{};
    bc::decodeBc4Block(block, out.data());
    return out;
}

// ---- test images -------------------------------------------------------------------------------

Cube makeCube(int res, const std::function<glm::vec2(int face, int i, int j)>& f) {
    Cube cube(6 * std::size_t(res) * std::size_t(res));
    for (int face = 0; face < 6; ++face)
        for (int j = 0; j < res; ++j)
            for (int i = 0; i < res; ++i) cube[cube::texelIndex(face, i, j, res)] = f(face, i, j);
    return cube;
}

float smoothstep(float e0, float e1, float x) {
    const float t = std::clamp((x - e0) / (e1 - e0), 0.0f, 1.0f);
    return t * t * (3.0f - 2.0f * t);
}

struct TestImage {
    const char* name;
    Cube cube;
    double minPsnr[2];  // measured floors for red (AO) and green (confidence), see imagesAt()
};

// Red and green differ in every image, so a swapped channel or block shows. The floors are the
// CPU encoder's PSNR at res 32 as measured when this was written (in brackets, dB; libsquish in
// braces), lowered by ~0.5 dB so that harmless changes pass and real regressions do not:
//  - gradients: a horizontal ramp across each face [69.9] {47.2}, a diagonal one [63.9] {46.8}.
//    A block then holds 4 (7) evenly spaced values, which fit levels 0, 2, 5, 7 or 1, 3, 5, 7 of an
//    8-level ramp almost exactly; what is left is mostly the rounding of endpoints to unorm8.
//  - steps: 0/1 cells in every arrangement inside blocks [+inf: codes 6 and 7 are exact] {+inf}, and
//    a step between 0.3 and 0.8 along a slanted edge [71.7] {58.3}: two values per block, each
//    within the rounding of an endpoint.
//  - random: uniform noise [30.8, 30.8] {29.4}. Eight evenly spread levels over [0, 1] leave
//    (1/7)/√12 ≈ 0.041 rms (27.7 dB); fitting the ramp to each block's 16 values does better.
//  - ao-like: smooth sky-to-floor shading, a contact band with a hard top edge and hard-edged pillar
//    shadows [50.5] {47.7}; confidence 1 up high, a smooth falloff towards the floor [54.4] {51.5}.
std::vector<TestImage> imagesAt(int res) {
    std::vector<TestImage> images;
    const float last = float(res - 1);
    images.push_back({"gradients", makeCube(res, [&](int, int i, int j) {
                          return glm::vec2(float(i) / last, float(i + j) / (2.0f * last));
                      }),
                      {69.3, 63.4}});
    images.push_back({"steps", makeCube(res, [&](int face, int i, int j) {
                          const float cell = (i * 3 + j * 5 + face) % 11 < 5 ? 0.0f : 1.0f;
                          const float edge = 2 * i + j < res + 3 * face ? 0.3f : 0.8f;
                          return glm::vec2(cell, edge);
                      }),
                      {kInf, 71.2}});
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> uniform(0.0f, 1.0f);
    images.push_back({"random", makeCube(res, [&](int, int, int) { return glm::vec2(uniform(rng), uniform(rng)); }),
                      {30.3, 30.3}});
    images.push_back({"ao-like", makeCube(res, [&](int face, int i, int j) {
                          const glm::vec3 d = cube::texelDirection(face, i, j, res);
                          float ao = 0.62f + 0.3f * d.y;                                   // sky above, floor below
                          if (d.y < -0.15f) ao -= 0.25f * std::exp(-(d.y + 0.15f) * -6.0f);  // contact band, hard top
                          if (std::abs(std::atan2(d.x, d.z) - 1.0f) < 0.25f && d.y < 0.4f) ao *= 0.55f;  // pillar
                          const float confidence = 0.45f + 0.55f * smoothstep(-0.6f, 0.2f, d.y);
                          return glm::vec2(std::clamp(ao, 0.0f, 1.0f), confidence);
                      }),
                      {49.9, 53.8}});
    return images;
}

// ---- measures --------------------------------------------------------------------------------

double channelPsnr(const Cube& reference, const Cube& test, int channel) {
    double sum = 0.0;
    for (std::size_t t = 0; t < reference.size(); ++t) {
        const double d = double(test[t][channel]) - double(reference[t][channel]);
        sum += d * d;
    }
    return sum == 0.0 ? double(kInf) : 10.0 * std::log10(double(reference.size()) / sum);
}

Cube decodeCube(const Bytes& bytes, int res) {
    Cube out;
    EXPECT_TRUE(bc::decodeBc5Cube(bytes.data(), bytes.size(), res, out));
    return out;
}

// libsquish's BC5 encoder on the cube quantised to 8 bits (the only input it takes), block for block
// in our order. Its blocks follow the spec layout (LibsquishWritesTheSpecLayout): decode with ours.
Bytes squishCube(const Cube& cube, int res) {
    Bytes out(bc::bc5Size(res));
    std::uint8_t* dst = out.data();
    const auto unorm8 = [](float v) { return std::uint8_t(std::lround(std::clamp(v, 0.0f, 1.0f) * 255.0f)); };
    for (int face = 0; face < 6; ++face)
        for (int by = 0; by < res / 4; ++by)
            for (int bx = 0; bx < res / 4; ++bx, dst += bc::kBc5Bytes) {
                std::uint8_t rgba[64] = {};
                for (int y = 0; y < 4; ++y)
                    for (int x = 0; x < 4; ++x) {
                        const glm::vec2 v = cube[cube::texelIndex(face, 4 * bx + x, 4 * by + y, res)];
                        rgba[4 * (4 * y + x)] = unorm8(v.x);
                        rgba[4 * (4 * y + x) + 1] = unorm8(v.y);
                        rgba[4 * (4 * y + x) + 3] = 255;
                    }
                squish::Compress(rgba, dst, squish::kBc5);
            }
    return out;
}

// ---- decoder against the spec ------------------------------------------------------------------

// Codes 0..7 in texels 0-7 and again in 8-15: 24 bits 0b111'110'101'100'011'010'001'000 = 0xFAC688,
// stored little-endian from bit 16 (bytes 2-4, then 5-7).
constexpr std::array<std::uint8_t, 3> kCodes01234567 = {0x88, 0xC6, 0xFA};

TEST(BcDecode, EightLevelModeFollowsTheSpec) {
    const auto [c0, c1, c2] = kCodes01234567;
    const auto out = decoded(fromBytes({200, 10, c0, c1, c2, c0, c1, c2}));  // red_0 > red_1
    const double r0 = 200.0 / 255.0, r1 = 10.0 / 255.0;
    const double expected[8] = {r0, r1, (6 * r0 + r1) / 7, (5 * r0 + 2 * r1) / 7, (4 * r0 + 3 * r1) / 7,
                                (3 * r0 + 4 * r1) / 7, (2 * r0 + 5 * r1) / 7, (r0 + 6 * r1) / 7};
    for (int t = 0; t < 16; ++t) EXPECT_NEAR(out[t], expected[t % 8], 1e-7) << "texel " << t;
}

TEST(BcDecode, SixLevelModeHasExplicitZeroAndOne) {
    const auto [c0, c1, c2] = kCodes01234567;
    for (const int red0 : {10, 200}) {  // red_0 < red_1, and red_0 == red_1 (also this mode)
        const auto out = decoded(fromBytes({std::uint8_t(red0), 200, c0, c1, c2, c0, c1, c2}));
        const double r0 = red0 / 255.0, r1 = 200.0 / 255.0;
        const double expected[8] = {r0, r1, (4 * r0 + r1) / 5, (3 * r0 + 2 * r1) / 5, (2 * r0 + 3 * r1) / 5,
                                    (r0 + 4 * r1) / 5, 0.0, 1.0};
        for (int t = 0; t < 16; ++t) EXPECT_NEAR(out[t], expected[t % 8], 1e-7) << "red_0 " << red0 << " texel " << t;
        EXPECT_EQ(out[6], 0.0f);  // exact, not interpolated
        EXPECT_EQ(out[7], 1.0f);
    }
}

TEST(BcDecode, EachTexelOwnsThreeBitsFromBit16) {
    // One texel at code 7 (= 1.0 in the 6-level mode with both endpoints 0), all others code 0:
    // covers texel 5 (bits 31-33, across the 32-bit word boundary) and texel 15 (bits 61-63).
    for (int texel = 0; texel < 16; ++texel) {
        const auto out = decoded(std::uint64_t(7) << (16 + 3 * texel));
        for (int t = 0; t < 16; ++t) EXPECT_EQ(out[t], t == texel ? 1.0f : 0.0f) << "set " << texel << ", read " << t;
    }
}

// ---- encoder ----------------------------------------------------------------------------------

TEST(BcEncode, ConstantBlocksAreExactForEveryUnorm8Value) {
    for (int k = 0; k < 256; ++k) {
        float values[16];
        std::fill(values, values + 16, float(k) / 255.0f);
        const auto out = decoded(bc::encodeBc4Block(values));
        for (int t = 0; t < 16; ++t) ASSERT_EQ(out[t], values[t]) << "value " << k << "/255, texel " << t;
    }
}

TEST(BcEncode, ZeroOneBlocksAreExact) {
    for (const std::uint32_t pattern : {0x0000u, 0xFFFFu, 0x8001u, 0x0F0Fu, 0x6996u, 0x1234u}) {
        float values[16];
        for (int t = 0; t < 16; ++t) values[t] = float(pattern >> t & 1);
        const auto out = decoded(bc::encodeBc4Block(values));
        for (int t = 0; t < 16; ++t) EXPECT_EQ(out[t], values[t]) << "pattern " << pattern << " texel " << t;
    }
}

TEST(BcEncode, ClampsInputToTheUnitRange) {
    float values[16];
    for (int t = 0; t < 16; ++t) values[t] = t < 4 ? -3.0f : t < 8 ? 7.0f : t < 12 ? std::nanf("") : 0.5f;
    const auto out = decoded(bc::encodeBc4Block(values));
    for (int t = 0; t < 12; ++t) EXPECT_EQ(out[t], t >= 4 && t < 8 ? 1.0f : 0.0f) << "texel " << t;  // NaN → 0
    for (int t = 12; t < 16; ++t) EXPECT_NEAR(out[t], 0.5f, 0.5f / 255.0f) << "texel " << t;
}

TEST(BcEncode, TestImagesMeetTheirMeasuredPsnr) {
    constexpr int kRes = 32;
    for (const TestImage& image : imagesAt(kRes)) {
        const Cube out = decodeCube(bc::encodeBc5Cube(image.cube, kRes), kRes);
        for (int c = 0; c < 2; ++c) {
            const double psnr = channelPsnr(image.cube, out, c);
            std::printf("[ bc4 cpu ] %-9s %s: %.2f dB\n", image.name, c == 0 ? "red  " : "green", psnr);
            EXPECT_GE(psnr, image.minPsnr[c]) << image.name << " channel " << c;
        }
    }
}

TEST(BcEncode, AtLeastAsGoodAsLibsquish) {
    constexpr int kRes = 32;
    for (const TestImage& image : imagesAt(kRes)) {
        const Cube ours = decodeCube(bc::encodeBc5Cube(image.cube, kRes), kRes);
        const Cube squish = decodeCube(squishCube(image.cube, kRes), kRes);
        for (int c = 0; c < 2; ++c) {
            const double o = channelPsnr(image.cube, ours, c), s = channelPsnr(image.cube, squish, c);
            std::printf("[ bc4 vs squish ] %-9s %s: ours %.2f dB, libsquish %.2f dB\n", image.name,
                        c == 0 ? "red  " : "green", o, s);
            EXPECT_GE(o, s - 0.5) << image.name << " channel " << c;  // the bound; measured: never below
        }
    }
}

TEST(BcEncode, LibsquishWritesTheSpecLayout) {
    // A ramp with an exact 0 and 1: libsquish picks its 6-level ("5-alpha") mode, red_0 <= red_1 in
    // byte 0 and 1, codes 6 and 7 for the 0 and the 1, codes from bit 16 as in the spec; its BC4
    // *decoder* is what is broken (it decodes the bytes as a DXT1 colour block), so ours decodes.
    std::uint8_t rgba[64] = {};
    for (int t = 0; t < 16; ++t) rgba[4 * t] = std::uint8_t(t == 0 ? 0 : t == 15 ? 255 : 20 + 13 * t);
    std::array<std::uint8_t, 8> block{};
    squish::Compress(rgba, block.data(), squish::kBc4);
    EXPECT_LE(block[0], block[1]);
    const std::uint64_t bits = fromBytes(block);
    EXPECT_EQ(bits >> 16 & 7, 6u);  // texel 0 → explicit 0
    EXPECT_EQ(bits >> 61 & 7, 7u);  // texel 15 → explicit 1
    const auto out = decoded(bits);
    const float halfStep = float(block[1] - block[0]) / 5.0f / 2.0f;  // its 6-level ramp, nearest level
    for (int t = 0; t < 16; ++t) EXPECT_NEAR(out[t] * 255.0f, float(rgba[4 * t]), halfStep + 0.01f) << t;
}

// ---- cube layout and wrong input -------------------------------------------------------------

TEST(BcCube, SizesAndResolutionChecks) {
    EXPECT_EQ(bc::bc5Size(4), 6u * 16u);
    EXPECT_EQ(bc::bc5Size(32), 6u * 64u * 16u);  // 1 byte per texel
    for (const int res : {0, -4, 2, 6, 30, bc::kMaxRes + 4}) {
        EXPECT_THROW((void)bc::bc5Size(res), std::invalid_argument) << res;
        EXPECT_THROW((void)bc::encodeBc5Cube(Cube(6 * std::size_t(std::abs(res) % 64) * std::size_t(std::abs(res) % 64)), res),
                     std::invalid_argument)
            << res;
    }
    EXPECT_THROW((void)bc::encodeBc5Cube(Cube(6 * 8 * 8 - 1), 8), std::invalid_argument);
}

TEST(BcCube, BlocksFollowFacesThenRowsBottomUpThenColumns) {
    // Every block constant at its own unorm8 value (exact, ConstantBlocksAreExactForEveryUnorm8Value):
    // block number id of the file must decode to id's value, and the whole cube back to the input.
    constexpr int kRes = 16, kPerSide = kRes / 4;
    const auto idOf = [](int face, int bx, int by) { return (face * kPerSide + by) * kPerSide + bx; };
    const Cube cube = makeCube(kRes, [&](int face, int i, int j) {
        const int id = idOf(face, i / 4, j / 4);
        return glm::vec2(float(id + 10) / 255.0f, float(245 - id) / 255.0f);
    });
    const Bytes bytes = bc::encodeBc5Cube(cube, kRes);
    for (int id = 0; id < 6 * kPerSide * kPerSide; ++id) {
        std::array<std::uint8_t, 8> red{}, green{};
        std::memcpy(red.data(), bytes.data() + std::size_t(id) * bc::kBc5Bytes, 8);
        std::memcpy(green.data(), bytes.data() + std::size_t(id) * bc::kBc5Bytes + 8, 8);
        for (const float v : decoded(fromBytes(red))) ASSERT_EQ(v, float(id + 10) / 255.0f) << "red of block " << id;
        for (const float v : decoded(fromBytes(green))) ASSERT_EQ(v, float(245 - id) / 255.0f) << "green of block " << id;
    }
    EXPECT_EQ(decodeCube(bytes, kRes), cube);
}

TEST(BcCube, DecoderRejectsWrongSizesWithoutReadingPastTheEnd) {
    constexpr int kRes = 8;
    const Bytes full = bc::encodeBc5Cube(imagesAt(kRes)[0].cube, kRes);
    const Cube untouched(3, glm::vec2(0.25f));
    for (std::size_t size = 0; size < full.size() + 2; ++size) {
        if (size == full.size()) continue;
        Bytes data(full.begin(), full.begin() + std::ptrdiff_t(std::min(size, full.size())));
        data.resize(size, 0x5A);  // truncated, or one byte too long; exact heap size so ASan sees overreads
        Cube out = untouched;
        EXPECT_FALSE(bc::decodeBc5Cube(data.data(), data.size(), kRes, out)) << size;
        EXPECT_EQ(out, untouched) << size;
    }
    Cube out = untouched;
    EXPECT_FALSE(bc::decodeBc5Cube(full.data(), full.size(), kRes / 2, out));  // the wrong res
    EXPECT_FALSE(bc::decodeBc5Cube(full.data(), full.size(), 6, out));          // not a multiple of 4
    EXPECT_FALSE(bc::decodeBc5Cube(full.data(), full.size(), -kRes, out));
    EXPECT_FALSE(bc::decodeBc5Cube(nullptr, full.size(), kRes, out));
    EXPECT_EQ(out, untouched);
    EXPECT_TRUE(bc::decodeBc5Cube(full.data(), full.size(), kRes, out));
}

TEST(BcCube, AnyBytesDecodeToTheUnitRange) {
    constexpr int kRes = 16;
    std::mt19937 rng(3);
    Bytes bytes(bc::bc5Size(kRes));
    for (auto& b : bytes) b = std::uint8_t(rng());
    Cube out;
    ASSERT_TRUE(bc::decodeBc5Cube(bytes.data(), bytes.size(), kRes, out));
    ASSERT_EQ(out.size(), 6u * kRes * kRes);
    for (const glm::vec2& v : out)
        for (int c = 0; c < 2; ++c) ASSERT_TRUE(v[c] >= 0.0f && v[c] <= 1.0f) << v[c];
}

// Probes the bake produced (builtin box room, res 32, radius 1 m so that most texels see some
// occlusion): the target is AO PSNR ≥ 40 dB on real probes. Traced AO carries Monte-Carlo
// noise (64 rays per texel), the hardest case for a 2-endpoint block. Measured: hsplit AO 43.9 dB,
// confidence 56.3 dB; traced AO 42.6 dB, confidence +inf (traced confidence is 1 everywhere).
TEST(BcBakedProbe, BoxRoomProbesMeetFortyDecibels) {
    constexpr int kRes = 32;
    const Scene scene = makeBuiltinScene("builtin:box-room");
    const EmbreeScene rt(scene);
    for (const Estimator estimator : {Estimator::HorizonSplit, Estimator::Traced}) {
        const BakeSettings s = test::bakeSettings(estimator, kRes, 1.0f, 64);
        const BakedProbe probe = bakeProbeCpu(rt, glm::vec3(3.0f, 1.4f, 2.5f), 0, s);
        Cube cube(probe.ao.size());
        for (std::size_t t = 0; t < cube.size(); ++t) cube[t] = {probe.ao[t], probe.confidence[t]};
        const Cube out = decodeCube(bc::encodeBc5Cube(cube, kRes), kRes);
        const double ao = channelPsnr(cube, out, 0), confidence = channelPsnr(cube, out, 1);
        const char* name = estimator == Estimator::Traced ? "traced" : "hsplit";
        std::printf("[ bc4 probe ] box room %s: AO %.2f dB, confidence %.2f dB\n", name, ao, confidence);
        EXPECT_GE(ao, 40.0) << name;
        EXPECT_GE(confidence, 40.0) << name;
    }
}

// ---- GPU encoder -------------------------------------------------------------------------------

class BcGl : public GlTest {};

gl::Buffer upload(const Cube& cube) {
    gl::Buffer buffer = gl::Buffer::create();
    glNamedBufferStorage(buffer.id(), GLsizeiptr(cube.size() * sizeof(glm::vec2)), cube.data(), 0);
    return buffer;
}

TEST_F(BcGl, GpuBlocksEqualCpuBlocksAndBeatLibsquish) {
    for (const int res : {8, 32}) {
        GpuBc5Encoder encoder(res);
        for (const TestImage& image : imagesAt(res)) {
            const gl::Buffer input = upload(image.cube);
            encoder.encode(input.id());
            const Bytes gpu = encoder.read(), cpu = bc::encodeBc5Cube(image.cube, res);
            ASSERT_EQ(glGetError(), static_cast<GLenum>(GL_NO_ERROR));
            ASSERT_EQ(gpu.size(), cpu.size());
            const auto mismatch = std::mismatch(gpu.begin(), gpu.end(), cpu.begin());
            EXPECT_TRUE(mismatch.first == gpu.end())
                << image.name << " res " << res << ": first difference in block " << (mismatch.first - gpu.begin()) / 16;
            if (res != 32) continue;
            const Cube decoded = decodeCube(gpu, res), squish = decodeCube(squishCube(image.cube, res), res);
            for (int c = 0; c < 2; ++c) {
                const double g = channelPsnr(image.cube, decoded, c), s = channelPsnr(image.cube, squish, c);
                std::printf("[ bc4 gpu ] %-9s %s: gpu %.2f dB, libsquish %.2f dB\n", image.name,
                            c == 0 ? "red  " : "green", g, s);
                EXPECT_GE(g, s - 0.5) << image.name << " channel " << c;
            }
        }
    }
}

TEST_F(BcGl, MesaDecodesOurLayoutLikeOurDecoder) {
    // Upload face f to layer f of a GL_COMPRESSED_RG_RGTC2 array texture and read it back through
    // Mesa's RGTC decoder. Random data: a wrong block order, row order or channel order moves values
    // by ~1/3 on average, far above the tolerance. Mesa (llvmpipe, 22.3) does not evaluate the spec's
    // formulas exactly: endpoints and the explicit 0 and 1 match, but interpolated levels come out of
    // 8-bit fixed-point arithmetic, measured up to 1.6/255 away from the exact (a·R0 + b·R1)/7 or /5.
    constexpr int kRes = 16;
    const Cube cube = imagesAt(kRes)[2].cube;
    const Bytes bytes = bc::encodeBc5Cube(cube, kRes);
    const Cube ours = decodeCube(bytes, kRes);

    const gl::Texture texture = gl::Texture::create(GL_TEXTURE_2D_ARRAY);
    glTextureStorage3D(texture.id(), 1, GL_COMPRESSED_RG_RGTC2, kRes, kRes, 6);
    const std::size_t faceBytes = bytes.size() / 6;
    for (int face = 0; face < 6; ++face)
        glCompressedTextureSubImage3D(texture.id(), 0, 0, 0, face, kRes, kRes, 1, GL_COMPRESSED_RG_RGTC2,
                                      GLsizei(faceBytes), bytes.data() + std::size_t(face) * faceBytes);
    Cube mesa(ours.size());
    glGetTextureImage(texture.id(), 0, GL_RG, GL_FLOAT, GLsizei(mesa.size() * sizeof(glm::vec2)), mesa.data());
    ASSERT_EQ(glGetError(), static_cast<GLenum>(GL_NO_ERROR));

    int exact = 0;
    float maxDiff = 0.0f;
    for (std::size_t t = 0; t < ours.size(); ++t)
        for (int c = 0; c < 2; ++c) {
            EXPECT_NEAR(mesa[t][c], ours[t][c], 2.0f / 255.0f) << "texel " << t << " channel " << c;
            exact += mesa[t][c] == ours[t][c];
            maxDiff = std::max(maxDiff, std::abs(mesa[t][c] - ours[t][c]));
        }
    std::printf("[ bc5 mesa ] %d of %zu values equal ours exactly, largest difference %.2f/255\n", exact,
                2 * ours.size(), maxDiff * 255.0f);
}

}  // namespace
}  // namespace cubeao
