#include "cubeao/cache/depth_cube.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <stdexcept>
#include <string>

namespace cubeao::depth {
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

// distanceAt(fine texel index) → distance; the layout arithmetic of downsample in one place.
template <class DistanceAt>
std::vector<float> downsampleWith(DistanceAt distanceAt, int res, int depthRes, Filter filter) {
    std::vector<float> out(std::size_t(kFaces) * std::size_t(depthRes) * std::size_t(depthRes), 0.0f);
    const auto lo = [res, depthRes](int c) { return int(std::int64_t(c) * res / depthRes); };
    const auto centre = [res, depthRes](int c) { return int((2 * std::int64_t(c) + 1) * res / (2 * depthRes)); };
    std::size_t o = 0;
    for (int f = 0; f < kFaces; ++f)
        for (int J = 0; J < depthRes; ++J)
            for (int I = 0; I < depthRes; ++I, ++o) {
                const auto fine = [&](int i, int j) {
                    return distanceAt((std::size_t(f) * std::size_t(res) + std::size_t(j)) * std::size_t(res) +
                                      std::size_t(i));
                };
                if (filter == Filter::Nearest) {
                    out[o] = fine(centre(I), centre(J));
                    continue;
                }
                float m = 0.0f;
                for (int j = lo(J); j < lo(J + 1); ++j)
                    for (int i = lo(I); i < lo(I + 1); ++i)
                        if (const float d = fine(i, j); d > 0.0f && (m == 0.0f || d < m)) m = d;
                out[o] = m;
            }
    return out;
}

float nonNegative(float d) { return d > 0.0f ? d : 0.0f; }  // NaN and negatives: empty

}  // namespace

const char* filterName(Filter f) { return f == Filter::Min ? "min" : "nearest"; }

int depthResFor(int res) { return std::max(1, res / kResDivisor); }

std::vector<float> downsample(std::span<const float> distances, int res, int depthRes, Filter filter) {
    checkSizes(distances.size(), res, depthRes);
    return downsampleWith([&](std::size_t t) { return nonNegative(distances[t]); }, res, depthRes, filter);
}

std::vector<float> downsample(std::span<const glm::vec4> gbuffer, int res, int depthRes, Filter filter) {
    checkSizes(gbuffer.size(), res, depthRes);
    return downsampleWith([&](std::size_t t) { return nonNegative(gbuffer[t].w); }, res, depthRes, filter);
}

float maxDistance(std::span<const float> coarse) {
    float m = 0.0f;
    for (const float d : coarse) m = std::max(m, nonNegative(d));
    return m;
}

// Rounding as in F. Giesen's float_to_half_fast3_rtne, with the subnormal range done as an exact
// power-of-two scale and roundEven instead of a float addition, so GLSL can repeat it bit for bit.
std::uint16_t floatToHalf(float f) {
    std::uint32_t u = std::bit_cast<std::uint32_t>(f);
    const std::uint32_t sign = (u >> 16) & 0x8000u;
    u &= 0x7FFFFFFFu;
    if (u > 0x7F800000u) return std::uint16_t(sign | 0x7E00u);              // NaN
    if (u >= 0x47800000u) return std::uint16_t(sign | 0x7C00u);             // ≥ 65536: inf
    if (u < 0x38800000u)                                                     // < 2^-14: subnormal half
        return std::uint16_t(sign | std::uint32_t(std::nearbyint(std::bit_cast<float>(u) * 16777216.0f)));
    const std::uint32_t odd = (u >> 13) & 1u;
    return std::uint16_t(sign | ((u + 0xC8000FFFu + odd) >> 13));  // rebias 127 → 15, round to even
}

float halfToFloat(std::uint16_t h) {
    const std::uint32_t sign = std::uint32_t(h & 0x8000u) << 16, exponent = (h >> 10) & 0x1Fu, mantissa = h & 0x3FFu;
    float v;
    if (exponent == 0) v = float(mantissa) / 16777216.0f;  // subnormal: mantissa · 2^-24
    else if (exponent == 31) v = mantissa ? std::nanf("") : INFINITY;
    else v = std::bit_cast<float>(((exponent + 112u) << 23) | (mantissa << 13));
    return std::bit_cast<float>(std::bit_cast<std::uint32_t>(v) | sign);
}

std::uint32_t encodeTexel(float distance, DepthFormat format, float maxDistance) {
    const float d = nonNegative(distance);
    switch (format) {
        case DepthFormat::R16Unorm: {
            if (d == 0.0f || !(maxDistance > 0.0f)) return 0;
            const float v = std::nearbyint(std::min(d / maxDistance, 1.0f) * 65535.0f);
            return std::uint32_t(std::max(v, 1.0f));
        }
        case DepthFormat::R16Float: {
            if (d == 0.0f) return 0;
            return std::clamp<std::uint32_t>(floatToHalf(d), 1u, 0x7BFFu);  // > 0, finite
        }
        case DepthFormat::R32Float: return std::bit_cast<std::uint32_t>(d);
    }
    return 0;
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
