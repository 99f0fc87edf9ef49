// The distance cube (src/cubeao/cache/depth_cube.h): half conversion against IEEE values, the
// downsampling rules, the encoding's clamps, the run-time depth test on analytic cases, and the GPU
// encoder (shaders/bake/depth_encode.comp) against the CPU one, texel for texel.
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include <glm/vec4.hpp>

#include "cubeao/bake/gpu_depth.h"
#include "cubeao/cache/depth_cube.h"
#include "gl_fixture.h"

namespace cubeao {
namespace {

TEST(DepthCube, HalfConversionRoundsToNearestEven) {
    EXPECT_EQ(depth::floatToHalf(1.0f), 0x3C00u);
    EXPECT_EQ(depth::floatToHalf(-2.0f), 0xC000u);
    EXPECT_EQ(depth::floatToHalf(65504.0f), 0x7BFFu);                        // largest finite
    EXPECT_EQ(depth::floatToHalf(65519.99f), 0x7BFFu);                       // still rounds down
    EXPECT_EQ(depth::floatToHalf(65520.0f), 0x7C00u);                        // tie → even → inf
    EXPECT_EQ(depth::floatToHalf(INFINITY), 0x7C00u);
    EXPECT_EQ(depth::floatToHalf(std::nanf("")), 0x7E00u);
    EXPECT_EQ(depth::floatToHalf(1.0f + 1.0f / 2048.0f), 0x3C00u);           // tie → even (down)
    EXPECT_EQ(depth::floatToHalf(1.0f + 3.0f / 2048.0f), 0x3C02u);           // tie → even (up)
    EXPECT_EQ(depth::floatToHalf(std::ldexp(1.0f, -24)), 0x0001u);           // smallest subnormal
    EXPECT_EQ(depth::floatToHalf(std::ldexp(1.0f, -25)), 0x0000u);           // tie → even (0)
    EXPECT_EQ(depth::floatToHalf(std::ldexp(3.0f, -25)), 0x0002u);           // tie → even (2)
    EXPECT_EQ(depth::floatToHalf(std::ldexp(1023.5f, -24)), 0x0400u);        // rounds into the normals
    // Every finite half survives the round trip; in between, the nearer neighbour wins.
    for (std::uint32_t h = 0; h < 0x10000u; ++h) {
        if ((h & 0x7C00u) == 0x7C00u) continue;
        const float f = depth::halfToFloat(std::uint16_t(h));
        ASSERT_EQ(depth::floatToHalf(f), h) << h;
        if ((h & 0x7FFFu) < 0x7BFFu && (h & 0x8000u) == 0) {
            const float next = depth::halfToFloat(std::uint16_t(h + 1));
            const float below = std::nextafter(0.5f * (f + next), 0.0f), above = std::nextafter(0.5f * (f + next), INFINITY);
            ASSERT_EQ(depth::floatToHalf(below), h) << h;
            ASSERT_EQ(depth::floatToHalf(above), h + 1) << h;
        }
    }
}

TEST(DepthCube, MinAndNearestDownsampling) {
    // res 6 → depthRes 4: coarse texel I covers fine [⌊6I/4⌋, ⌊6(I+1)/4⌋) = [0,1) [1,3) [3,4) [4,6).
    const int res = 6, depthRes = 4;
    std::vector<float> fine(6 * res * res);
    for (std::size_t t = 0; t < fine.size(); ++t) fine[t] = 1.0f + float(t);  // distinct, increasing
    fine[res * 1 + 1] = 0.0f;  // face 0, (1, 1): empty, ignored by min
    const auto at = [&](int f, int i, int j) { return fine[std::size_t((f * res + j) * res + i)]; };
    const std::vector<float> m = depth::downsample(fine, res, depthRes, depth::Filter::Min);
    const std::vector<float> n = depth::downsample(fine, res, depthRes, depth::Filter::Nearest);
    ASSERT_EQ(m.size(), 6u * depthRes * depthRes);
    EXPECT_EQ(m[0], at(0, 0, 0));
    EXPECT_EQ(m[1], at(0, 1, 0)) << "covers i 1..2, j 0";
    EXPECT_EQ(m[1 * depthRes + 1], at(0, 2, 1)) << "covers (1..2, 1..2); (1,1) is empty";
    EXPECT_EQ(n[1 * depthRes + 1], at(0, 2, 2)) << "nearest: fine ⌊(2I+1)·6/8⌋ = 2";
    EXPECT_EQ(n[3 * depthRes + 3], at(0, 5, 5));
    EXPECT_EQ(m[5 * depthRes * depthRes], at(5, 0, 0));

    std::vector<glm::vec4> gbuffer(fine.size());
    for (std::size_t t = 0; t < fine.size(); ++t) gbuffer[t] = glm::vec4(0.0f, 0.0f, 1.0f, fine[t]);
    EXPECT_EQ(depth::downsample(gbuffer, res, depthRes, depth::Filter::Min), m);
    std::vector<float> empty(fine.size(), 0.0f);
    EXPECT_EQ(depth::maxDistance(depth::downsample(empty, res, 1, depth::Filter::Min)), 0.0f);
    EXPECT_THROW(depth::downsample(fine, res, res + 1, depth::Filter::Min), std::invalid_argument);
    EXPECT_THROW(depth::downsample(std::vector<float>(5), res, 2, depth::Filter::Min), std::invalid_argument);
}

TEST(DepthCube, EncodingKeepsEmptyAndNonEmptyApart) {
    EXPECT_EQ(depth::encodeTexel(0.0f, DepthFormat::R16Unorm, 10.0f), 0u);
    EXPECT_EQ(depth::encodeTexel(1e-9f, DepthFormat::R16Unorm, 10.0f), 1u);  // never empty
    EXPECT_EQ(depth::encodeTexel(10.0f, DepthFormat::R16Unorm, 10.0f), 65535u);
    EXPECT_EQ(depth::encodeTexel(5.0f, DepthFormat::R16Unorm, 10.0f), 32768u);  // 32767.5 → even
    EXPECT_EQ(depth::encodeTexel(1e-30f, DepthFormat::R16Float, 0.0f), 1u);
    EXPECT_EQ(depth::encodeTexel(1e6f, DepthFormat::R16Float, 0.0f), 0x7BFFu);  // clamped, not inf
    EXPECT_EQ(depth::encodeTexel(-1.0f, DepthFormat::R32Float, 0.0f), 0u);
    EXPECT_NEAR(depth::decodeTexel(32768u, DepthFormat::R16Unorm, 10.0f), 5.0f, 1e-4f);

    const std::vector<float> coarse{0.0f, 1.5f, 2.25f, 7.0f, 3.0f, 0.5f};  // depthRes 1
    for (const DepthFormat f : {DepthFormat::R16Unorm, DepthFormat::R16Float, DepthFormat::R32Float}) {
        const float maxD = depth::maxDistance(coarse);
        const std::vector<std::uint8_t> bytes = depth::encode(coarse, f, maxD);
        EXPECT_EQ(bytes.size(), 6u * depthBytesPerTexel(f));
        std::vector<float> back;
        ASSERT_TRUE(depth::decode(bytes, 1, f, maxD, back));
        for (std::size_t t = 0; t < coarse.size(); ++t) EXPECT_NEAR(back[t], coarse[t], 1e-3f * coarse[t]) << t;
        EXPECT_FALSE(depth::decode({bytes.data(), bytes.size() - 1}, 1, f, maxD, back));
    }
    EXPECT_EQ(depth::depthResFor(512), 128);
    EXPECT_EQ(depth::depthResFor(4), 1);
}

TEST(DepthCube, RunTimeTestOnAnalyticCases) {
    const depth::DepthTest plain{0.01f, 0.0f, false}, slope{0.0f, 1.0f, false}, facing{0.01f, 0.0f, true};
    EXPECT_TRUE(depth::visible(plain, 10.0f, 10.09f, 1.0f, 128));
    EXPECT_FALSE(depth::visible(plain, 10.0f, 10.11f, 1.0f, 128));
    EXPECT_TRUE(depth::visible(plain, 0.0f, 1e6f, 1.0f, 128)) << "an empty texel hides nothing";
    // Slope term: w = 2/128, at 60° tan θ = √3: slack 10 · w · √3 ≈ 0.2706.
    const float c60 = 0.5f, slack = 10.0f * (2.0f / 128.0f) * std::sqrt(3.0f);
    EXPECT_TRUE(depth::visible(slope, 10.0f, 10.0f + 0.99f * slack, c60, 128));
    EXPECT_FALSE(depth::visible(slope, 10.0f, 10.0f + 1.01f * slack, c60, 128));
    EXPECT_FALSE(depth::visible(slope, 10.0f, 10.0f + 1e-3f, 1.0f, 128)) << "head-on: no slope slack";
    // Grazing: tan θ capped at kMaxTan.
    const float capped = 10.0f * (2.0f / 128.0f) * depth::kMaxTan;
    EXPECT_TRUE(depth::visible(slope, 10.0f, 10.0f + 0.99f * capped, 1e-4f, 128));
    EXPECT_FALSE(depth::visible(slope, 10.0f, 10.0f + 1.01f * capped, 1e-4f, 128));
    // Facing: the seen side turned away from the probe is hidden, whatever the cube says.
    EXPECT_FALSE(depth::visible(facing, 10.0f, 10.0f, -0.2f, 128));
    EXPECT_FALSE(depth::visible(facing, 0.0f, 10.0f, -0.2f, 128));
    EXPECT_TRUE(depth::visible(facing, 10.0f, 10.0f, 0.2f, 128));
    // The second half: the point lifted by 0.5 texel widths (w = 2/128) at distance 10 along its
    // normal. Beyond the relative tolerance, within the slope bias, the lifted point must be within
    // the relative tolerance of the texel in its direction (an empty one hides nothing); within the
    // tolerance no lift is asked; no lift (offset 0), no second half.
    const depth::DepthTest lifted{0.01f, 1.0f, true, 0.5f};
    const glm::vec3 point = depth::liftedPoint(lifted, {0, 0, 0}, {0, 0, -10}, {0, 1, 0}, 128);
    EXPECT_NEAR(point.y, 0.5f * (2.0f / 128.0f) * 10.0f, 1e-6f);
    EXPECT_EQ(point.z, -10.0f);
    const float slanted = 10.0f + 0.5f * slack;  // within the slope bias at 60°
    EXPECT_TRUE(depth::visible(lifted, 10.0f, slanted, c60, 128, {10.0f, 10.09f}));
    EXPECT_FALSE(depth::visible(lifted, 10.0f, slanted, c60, 128, {10.0f, 10.11f})) << "the lifted point is behind";
    EXPECT_TRUE(depth::visible(lifted, 10.0f, slanted, c60, 128, {0.0f, 10.11f})) << "nothing in front of it";
    EXPECT_TRUE(depth::visible(lifted, 10.0f, 10.09f, c60, 128, {10.0f, 1e6f})) << "within the tolerance: no lift";
    EXPECT_TRUE(depth::visible({0.01f, 1.0f, true, 0.0f}, 10.0f, slanted, c60, 128, {10.0f, 1e6f})) << "no lift";
    EXPECT_FALSE(depth::visible(lifted, 10.0f, 10.1f + 1.01f * slack, c60, 128, {10.0f, 10.0f})) << "beyond the bias";
}

// ---- GPU encoder ---------------------------------------------------------------------------------

class DepthCubeGl : public GlTest {};

TEST_F(DepthCubeGl, GpuBytesEqualCpuBytes) {
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> distance(0.05f, 40.0f), unit(0.0f, 1.0f);
    for (const int res : {8, 12, 32}) {
        std::vector<glm::vec4> gbuffer(std::size_t(6 * res * res));
        for (glm::vec4& t : gbuffer) {
            const float u = unit(rng);
            // Empty texels, ordinary distances, distances in the half's subnormal range and beyond 65504.
            const float d = u < 0.1f ? 0.0f : u < 0.12f ? 3e-6f * unit(rng) : u < 0.13f ? 7e4f : distance(rng);
            t = glm::vec4(0.0f, 1.0f, 0.0f, d);
        }
        gbuffer[5].w = 0.0f;
        const gl::Texture texture = gl::Texture::create(GL_TEXTURE_2D_ARRAY);
        glTextureStorage3D(texture.id(), 1, GL_RGBA32F, res, res, 6);
        glTextureSubImage3D(texture.id(), 0, 0, 0, 0, res, res, 6, GL_RGBA, GL_FLOAT, gbuffer.data());
        for (const int depthRes : {res / 4, res / 3, 1, res})
            for (const DepthFormat f : {DepthFormat::R16Unorm, DepthFormat::R16Float, DepthFormat::R32Float}) {
                SCOPED_TRACE("res " + std::to_string(res) + " depthRes " + std::to_string(depthRes) + " " +
                             depthFormatName(f));
                GpuDepthEncoder encoder(res, depthRes, f);
                encoder.encode(texture.id());
                const EncodedDepth gpu = encoder.read();
                ASSERT_EQ(glGetError(), static_cast<GLenum>(GL_NO_ERROR));
                const std::vector<float> coarse = depth::downsample(gbuffer, res, depthRes, depth::kFilter);
                const float maxD = depth::maxDistance(coarse);
                EXPECT_EQ(gpu.maxDistance, maxD);
                const std::vector<std::uint8_t> cpu = depth::encode(coarse, f, maxD);
                ASSERT_EQ(gpu.bytes.size(), cpu.size());
                const std::size_t per = depthBytesPerTexel(f);
                for (std::size_t t = 0; t < cpu.size() / per; ++t) {
                    std::int64_t a = 0, b = 0;
                    for (std::size_t k = 0; k < per; ++k) {
                        a |= std::int64_t(gpu.bytes[t * per + k]) << (8 * k);
                        b |= std::int64_t(cpu[t * per + k]) << (8 * k);
                    }
                    // r16unorm: GLSL's division may differ from C++'s in the last bit: one code.
                    EXPECT_LE(std::abs(a - b), f == DepthFormat::R16Unorm ? 1 : 0) << "texel " << t;
                }
            }
    }
}

}  // namespace
}  // namespace cubeao
