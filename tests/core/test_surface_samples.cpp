// The one surface sampler (core/surface_samples.h) of the candidate grid and of placement.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "cubeao/core/surface_samples.h"

namespace {

using namespace cubeao;

// A 2 × 3 rectangle at z = 1 as two triangles, and a degenerate triangle that must get no sample.
const std::vector<glm::vec3> kPositions = {{0, 0, 1}, {2, 0, 1}, {2, 3, 1}, {0, 3, 1}, {5, 5, 5}};
const std::vector<std::uint32_t> kIndices = {0, 1, 2, 0, 2, 3, 4, 4, 4};

TEST(SurfaceSamples, BothSidesEvenlyOverTheAreaAndDeterministic) {
    const std::size_t count = surfacePointsFor(kPositions, kIndices, 0.1f, std::size_t(1) << 22);
    EXPECT_EQ(count, 600u) << "6 m² at one point per (0.1 m)² on each side";
    const std::vector<SurfaceSample> samples = sampleSurface(kPositions, kIndices, count, 7u);
    ASSERT_EQ(samples.size(), 2 * count);
    for (std::size_t i = 0; i < samples.size(); ++i) {
        const SurfaceSample& s = samples[i];
        EXPECT_NEAR(s.position.z, 1.0f, 1e-5f);
        EXPECT_GE(s.position.x, -1e-5f);
        EXPECT_LE(s.position.x, 2.0f + 1e-5f);
        EXPECT_GE(s.position.y, -1e-5f);
        EXPECT_LE(s.position.y, 3.0f + 1e-5f);
        EXPECT_NEAR(s.area, 0.01f, 1e-6f);
        EXPECT_LT(s.triangle, 2u) << "the degenerate triangle has no area";
        if (i % 2 == 1) {
            EXPECT_EQ(s.position, samples[i - 1].position) << "2i and 2i + 1 share a point";
            EXPECT_EQ(s.normal, -samples[i - 1].normal) << "and stand for its two sides";
        }
        EXPECT_NEAR(std::fabs(s.normal.z), 1.0f, 1e-6f);
    }
    // Stratified along the area: each 1 × 1 square of the rectangle holds about 100 points.
    for (int sx = 0; sx < 2; ++sx)
        for (int sy = 0; sy < 3; ++sy) {
            const auto n = std::count_if(samples.begin(), samples.end(), [&](const SurfaceSample& s) {
                return s.normal.z > 0.0f && int(s.position.x) == sx && int(s.position.y) == sy;
            });
            EXPECT_NEAR(double(n), 100.0, 30.0) << sx << "," << sy;
        }
    const std::vector<SurfaceSample> again = sampleSurface(kPositions, kIndices, count, 7u);
    ASSERT_EQ(again.size(), samples.size());
    for (std::size_t i = 0; i < samples.size(); ++i) EXPECT_EQ(again[i].position, samples[i].position);
    const std::vector<SurfaceSample> other = sampleSurface(kPositions, kIndices, count, 8u);
    EXPECT_NE(other[0].position, samples[0].position) << "another seed, other points";
}

TEST(SurfaceSamples, ACapWidensTheSpacingAndNoAreaGivesNone) {
    EXPECT_EQ(surfacePointsFor(kPositions, kIndices, 0.1f, 200), 100u) << "200 samples: 100 points, two sides each";
    EXPECT_EQ(surfacePointsFor(kPositions, kIndices, 1.0f, std::size_t(1) << 22), 6u);
    const std::vector<std::uint32_t> degenerate = {4, 4, 4};
    EXPECT_EQ(surfacePointsFor(kPositions, degenerate, 0.1f, 1000), 0u);
    EXPECT_TRUE(sampleSurface(kPositions, degenerate, 10, 1u).empty());
    EXPECT_TRUE(sampleSurface(kPositions, kIndices, 0, 1u).empty());
}

// A model whose faces point the other way is sampled at the same points, sides in the same order.
TEST(SurfaceSamples, TheSameWhicheverWayTheFacesAreWound) {
    std::vector<std::uint32_t> reversed = kIndices;
    for (std::size_t t = 0; t < reversed.size(); t += 3) std::swap(reversed[t + 1], reversed[t + 2]);
    const std::vector<SurfaceSample> a = sampleSurface(kPositions, kIndices, 50, 3u);
    const std::vector<SurfaceSample> b = sampleSurface(kPositions, reversed, 50, 3u);
    ASSERT_EQ(a.size(), b.size());
    for (std::size_t i = 0; i < a.size(); ++i) {
        EXPECT_EQ(a[i].position, b[i].position) << i;
        EXPECT_EQ(a[i].normal, b[i].normal) << i;
    }
}

}  // namespace
