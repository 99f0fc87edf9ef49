// Candidate probes per world cell (src/cubeao/runtime/probe_grid.h): probes that see a cell come
// first, nearest first; the per-point work stays K however many probes there are.
#include <gtest/gtest.h>

#include <vector>

#include <glm/geometric.hpp>

#include "cubeao/runtime/probe_grid.h"

namespace {

using namespace cubeao;

TEST(ProbeGrid, NearestVisibleProbesFirstAndAtMostK) {
    // Five probes on a line; a wall at x = 5.2 that probes on the far side cannot see through.
    const std::vector<glm::vec3> probes = {{0.5f, 1, 1}, {2.5f, 1, 1}, {4.5f, 1, 1}, {5.5f, 1, 1}, {9.5f, 1, 1}};
    const auto sees = [&](std::uint32_t p, const glm::vec3& x) { return (probes[p].x < 5.2f) == (x.x < 5.2f); };
    const ProbeGrid grid({0, 0, 0}, {10, 2, 2}, probes, sees, {3, 1.0f, 0});
    EXPECT_EQ(grid.dims(), glm::ivec3(10, 2, 2));
    const auto near4 = grid.candidates({4.2f, 1.2f, 1.2f});
    ASSERT_EQ(near4.size(), 3u);
    EXPECT_EQ(near4[0], 2u);  // nearest that sees
    EXPECT_EQ(near4[1], 1u);
    EXPECT_EQ(near4[2], 0u);  // probe 3 is nearer than 0 but behind the wall
    const auto far = grid.candidates({8.7f, 0.5f, 0.5f});
    ASSERT_EQ(far.size(), 3u);
    EXPECT_EQ(far[0], 4u);
    EXPECT_EQ(far[1], 3u);
    EXPECT_EQ(far[2], 2u);  // only two see it: the nearest other fills up
    // Outside the grid: clamped to the border cell.
    EXPECT_EQ(grid.candidates({-5.0f, 1.0f, 1.0f})[0], 0u);
}

TEST(ProbeGrid, WorkPerPointStaysKAndMemoryIsCapped) {
    std::vector<glm::vec3> probes;
    for (int i = 0; i < 1000; ++i) probes.push_back({float(i % 10) + 0.5f, float(i / 100) * 0.3f, float((i / 10) % 10) + 0.5f});
    const ProbeGrid grid({0, 0, 0}, {10, 3, 10}, probes, [](std::uint32_t, const glm::vec3&) { return true; },
                         {8, 0.05f, 4096});
    EXPECT_LE(std::size_t(grid.dims().x) * grid.dims().y * grid.dims().z, 4096u) << "cells grow to fit the cap";
    EXPECT_EQ(grid.candidates({5, 1, 5}).size(), 8u);
    EXPECT_EQ(grid.table().size(), std::size_t(grid.dims().x) * grid.dims().y * grid.dims().z * 8u);
}

}  // namespace
