// The distance cube's CPU side (depth_cube.h). The Min filter, the half conversion and the texel
// encoding are common/depth_encode.h's (shaders/common/depth_encode.h), the code that
// shaders/bake/depth_encode.comp compiles too. C++ only: the Nearest filter, decoding and the byte
// layout, which the GPU bake does not need (it bakes kFilter = Min, and a run time decodes in the
// texture unit); the GPU's largest-distance reduction is an atomicMax on the bits, the same value as
// maxDistance below because non-negative floats order like their bits.
#include "cubeao/cache/depth_cube.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <stdexcept>
#include <string>

#include "common/depth_encode.h"

namespace cubeao::depth {

static_assert(int(DepthFormat::R16Unorm) == kernel::kDepthR16Unorm && int(DepthFormat::R16Float) == kernel::kDepthR16Float &&
              int(DepthFormat::R32Float) == kernel::kDepthR32Float);

namespace {

constexpr int kFaces = 6;

void checkSizes(std::size_t fine, int res, int depthRes) {
    if (res < 1 || depthRes < 1 || depthRes > res)
        throw std::invalid_argument("depth::downsample: depthRes " + std::to_string(depthRes) +
                                    " is not in 1..res (" + std::to_string(res) + ")");
    if (fine != std::size_t(kFaces) * std::size_t(res) * std::size_t(res))
        throw std::invalid_argument("depth::downsample: " + std::to_string(fine) + " distances, res " +
                                    std::to_string(res) + " needs 6·res²");
}

float nonNegative(float d) { return d > 0.0f ? d : 0.0f; }  // NaN and negatives: empty

// Coarse texels in cubeTexelIndex order. kFromGbuffer: the fetch's flag as a constant (depth_encode.h).
template <bool kFromGbuffer>
std::vector<float> downsampleWith(const float* distances, const glm::vec4* gbuffer, int res, int depthRes, Filter filter) {
    const kernel::DepthDownsampleParams p{res, depthRes, distances, gbuffer, kFromGbuffer};
    std::vector<float> out(std::size_t(kFaces) * std::size_t(depthRes) * std::size_t(depthRes), 0.0f);
    std::size_t o = 0;
    if (filter == Filter::Min) {
        for (int f = 0; f < kFaces; ++f)
            for (int J = 0; J < depthRes; ++J)
                for (int I = 0; I < depthRes; ++I, ++o) out[o] = kernel::depthCoarseMin(p, glm::ivec3(I, J, f));
        return out;
    }
    // Filter::Nearest: C++ only, for `bench depth`'s comparison (the bake uses kFilter = Min).
    const auto centre = [res, depthRes](int c) { return int((2 * std::int64_t(c) + 1) * res / (2 * depthRes)); };
    for (int f = 0; f < kFaces; ++f)
        for (int J = 0; J < depthRes; ++J)
            for (int I = 0; I < depthRes; ++I, ++o)
                out[o] = nonNegative(kernel::depthFineDistance(p, glm::ivec3(centre(I), centre(J), f)));
    return out;
}

}  // namespace

const char* filterName(Filter f) { return f == Filter::Min ? "min" : "nearest"; }

int depthResFor(int res) { return std::max(1, res / kResDivisor); }

std::vector<float> downsample(std::span<const float> distances, int res, int depthRes, Filter filter) {
    checkSizes(distances.size(), res, depthRes);
    return downsampleWith<false>(distances.data(), nullptr, res, depthRes, filter);
}

std::vector<float> downsample(std::span<const glm::vec4> gbuffer, int res, int depthRes, Filter filter) {
    checkSizes(gbuffer.size(), res, depthRes);
    return downsampleWith<true>(nullptr, gbuffer.data(), res, depthRes, filter);
}

float maxDistance(std::span<const float> coarse) {
    float m = 0.0f;
    for (const float d : coarse) m = std::max(m, nonNegative(d));
    return m;
}

std::uint16_t floatToHalf(float f) { return std::uint16_t(kernel::depthFloatToHalf(f)); }

float halfToFloat(std::uint16_t h) {
    const std::uint32_t sign = std::uint32_t(h & 0x8000u) << 16, exponent = (h >> 10) & 0x1Fu, mantissa = h & 0x3FFu;
    float v;
    if (exponent == 0) v = float(mantissa) / 16777216.0f;  // subnormal: mantissa · 2^-24
    else if (exponent == 31) v = mantissa ? std::nanf("") : INFINITY;
    else v = std::bit_cast<float>(((exponent + 112u) << 23) | (mantissa << 13));
    return std::bit_cast<float>(std::bit_cast<std::uint32_t>(v) | sign);
}

std::uint32_t encodeTexel(float distance, DepthFormat format, float maxDistance) {
    return kernel::depthEncodeTexel(distance, int(format), maxDistance);
}

float decodeTexel(std::uint32_t stored, DepthFormat format, float maxDistance) {
    switch (format) {
        case DepthFormat::R16Unorm: return float(stored & 0xFFFFu) / 65535.0f * maxDistance;
        case DepthFormat::R16Float: return halfToFloat(std::uint16_t(stored));
        case DepthFormat::R32Float: return std::bit_cast<float>(stored);
    }
    return 0.0f;
}

std::vector<std::uint8_t> encode(std::span<const float> coarse, DepthFormat format, float maxDistance) {
    const std::size_t bytes = depthBytesPerTexel(format);
    if (bytes == 0) throw std::invalid_argument("depth::encode: unknown depth format");
    std::vector<std::uint8_t> out(coarse.size() * bytes);
    for (std::size_t t = 0; t < coarse.size(); ++t) {
        const std::uint32_t v = encodeTexel(coarse[t], format, maxDistance);
        for (std::size_t b = 0; b < bytes; ++b) out[t * bytes + b] = std::uint8_t(v >> (8 * b));
    }
    return out;
}

bool decode(std::span<const std::uint8_t> bytes, int depthRes, DepthFormat format, float maxDistance,
            std::vector<float>& out) {
    const std::size_t per = depthBytesPerTexel(format);
    if (per == 0 || depthRes < 1) return false;
    const std::size_t texels = std::size_t(kFaces) * std::size_t(depthRes) * std::size_t(depthRes);
    if (bytes.size() != texels * per) return false;
    out.resize(texels);
    for (std::size_t t = 0; t < texels; ++t) {
        std::uint32_t v = 0;
        for (std::size_t b = 0; b < per; ++b) v |= std::uint32_t(bytes[t * per + b]) << (8 * b);
        out[t] = decodeTexel(v, format, maxDistance);
    }
    return true;
}

}  // namespace cubeao::depth
