#include "cubeao/cache/probe_levels.h"

#include <algorithm>
#include <cstring>
#include <string>

#include "cubeao/cache/bc4.h"
#include "cubeao/core/cube.h"
#include "cubeao/core/error.h"

namespace cubeao::levels {
namespace {

constexpr int kFaces = 6;

void checkHalving(int size, int divisor, int levels, const char* what) {
    if (levels > int(kMaxCacheLevels) || (levels > 1 && (size <= 0 || size % (divisor << (levels - 1)) != 0)))
        throw Error(std::string(what) + " of " + std::to_string(size) + " texels a side does not halve into " +
                    std::to_string(levels) + " levels");
}

}  // namespace

std::vector<std::uint8_t> coarserAo(std::span<const glm::vec2> aoConfidence, std::span<const float> distances, int res,
                                    int levels) {
    if (levels <= 1) return {};
    checkHalving(res, 4, levels, "AO face");
    const std::size_t texels = std::size_t(kFaces) * std::size_t(res) * std::size_t(res);
    if (aoConfidence.size() != texels || distances.size() != texels)
        throw Error("probe levels: " + std::to_string(aoConfidence.size()) + " AO and " +
                    std::to_string(distances.size()) + " distance texels for a cube of " + std::to_string(texels));
    std::vector<std::uint8_t> out;
    for (int k = 1; k < levels; ++k) {
        const int side = res >> k, span = 1 << k;
        std::vector<glm::vec2> level(std::size_t(kFaces) * std::size_t(side) * std::size_t(side));
        for (int f = 0; f < kFaces; ++f)
            for (int j = 0; j < side; ++j)
                for (int i = 0; i < side; ++i) {
                    glm::vec2 surface(0.0f), all(0.0f);
                    int surfaceCount = 0;
                    for (int y = j * span; y < (j + 1) * span; ++y)
                        for (int x = i * span; x < (i + 1) * span; ++x) {
                            const std::size_t t = cube::texelIndex(f, x, y, res);
                            all += aoConfidence[t];
                            if (distances[t] > 0.0f) surface += aoConfidence[t], ++surfaceCount;
                        }
                    level[cube::texelIndex(f, i, j, side)] =
                        surfaceCount > 0 ? surface / float(surfaceCount) : all / float(span * span);
                }
        const std::vector<std::uint8_t> blocks = bc::encodeBc5Cube(level, side);
        out.insert(out.end(), blocks.begin(), blocks.end());
    }
    return out;
}

std::vector<std::uint8_t> coarserDistances(std::span<const std::uint8_t> level0, int depthRes, DepthFormat format,
                                           int levels) {
    if (levels <= 1) return {};
    checkHalving(depthRes, 1, levels, "distance face");
    const std::size_t bytes = depthBytesPerTexel(format);
    if (bytes == 0 || level0.size() != std::size_t(kFaces) * std::size_t(depthRes) * std::size_t(depthRes) * bytes)
        throw Error("probe levels: " + std::to_string(level0.size()) + " distance bytes are not a " +
                    depthFormatName(format) + " cube of " + std::to_string(depthRes) + "² faces");
    const auto code = [bytes](const std::uint8_t* p) {
        std::uint32_t v = 0;
        for (std::size_t b = 0; b < bytes; ++b) v |= std::uint32_t(p[b]) << (8 * b);  // little-endian
        return v;
    };
    std::vector<std::uint8_t> out;
    std::vector<std::uint8_t> above(level0.begin(), level0.end());
    for (int k = 1, side = depthRes / 2; k < levels; ++k, side /= 2) {
        const int fine = side * 2;
        std::vector<std::uint8_t> level(std::size_t(kFaces) * std::size_t(side) * std::size_t(side) * bytes);
        for (int f = 0; f < kFaces; ++f)
            for (int j = 0; j < side; ++j)
                for (int i = 0; i < side; ++i) {
                    // Non-negative distances: a format's codes order as the distances do (r16unorm,
                    // and the bits of positive halves and floats); 0 is empty.
                    std::uint32_t nearest = 0;
                    for (int y = 2 * j; y < 2 * j + 2; ++y)
                        for (int x = 2 * i; x < 2 * i + 2; ++x) {
                            const std::size_t t = cube::texelIndex(f, x, y, fine);
                            const std::uint32_t c = code(&above[t * bytes]);
                            if (c != 0 && (nearest == 0 || c < nearest)) nearest = c;
                        }
                    const std::size_t t = cube::texelIndex(f, i, j, side);
                    for (std::size_t b = 0; b < bytes; ++b) level[t * bytes + b] = std::uint8_t(nearest >> (8 * b));
                }
        out.insert(out.end(), level.begin(), level.end());
        above = std::move(level);
    }
    return out;
}

}  // namespace cubeao::levels
