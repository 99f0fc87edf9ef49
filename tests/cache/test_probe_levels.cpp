// A probe's levels of detail (src/cubeao/cache/probe_levels.h): each level made from the
// full-resolution data. AO: the mean of the surface texels a coarse texel covers (sky does not
// brighten a silhouette); distances: the nearest surface, the same codes the cube's Min filter gives
// from the full-resolution distances at that level's size, in every depth format.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include <glm/vec2.hpp>

#include "cubeao/cache/bc4.h"
#include "cubeao/cache/depth_cube.h"
#include "cubeao/cache/probe_levels.h"
#include "cubeao/core/cube.h"
#include "cubeao/core/error.h"
#include "test_util.h"

namespace cubeao {
namespace {

using test::contains;
using test::errorMessage;

TEST(ProbeLevels, CoarseAoIsTheMeanOfTheSurfaceTexelsItCovers) {
    const int res = 16, levels = 3;  // 16², 8², 4²
    const std::size_t texels = 6 * res * res;
    std::vector<glm::vec2> aoConfidence(texels);
    std::vector<float> distances(texels);
    for (int f = 0; f < 6; ++f)
        for (int j = 0; j < res; ++j)
            for (int i = 0; i < res; ++i) {
                const std::size_t t = cube::texelIndex(f, i, j, res);
                // Left half of every face: a surface whose AO rises along x and whose confidence is 0.5;
                // the right half: sky (AO 1, confidence 1, no distance).
                const bool surface = i < res / 2;
                aoConfidence[t] = surface ? glm::vec2(0.1f + 0.02f * float(i), 0.5f) : glm::vec2(1.0f, 1.0f);
                distances[t] = surface ? 3.0f : 0.0f;
            }
    const std::vector<std::uint8_t> chain = levels::coarserAo(aoConfidence, distances, res, levels);
    ASSERT_EQ(chain.size(), bc::bc5Size(8) + bc::bc5Size(4));
    std::vector<glm::vec2> level1, level2;
    ASSERT_TRUE(bc::decodeBc5Cube(chain.data(), bc::bc5Size(8), 8, level1));
    ASSERT_TRUE(bc::decodeBc5Cube(chain.data() + bc::bc5Size(8), bc::bc5Size(4), 4, level2));
    // BC4's error: a block's range / 14 (8 codes between its endpoints) and the endpoints' 8 bits. Level 1's
    // blocks span 0.12 (surface) or nothing (sky); level 2's one block per face spans 0.13..1.
    constexpr float kBc = 0.12f / 14.0f + 1.0f / 255.0f, kBcWide = 0.87f / 14.0f + 1.0f / 255.0f;
    for (int f = 0; f < 6; ++f)
        for (int j = 0; j < 8; ++j)
            for (int i = 0; i < 8; ++i) {
                const glm::vec2 v = level1[cube::texelIndex(f, i, j, 8)];
                const float expected = i < 4 ? 0.1f + 0.02f * (2.0f * float(i) + 0.5f) : 1.0f;
                EXPECT_NEAR(v.x, expected, kBc) << f << " " << i << " " << j;
                EXPECT_NEAR(v.y, i < 4 ? 0.5f : 1.0f, kBc);
            }
    // Level 2's texel (1, j) covers x 4..7 only (surface); texel 2 covers x 8..11 (sky).
    EXPECT_NEAR(level2[cube::texelIndex(0, 1, 0, 4)].x, 0.1f + 0.02f * 5.5f, kBcWide);
    EXPECT_NEAR(level2[cube::texelIndex(0, 2, 0, 4)].x, 1.0f, kBcWide);

    // A texel half sky, half surface takes the surface's AO, not their mean.
    for (int j = 0; j < res; ++j) distances[cube::texelIndex(0, 7, j, res)] = 0.0f;  // x = 7: sky now
    const std::vector<std::uint8_t> edge = levels::coarserAo(aoConfidence, distances, res, 2);
    ASSERT_TRUE(bc::decodeBc5Cube(edge.data(), edge.size(), 8, level1));
    EXPECT_NEAR(level1[cube::texelIndex(0, 3, 0, 8)].x, 0.1f + 0.02f * 6.0f, kBc) << "x = 6 alone";

    EXPECT_TRUE(levels::coarserAo(aoConfidence, distances, res, 1).empty());
    EXPECT_TRUE(contains(errorMessage([&] { levels::coarserAo(aoConfidence, distances, res, 4); }),
                         "AO face of 16 texels a side does not halve into 4 levels"));
}

TEST(ProbeLevels, CoarseDistancesAreTheMinFilterOfTheFullResolutionOnesInEveryFormat) {
    const int res = 32, depthRes = 8, levels = 4;  // distances 8², 4², 2², 1²
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> d(0.5f, 40.0f);
    std::vector<float> fine(6 * res * res);
    for (float& x : fine) x = rng() % 5 == 0 ? 0.0f : d(rng);  // a fifth empty
    for (int j = 0; j < res; ++j)
        for (int i = 0; i < res; ++i) fine[cube::texelIndex(2, i, j, res)] = 0.0f;  // one face sees nothing
    for (const DepthFormat format : {DepthFormat::R16Unorm, DepthFormat::R16Float, DepthFormat::R32Float}) {
        const std::vector<float> level0 = depth::downsample(fine, res, depthRes, depth::Filter::Min);
        const float scale = depth::maxDistance(level0);
        const std::vector<std::uint8_t> chain =
            levels::coarserDistances(depth::encode(level0, format, scale), depthRes, format, levels);
        std::size_t at = 0;
        for (int k = 1; k < levels; ++k) {
            // What a bake would store at depthRes >> k, from the full-resolution distances.
            const std::vector<std::uint8_t> expected =
                depth::encode(depth::downsample(fine, res, depthRes >> k, depth::Filter::Min), format, scale);
            ASSERT_LE(at + expected.size(), chain.size());
            EXPECT_EQ(std::vector<std::uint8_t>(chain.begin() + long(at), chain.begin() + long(at + expected.size())),
                      expected)
                << depthFormatName(format) << " level " << k;
            at += expected.size();
        }
        EXPECT_EQ(at, chain.size());
    }
    EXPECT_TRUE(contains(errorMessage([&] { levels::coarserDistances(std::vector<std::uint8_t>(10), depthRes,
                                                                      DepthFormat::R16Unorm, 2); }),
                         "10 distance bytes are not a r16unorm cube of 8² faces"));
}

}  // namespace
}  // namespace cubeao
