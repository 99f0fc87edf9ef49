// Candidate probes per world cell (src/cubeao/runtime/probe_grid.h): per cell the K probes that
// shade its surface points best together, chosen greedily; the per-point work stays K however many
// probes there are.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <utility>
#include <vector>

#include <glm/geometric.hpp>

#include "cubeao/core/error.h"
#include "cubeao/runtime/nearest_lists.h"
#include "cubeao/runtime/probe_grid.h"
#include "common/runtime_layout.h"

namespace {

using namespace cubeao;

bool contains(std::span<const std::uint32_t> list, std::uint32_t probe) {
    return std::find(list.begin(), list.end(), probe) != list.end();
}

// Floor points (normal up) every 0.25 along x in [0, 10) at z = 1.
std::vector<SurfaceSample> floorLine() {
    std::vector<SurfaceSample> points;
    for (float x = 0.125f; x < 10.0f; x += 0.25f) points.push_back({{x, 0.0f, 1.0f}, {0.0f, 1.0f, 0.0f}});
    return points;
}

TEST(ProbeGrid, ProbesBehindAWallLoseToFartherOnesThatSeeTheCell) {
    // Five probes on a line; a wall at x = 5.2 that probes on the far side cannot see through.
    const std::vector<glm::vec3> probes = {{0.5f, 1, 1}, {2.5f, 1, 1}, {4.5f, 1, 1}, {5.5f, 1, 1}, {9.5f, 1, 1}};
    const auto quality = [&](std::uint32_t p, const SurfaceSample& x) {
        if ((probes[p].x < 5.2f) != (x.position.x < 5.2f)) return 0.0;
        const glm::vec3 d = x.position - probes[p];
        return 1.0 / double(glm::dot(d, d));
    };
    const ProbeGrid grid({0, 0, 0}, {10, 2, 2}, ProbeSet(probes), floorLine(), quality, {3, 1.0f, 0, 0, 0});
    EXPECT_EQ(grid.dims(), glm::ivec3(10, 2, 2));
    const auto near4 = grid.candidates({4.2f, 0.2f, 1.2f});
    ASSERT_EQ(near4.size(), 3u);
    EXPECT_EQ(near4[0], 2u);  // the best for every point of the cell
    EXPECT_EQ(near4[1], 1u);  // the best second
    EXPECT_EQ(near4[2], 0u);  // probe 3 is nearer than 0 but behind the wall
    const auto far = grid.candidates({8.7f, 0.2f, 1.2f});
    ASSERT_EQ(far.size(), 3u);
    EXPECT_EQ(far[0], 4u);
    EXPECT_EQ(far[1], 3u);
    EXPECT_EQ(far[2], 2u);  // only two see it: the nearest other fills up
    // Outside the grid: clamped to the border cell.
    EXPECT_EQ(grid.candidates({-5.0f, 0.2f, 1.2f})[0], 0u);
}

TEST(ProbeGrid, AFarProbeWithTheOnlyViewOfASurfaceBeatsNearerOnes) {
    // A cell holding both faces of a thin column: 8 probes crowd its west side, one stands farther
    // off to the east. "Nearest K" would take west probes only and leave the east face unshaded; the
    // greedy choice must take the east probe, and then the best west ones.
    std::vector<glm::vec3> probes;
    for (int i = 0; i < 8; ++i) probes.push_back({3.0f - 0.2f * float(i), 1.0f, 0.5f + 0.1f * float(i)});
    probes.push_back({9.0f, 1.0f, 1.0f});  // index 8
    std::vector<SurfaceSample> points;
    for (float y = 0.1f; y < 1.0f; y += 0.2f) {
        points.push_back({{4.45f, y, 1.0f}, {-1.0f, 0.0f, 0.0f}});  // west face
        points.push_back({{4.55f, y, 1.0f}, {1.0f, 0.0f, 0.0f}});   // east face
    }
    const auto quality = [&](std::uint32_t p, const SurfaceSample& x) {
        const glm::vec3 d = x.position - probes[p];
        if (!(glm::dot(x.normal, d) < 0.0f)) return 0.0;  // the face looks away from the probe
        return 1.0 / double(glm::dot(d, d));
    };
    const ProbeGrid grid({0, 0, 0}, {10, 2, 2}, ProbeSet(probes), points, quality, {4, 1.0f, 0, 0, 0});
    const auto list = grid.candidates({4.5f, 0.5f, 1.0f});
    ASSERT_EQ(list.size(), 4u);
    EXPECT_TRUE(contains(list, 8u)) << "the east face's only probe";
    EXPECT_TRUE(contains(list, 0u)) << "the west face's best probe";
    EXPECT_TRUE(contains(list, 1u)) << "the west face's second best";
}

TEST(ProbeGrid, WorkPerPointStaysKAndMemoryIsCapped) {
    std::vector<glm::vec3> probes;
    for (int i = 0; i < 1000; ++i) probes.push_back({float(i % 10) + 0.5f, float(i / 100) * 0.3f, float((i / 10) % 10) + 0.5f});
    const ProbeGrid grid({0, 0, 0}, {10, 3, 10}, ProbeSet(probes), floorLine(),
                         [](std::uint32_t, const SurfaceSample&) { return 1.0; }, {8, 0.05f, 4096, 0, 0});
    EXPECT_LE(std::size_t(grid.dims().x) * grid.dims().y * grid.dims().z, 4096u) << "cells grow to fit the cap";
    EXPECT_EQ(grid.candidates({5, 1, 5}).size(), 8u);
    EXPECT_EQ(grid.candidates({0.2f, 0.0f, 1.0f}).size(), 8u);
    EXPECT_EQ(grid.table().size(), std::size_t(grid.dims().x) * grid.dims().y * grid.dims().z * 8u);
}

// ---- the second list: the K probes of a set nearest each cell (nearest_lists.h) -------------------

// Every cell's list is the K of the set nearest its centre, as trying every probe finds them.
void expectNearestOfTheSet(const NearestProbeLists& lists, const std::vector<std::uint32_t>& ids,
                           const std::vector<glm::vec3>& at) {
    for (std::size_t c = 0; c < lists.cellCount(); ++c) {
        std::vector<std::pair<float, std::uint32_t>> all;
        for (std::size_t i = 0; i < ids.size(); ++i) {
            const glm::vec3 d = at[i] - lists.cellCentre(c);
            all.emplace_back(glm::dot(d, d), ids[i]);
        }
        std::sort(all.begin(), all.end());
        const auto list = lists.cellList(c);
        for (std::size_t j = 0; j < list.size(); ++j)
            ASSERT_EQ(list[j], j < all.size() ? all[j].second : kernel::kNoProbe) << "cell " << c << " entry " << j;
    }
}

// The cells whose list differs from `before` (K entries a cell), ascending.
std::vector<std::size_t> cellsThatDiffer(const NearestProbeLists& lists, const std::vector<std::uint32_t>& before) {
    std::vector<std::size_t> differ;
    const auto k = std::ptrdiff_t(lists.k());
    for (std::size_t c = 0; c < lists.cellCount(); ++c)
        if (!std::equal(lists.cellList(c).begin(), lists.cellList(c).end(), before.begin() + std::ptrdiff_t(c) * k))
            differ.push_back(c);
    return differ;
}

// Every cell's list against trying every probe: clustered, spread, fewer than K, none, and probes
// outside the grid (clamped into its border cells by the search, at their true distance).
TEST(NearestProbeLists, EveryCellListsTheKNearestOfTheSetAsTryingEveryProbeWould) {
    NearestProbeLists lists({0, 0, 0}, {20, 4, 12}, 1.0f, 4, 512);
    EXPECT_LE(std::size_t(lists.dims().x) * lists.dims().y * lists.dims().z, 512u);
    std::mt19937 rng(7u);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    const auto check = [&](const std::vector<std::uint32_t>& ids, const std::vector<glm::vec3>& at) {
        expectNearestOfTheSet(lists, ids, at);
    };
    std::vector<std::uint32_t> ids;
    std::vector<glm::vec3> at;
    for (int round = 0; round < 4; ++round) {
        ids.clear(), at.clear();
        const int n = round == 0 ? 300 : round == 1 ? 3 : round == 2 ? 40 : 0;
        for (int i = 0; i < n; ++i) {
            // Round 2: a cluster in one corner and two probes outside the bounds.
            const glm::vec3 p = round == 2 ? glm::vec3(2.0f * u(rng), 1.0f * u(rng), 2.0f * u(rng))
                                           : glm::vec3(20.0f * u(rng), 4.0f * u(rng), 12.0f * u(rng));
            ids.push_back(std::uint32_t(1000 + 7 * i)), at.push_back(p);
        }
        if (round == 2) {
            ids.push_back(5), at.push_back({30.0f, 2.0f, 6.0f});
            ids.push_back(6), at.push_back({10.0f, -9.0f, 6.0f});
        }
        const std::vector<std::uint32_t> before = lists.table();
        const std::vector<std::size_t> changed = lists.assign(ids, at);
        ASSERT_NO_FATAL_FAILURE(check(ids, at)) << "round " << round;
        // Exactly the cells whose list differs are reported, ascending.
        EXPECT_EQ(changed, cellsThatDiffer(lists, before)) << "round " << round;
        EXPECT_FALSE(changed.empty()) << "round " << round;
    }
    EXPECT_TRUE(lists.assign(ids, at).empty()) << "the same set again changes nothing";
}

// The residency changes the set a few probes a frame: each assign searches only the cells a probe that
// left or came can change, and must still list what trying every probe lists, reporting exactly the
// cells that changed. Loads, evictions, both in one step, a probe that moves, ties in distance (probes
// on a lattice), a list that empties, and a duplicate id refused.
TEST(NearestProbeLists, AFewProbesComingAndGoingListWhatARebuildLists) {
    NearestProbeLists lists({0, 0, 0}, {16, 4, 8}, 1.0f, 4, 512);
    std::mt19937 rng(11u);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    // A pool of 400 candidates, half of them on a lattice (equal distances to many cell centres).
    std::vector<glm::vec3> pool;
    for (int i = 0; i < 400; ++i)
        pool.push_back(i % 2 == 0 ? glm::vec3(float(i % 16), float(i / 16 % 4), float(i / 64 % 8))
                                  : glm::vec3(16.0f * u(rng), 4.0f * u(rng), 8.0f * u(rng)));
    std::vector<bool> in(pool.size(), false);
    for (std::size_t i = 0; i < 120; ++i) in[i * 3] = true;  // the first frame: many at once
    std::size_t step = 0;
    for (; step < 60; ++step) {
        if (step > 0) {
            // 1–3 loads and 0–3 evictions, as a frame of the residency makes; every 10th step moves one.
            for (int j = 0, loads = 1 + int(rng() % 3); j < loads; ++j) in[rng() % pool.size()] = true;
            for (int j = 0, evictions = int(rng() % 4); j < evictions; ++j) in[rng() % pool.size()] = false;
            if (step % 10 == 0) pool[rng() % pool.size()] = {16.0f * u(rng), 4.0f * u(rng), 8.0f * u(rng)};
        }
        std::vector<std::uint32_t> ids;
        std::vector<glm::vec3> at;
        for (std::uint32_t i = 0; i < pool.size(); ++i)
            if (in[i]) ids.push_back(i), at.push_back(pool[i]);
        std::shuffle(ids.begin(), ids.end(), rng);  // the order of the set does not matter
        for (std::size_t i = 0; i < ids.size(); ++i) at[i] = pool[ids[i]];
        const std::vector<std::uint32_t> before = lists.table();
        const std::vector<std::size_t> changed = lists.assign(ids, at);
        ASSERT_NO_FATAL_FAILURE(expectNearestOfTheSet(lists, ids, at)) << "step " << step;
        ASSERT_EQ(changed, cellsThatDiffer(lists, before)) << "step " << step;
    }
    // Down to two probes: every list holds those two, then nothing.
    const std::vector<std::uint32_t> two = {7, 3};
    const std::vector<glm::vec3> twoAt = {pool[7], pool[3]};
    lists.assign(two, twoAt);
    expectNearestOfTheSet(lists, two, twoAt);
    lists.assign({}, {});
    expectNearestOfTheSet(lists, {}, {});
    EXPECT_THROW(lists.assign(std::vector<std::uint32_t>{4, 4}, std::vector<glm::vec3>{pool[4], pool[4]}), Error);
}

}  // namespace
