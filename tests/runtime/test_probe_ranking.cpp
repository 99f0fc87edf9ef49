// Which probes a frame wants resident, best first (runtime/probe_ranking.h), on the CPU: the pixels'
// demand before place, what the camera sees before what is behind it, where it is heading before
// where it comes from, and everything nearest first when the pool holds every probe.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <memory>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "cubeao/runtime/probe_ranking.h"

namespace {

using namespace cubeao;

// A 8 × 2 × 8 m room of 1 m cells, K = 2; every probe sees every point, nearer better.
ProbeGrid roomGrid(const std::vector<glm::vec3>& probes) {
    std::vector<SurfaceSample> points;
    for (int x = 0; x < 16; ++x)
        for (int z = 0; z < 16; ++z) points.push_back({{0.25f + 0.5f * float(x), 0.0f, 0.25f + 0.5f * float(z)}, {0, 1, 0}});
    auto positions = std::make_shared<std::vector<glm::vec3>>(probes);
    return ProbeGrid({0, 0, 0}, {8, 2, 8}, ProbeSet(probes), points,
                     [positions](std::uint32_t p, const SurfaceSample& x) {
                         const float d = glm::length((*positions)[p] - x.position);
                         return 1.0 / (1.0 + double(d) * d);
                     },
                     ProbeGridSettings{2, 1.0f, 0, 8, 16});
}

CameraView looking(const glm::vec3& eye, const glm::vec3& direction) {
    CameraView view;
    view.viewFromWorld = glm::lookAt(eye, eye + direction, glm::vec3(0, 1, 0));
    view.width = 160, view.height = 90;
    return view;
}

ResidencyPlanner pool(std::size_t slots, std::size_t probes, std::vector<std::uint32_t> demand = {}) {
    ResidencyPlanner planner(slots, 1, 1);
    planner.resizeProbes(probes);
    demand.resize(probes, 0u);
    planner.feedback(demand, 0);
    return planner;
}

// The ids as numbers, for comparing with lists written out.
std::vector<std::uint32_t> raw(const std::vector<ProbeId>& ids) {
    std::vector<std::uint32_t> out;
    for (const ProbeId id : ids) out.push_back(index(id));
    return out;
}

std::ptrdiff_t rankOf(const std::vector<std::uint32_t>& list, std::uint32_t id) {
    const auto it = std::find(list.begin(), list.end(), id);
    return it == list.end() ? -1 : it - list.begin();
}

// Beside the two probes a test looks at (ids 0, 1): two a metre either side of `eye` along z, which the
// cells around the eye list first (cells that near rank alike in view or not: a turn of the head), and
// four in the far corners, so that there are more probes than slots.
std::vector<glm::vec3> scene(const glm::vec3& a, const glm::vec3& b, const glm::vec3& eye) {
    return {a, b, eye - glm::vec3(0, 0, 1), eye + glm::vec3(0, 0, 1), {0.5f, 1, 0.5f}, {7.5f, 1, 0.5f}, {0.5f, 1, 7.5f}, {7.5f, 1, 7.5f}};
}
constexpr std::size_t kSlots = 7;  // one less than the probes: the box of cells grows over the room

TEST(ProbeRanking, WithRoomForEveryProbeAllLiveOnesNearestFirstThenNothingOnceResident) {
    const std::vector<glm::vec3> probes = {{6, 1, 4}, {2, 1, 4}, {4.5f, 1, 4}, {4, 1, 7}, {1, 1, 1}};
    ProbeGrid grid = roomGrid(probes);
    ProbeSet set(probes);
    set.remove(ProbeId{3});
    grid.removeProbe(set, ProbeId{3});
    ResidencyPlanner planner = pool(8, probes.size());
    ProbeRanking ranking;
    const auto wanted = ranking.wanted(looking({4, 1, 4}, {1, 0, 0}), grid, set, planner);
    EXPECT_EQ(raw(wanted), (std::vector<std::uint32_t>{2, 0, 1, 4}));  // 0.5, 2, 2 (by id), 4.2 m; 3 removed
    planner.remove(ProbeId{3});
    planner.beginFrame(wanted, set, true);
    while (const auto load = planner.next()) planner.loaded(*load);
    planner.endFrame();
    EXPECT_TRUE(ranking.wanted(looking({4, 1, 4}, {1, 0, 0}), grid, set, planner).empty());
}

TEST(ProbeRanking, WhatThePixelsAskedForComesFirstByHowManyAsked) {
    const std::vector<glm::vec3> probes = scene({7.5f, 1, 4}, {0.5f, 1, 4}, {4.3f, 1, 4});
    const ProbeGrid grid = roomGrid(probes);
    const ProbeSet set(probes);
    ProbeRanking ranking;
    const CameraView view = looking({4.3f, 1, 4}, {1, 0, 0});
    // Without demand the probes beside the eye come first.
    const auto byPlace = raw(ranking.wanted(view, grid, set, pool(kSlots, probes.size())));
    ASSERT_GE(byPlace.size(), 2u);
    EXPECT_EQ(std::min(byPlace[0], byPlace[1]), 2u);
    EXPECT_EQ(std::max(byPlace[0], byPlace[1]), 3u);
    // The far corners 4 and 7 asked for by 2 and 9 pixels: first, 7 then 4, whatever the place says.
    const auto wanted = raw(ranking.wanted(view, grid, set, pool(kSlots, probes.size(), {0, 0, 0, 0, 2, 0, 0, 9})));
    ASSERT_GE(wanted.size(), 2u);
    EXPECT_EQ(wanted[0], 7u);
    EXPECT_EQ(wanted[1], 4u);
}

TEST(ProbeRanking, WhatTheCameraSeesBeforeWhatIsBehindIt) {
    // 0 and 1 3 m either side of the eye along x; the eye at a cell's centre, so that the box of
    // cells around it is symmetric.
    const glm::vec3 eye(4.5f, 1, 4.5f);
    const std::vector<glm::vec3> probes = scene(eye + glm::vec3(3, 0, 0), eye - glm::vec3(3, 0, 0), eye);
    const ProbeGrid grid = roomGrid(probes);
    const ProbeSet set(probes);
    ProbeRanking forward, backward;
    const auto ahead = raw(forward.wanted(looking(eye, {1, 0, 0}), grid, set, pool(kSlots, probes.size())));
    const auto behind = raw(backward.wanted(looking(eye, {-1, 0, 0}), grid, set, pool(kSlots, probes.size())));
    // The box of cells grew until it listed a probe per slot (the first box lists the two by the eye).
    EXPECT_GE(ahead.size(), kSlots);
    ASSERT_TRUE(rankOf(ahead, 0) >= 0 && rankOf(ahead, 1) >= 0 && rankOf(behind, 0) >= 0 && rankOf(behind, 1) >= 0);
    EXPECT_LT(rankOf(ahead, 0), rankOf(ahead, 1));
    EXPECT_LT(rankOf(behind, 1), rankOf(behind, 0));
}

TEST(ProbeRanking, WhereTheCameraIsHeadingBeforeWhereItComesFrom) {
    // Probes 3 m to either side of the walk, out of view of a camera looking along +z.
    const auto lastFrame = [](float step) {
        const std::vector<glm::vec3> probes = scene({7, 1, 2}, {1, 1, 2}, {4, 1, 2});
        const ProbeGrid grid = roomGrid(probes);
        const ProbeSet set(probes);
        ProbeRanking ranking;
        std::vector<std::uint32_t> wanted;
        for (int f = 0; f <= 10; ++f)  // ends at x = 4 either way
            wanted = raw(ranking.wanted(looking({4.0f - step * float(10 - f), 1, 2}, {0, 0, 1}), grid, set,
                                        pool(kSlots, probes.size())));
        return wanted;
    };
    const auto east = lastFrame(0.2f), west = lastFrame(-0.2f);
    ASSERT_TRUE(rankOf(east, 0) >= 0 && rankOf(east, 1) >= 0 && rankOf(west, 0) >= 0 && rankOf(west, 1) >= 0);
    EXPECT_LT(rankOf(east, 0), rankOf(east, 1));
    EXPECT_LT(rankOf(west, 1), rankOf(west, 0));
}

}  // namespace
