// The residency's rules without GL (runtime/residency_planner.h): the pool a budget holds, the
// per-frame upload bound, which resident probe is evicted, and the hysteresis that keeps two probes
// of similar demand from swapping places every frame.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "cubeao/core/error.h"
#include "cubeao/runtime/residency_planner.h"
#include "probe_id_print.h"

namespace {

using cubeao::ProbeId;
using cubeao::ResidencyBudget;
using cubeao::ResidencyHysteresis;
using cubeao::ResidencyPlanner;
using cubeao::residencyPool;
using cubeao::ResidencyPool;
using cubeao::stagingRegionBytes;
using cubeao::SlotId;
using Load = ResidencyPlanner::Load;
constexpr std::size_t kProbe = 1000;  // bytes a probe

std::vector<ProbeId> ids(const std::vector<std::uint32_t>& raw) {
    std::vector<ProbeId> out;
    for (const std::uint32_t i : raw) out.push_back(ProbeId{i});
    return out;
}

// Every probe the planner knows, live (where they are plays no part in planning).
cubeao::ProbeSet allLive(std::size_t probes) { return cubeao::ProbeSet(std::vector<glm::vec3>(probes)); }

// Plans and applies one frame (every load's bytes readable) over `set` (all live without one);
// returns its loads in order.
std::vector<Load> runFrame(ResidencyPlanner& planner, const std::vector<std::uint32_t>& wanted, bool unbounded = false,
                           const cubeao::ProbeSet* set = nullptr) {
    std::vector<Load> loads;
    const std::vector<ProbeId> typed = ids(wanted);
    const cubeao::ProbeSet everyone = allLive(planner.probes());
    planner.beginFrame(typed, set ? *set : everyone, unbounded);
    while (const std::optional<Load> load = planner.next()) {
        planner.loaded(*load);
        loads.push_back(*load);
    }
    planner.endFrame();
    return loads;
}

std::vector<std::uint32_t> probesOf(const std::vector<Load>& loads) {
    std::vector<std::uint32_t> ids;
    for (const Load& l : loads) ids.push_back(index(l.probe));
    return ids;
}

// The pixels' feedback of the frame just planned: `counts` per probe id.
void see(ResidencyPlanner& planner, std::vector<std::uint32_t> counts) {
    counts.resize(planner.probes(), 0u);
    planner.feedback(counts, planner.frame() - 1);
}

ResidencyPlanner fullPool(std::size_t slots, std::size_t probes) {
    ResidencyPlanner planner(slots, kProbe, 100 * kProbe);
    planner.resizeProbes(probes);
    std::vector<std::uint32_t> all(slots);
    for (std::uint32_t i = 0; i < slots; ++i) all[i] = i;
    runFrame(planner, all, true);
    return planner;
}

TEST(ResidencyPlanner, ABudgetHoldsWholePagesBesideTheFixedBytes) {
    ResidencyBudget b;
    b.fixedBytes = 5000, b.probeBytes = kProbe, b.probes = 100, b.res = 64, b.maxTextureSize = 16384, b.maxLayers = 2048;
    // 5.5 probes' room: 5 would need a 3×2 page (6 tiles, too much), 4 fit a 2×2 page exactly.
    b.budgetBytes = 5000 + 5 * kProbe + kProbe / 2;
    auto pool = residencyPool(b);
    EXPECT_EQ(pool.slots, 4u);
    EXPECT_EQ(pool.atlasBytes, 4 * kProbe);
    // Every budget from one probe's room to 40: the atlas fits, and no larger pool would.
    for (std::size_t room = 1; room <= 40; ++room) {
        b.budgetBytes = 5000 + room * kProbe;
        pool = residencyPool(b);
        EXPECT_LE(5000 + pool.atlasBytes, b.budgetBytes) << room;
        EXPECT_EQ(pool.slots, pool.atlas.tiles()) << room;  // a tile paid for is a slot
        EXPECT_GE(pool.slots, 1u);
        for (std::size_t more = pool.slots + 1; more <= room; ++more)
            EXPECT_GT(cubeao::probeAtlasLayout(more, 64, 16384, 2048).tiles(), room) << room << " " << more;
    }
    // No more slots than probes; without a budget, exactly the probes.
    b.budgetBytes = 5000 + 200 * kProbe;
    EXPECT_EQ(residencyPool(b).slots, 100u);
    b.budgetBytes = 0;
    EXPECT_EQ(residencyPool(b).slots, 100u);
}

TEST(ResidencyPlanner, ABudgetBelowOneProbeNamesTheLeastThatHoldsOne) {
    ResidencyBudget b;
    b.fixedBytes = 3 << 20, b.probeBytes = 1 << 20, b.probes = 10, b.res = 512, b.maxTextureSize = 16384, b.maxLayers = 2048;
    b.budgetBytes = (4 << 20) - 1;
    try {
        residencyPool(b);
        FAIL() << "a budget one byte short of one probe was accepted";
    } catch (const cubeao::Error& e) {
        EXPECT_NE(std::string(e.what()).find("give at least 4.0000 MiB"), std::string::npos) << e.what();
    }
    b.budgetBytes = 4 << 20;
    EXPECT_EQ(residencyPool(b).slots, 1u);
}

// The staging (two regions of a frame's uploads) shrinks with the pool: a frame never loads more
// probes than there are slots, so a region holds min(uploadBytes, slots · probeBytes). Under a small
// budget each slot then costs three probes' bytes (its tile and its share of two regions) instead of
// the full regions standing beside one probe.
TEST(ResidencyPlanner, TheStagingShrinksWithThePool) {
    ResidencyBudget b;
    b.fixedBytes = 5000, b.probeBytes = kProbe, b.probes = 100, b.res = 64, b.maxTextureSize = 16384, b.maxLayers = 2048;
    b.uploadBytes = 8 * kProbe, b.stagingRegions = 2;
    b.budgetBytes = 5000 + 12 * kProbe;  // full regions (16 probes' bytes) would not leave room for one
    ResidencyPool pool = residencyPool(b);
    EXPECT_EQ(pool.slots, 4u);  // 4 tiles + 2 × 4 staged: 12
    EXPECT_EQ(pool.uploadBound, 4 * kProbe);
    EXPECT_EQ(pool.stagingBytes, 2 * stagingRegionBytes(4 * kProbe));
    EXPECT_LE(5000 + pool.atlasBytes + pool.stagingBytes, b.budgetBytes);
    b.budgetBytes = 5000 + 100 * kProbe;  // the regions reach uploadBytes: 81 tiles (9 × 9) + 16
    pool = residencyPool(b);
    EXPECT_EQ(pool.slots, 81u);
    EXPECT_EQ(pool.uploadBound, 8 * kProbe);
    EXPECT_LE(5000 + pool.atlasBytes + pool.stagingBytes, b.budgetBytes);
    EXPECT_EQ(stagingRegionBytes(10485), 10496u) << "regions start at multiples of 16 bytes";
    // The least budget: one tile and two regions of one probe.
    b.budgetBytes = 5000 + kProbe + 2 * stagingRegionBytes(kProbe) - 1;
    EXPECT_THROW(residencyPool(b), cubeao::Error);
    b.budgetBytes += 1;
    EXPECT_EQ(residencyPool(b).slots, 1u);
    // Without a budget the regions hold what the probes there are can fill.
    b.budgetBytes = 0, b.probes = 3;
    EXPECT_EQ(residencyPool(b).uploadBound, 3 * kProbe);
}

// The coarse tier's level: the finest that costs the full-resolution pool no slot; where every level
// costs slots, the coarsest that leaves one; none where the pool holds every probe.
TEST(ResidencyPlanner, TheCoarseTierTakesTheFinestLevelThatCostsNoSlot) {
    const std::vector<std::size_t> tier = {0, 2500, 640, 160};  // the tier's bytes at levels 1..3
    // A budget of `room` bytes for the tier and pages of 4 slots of 1000 bytes.
    const auto pool = [](std::size_t room) {
        return [room](std::size_t tierBytes) -> std::size_t {
            return tierBytes > room ? 0 : (room - tierBytes) / 4000 * 4;
        };
    };
    EXPECT_EQ(cubeao::coarseTierLevel(tier, 10, pool(12000)), 0u) << "every probe has a slot";
    EXPECT_EQ(cubeao::coarseTierLevel(tier, 10, pool(11000)), 1u) << "8 slots beside level 1's 2500 bytes too";
    EXPECT_EQ(cubeao::coarseTierLevel(tier, 10, pool(10000)), 2u) << "level 1 costs a page, level 2 none";
    EXPECT_EQ(cubeao::coarseTierLevel(tier, 10, pool(8300)), 3u);
    EXPECT_EQ(cubeao::coarseTierLevel(tier, 10, pool(8100)), 3u) << "every level costs slots: the coarsest";
    EXPECT_EQ(cubeao::coarseTierLevel(tier, 10, pool(4100)), 0u) << "no level leaves a slot: no tier";
    EXPECT_EQ(cubeao::coarseTierLevel(tier, 10, pool(3000)), 0u) << "no slot even without a tier";
    EXPECT_EQ(cubeao::coarseTierLevel(std::vector<std::size_t>{0}, 10, pool(5000)), 0u) << "one level";
}

TEST(ResidencyPlanner, EachFrameLoadsAtMostTheUploadBoundAndReadsAheadWhatComesNext) {
    ResidencyPlanner planner(20, kProbe, 2 * kProbe + kProbe / 2);  // 2.5 probes a frame: 2 loads
    planner.resizeProbes(20);
    std::vector<std::uint32_t> wanted;
    for (std::uint32_t i = 0; i < 12; ++i) wanted.push_back(11 - i);
    EXPECT_EQ(probesOf(runFrame(planner, wanted)), (std::vector<std::uint32_t>{11, 10}));
    const std::vector<ProbeId> typed = ids(wanted);
    const cubeao::ProbeSet set = allLive(20);
    planner.beginFrame(typed, set, false);
    std::vector<std::uint32_t> loaded;
    while (const auto load = planner.next()) planner.loaded(*load), loaded.push_back(index(load->probe));
    EXPECT_EQ(loaded, (std::vector<std::uint32_t>{9, 8}));
    // The next ⌊2 · 2.5⌋ = 5 wanted probes not resident, in order.
    EXPECT_EQ(std::vector<ProbeId>(planner.readAhead().begin(), planner.readAhead().end()), ids({7, 6, 5, 4, 3}));
    planner.endFrame();
    // Unbounded (a start, a cut): everything wanted in one frame.
    EXPECT_EQ(runFrame(planner, wanted, true).size(), 8u);
    EXPECT_EQ(planner.resident(), 12u);
    EXPECT_EQ(planner.loads(), 12u);
}

TEST(ResidencyPlanner, NoMoreResidentsThanSlotsAndWantedResidentsAreNeverEvicted) {
    ResidencyPlanner planner = fullPool(3, 10);
    EXPECT_EQ(planner.resident(), 3u);
    // Probes 0, 1, 2 resident and still wanted, first: nothing else gets in (the list is cut at 3).
    EXPECT_TRUE(runFrame(planner, {0, 1, 2, 3, 4}).empty());
    EXPECT_EQ(planner.evictions(), 0u);
    // 3 and 4 wanted before them: two are evicted, 2 (still wanted) stays.
    see(planner, {0, 0, 0, 50, 50});
    const auto loads = runFrame(planner, {3, 4, 2});
    EXPECT_EQ(probesOf(loads), (std::vector<std::uint32_t>{3, 4}));
    EXPECT_TRUE(planner.isResident(ProbeId{2}));
    EXPECT_EQ(planner.resident(), 3u);
    for (const SlotId s : {SlotId{0}, SlotId{1}, SlotId{2}}) EXPECT_EQ(planner.slotOf(planner.ownerOf(s)), s);
}

TEST(ResidencyPlanner, TheVictimIsTheLeastDemandedThenTheLeastRecentlyUsed) {
    ResidencyPlanner planner = fullPool(4, 10);
    see(planner, {5});  // frame 0: probe 0 used
    for (int f = 0; f <= ResidencyHysteresis::kFreshFrames; ++f) runFrame(planner, {0, 1, 2, 3});
    // The newest feedback: 1 and 2 used by 9 and 3 pixels, 0 and 3 by none (0 was used in frame 0,
    // 3 never); 4, 5, 6 asked for by many.
    see(planner, {0, 9, 3, 0, 100, 100, 100});
    const auto loads = runFrame(planner, {4, 5, 6});
    std::vector<ProbeId> evicted;
    for (const Load& l : loads) evicted.push_back(l.evicted);
    EXPECT_EQ(evicted, ids({3, 0, 2}));
    EXPECT_TRUE(planner.isResident(ProbeId{1}));
    EXPECT_EQ(planner.evictions(), 3u);
}

TEST(ResidencyPlanner, AProbeInUseGivesWayOnlyToOneWantedClearlyMore) {
    ResidencyPlanner planner = fullPool(2, 4);
    see(planner, {10, 10, 0, 0});
    runFrame(planner, {0, 1});
    const auto wantThree = [&](std::uint32_t demandOf3) {
        see(planner, {10, 10, 0, demandOf3});
        return runFrame(planner, {3});
    };
    // 1.5 · 10 + 4 = 19 sampled pixels: 19 is not enough, 20 is.
    EXPECT_TRUE(wantThree(19).empty());
    const auto loads = wantThree(20);
    ASSERT_EQ(loads.size(), 1u);
    EXPECT_EQ(loads[0].probe, ProbeId{3});
    EXPECT_NE(loads[0].evicted, ProbeId::None);
}

TEST(ResidencyPlanner, AProbeNoPixelAskedForDoesNotDisplaceOneJustLoaded) {
    ResidencyPlanner planner = fullPool(2, 4);  // loaded in frame 0, never used by a pixel
    for (int f = 1; f <= ResidencyHysteresis::kFreshFrames; ++f) EXPECT_TRUE(runFrame(planner, {3}).empty()) << f;
    // kFreshFrames later, 3 (ranked by place only) takes a slot.
    EXPECT_EQ(probesOf(runFrame(planner, {3})), (std::vector<std::uint32_t>{3}));
    // A probe one pixel asks for displaces a fresh one that no pixel uses (past kInUseFrames).
    ResidencyPlanner fresh = fullPool(2, 4);
    for (int f = 1; f <= ResidencyHysteresis::kInUseFrames; ++f) runFrame(fresh, {});
    EXPECT_TRUE(runFrame(fresh, {3}).empty());
    see(fresh, {0, 0, 0, 1});
    EXPECT_EQ(probesOf(runFrame(fresh, {3})), (std::vector<std::uint32_t>{3}));
}

TEST(ResidencyPlanner, AProbeWhoseBytesFailIsPassedOverAndTheNextTakesItsSlot) {
    ResidencyPlanner planner(2, kProbe, 10 * kProbe);
    planner.resizeProbes(3);
    const std::vector<ProbeId> wanted = ids({0, 1});
    const cubeao::ProbeSet set = allLive(3);
    planner.beginFrame(wanted, set, false);
    const auto first = planner.next();
    ASSERT_TRUE(first);
    planner.skipped(*first);
    const auto second = planner.next();
    ASSERT_TRUE(second);
    EXPECT_EQ(second->probe, ProbeId{1});
    EXPECT_EQ(second->slot, first->slot);
    planner.loaded(*second);
    EXPECT_FALSE(planner.next());
    EXPECT_FALSE(planner.isResident(ProbeId{0}));
    EXPECT_EQ(planner.loads(), 1u);
}

TEST(ResidencyPlanner, ARemovedProbeFreesItsSlotAndIsNeverLoaded) {
    ResidencyPlanner planner = fullPool(2, 4);
    cubeao::ProbeSet set = allLive(4);
    set.remove(ProbeId{1});
    EXPECT_EQ(planner.remove(ProbeId{1}), SlotId{1});
    EXPECT_EQ(planner.remove(ProbeId{1}), SlotId::None);  // already gone
    EXPECT_EQ(planner.resident(), 1u);
    const auto loads = runFrame(planner, {1, 2}, false, &set);  // wanted, but not live in the set
    ASSERT_EQ(loads.size(), 1u);
    EXPECT_EQ(loads[0].probe, ProbeId{2});
    EXPECT_EQ(loads[0].slot, SlotId{1});
    EXPECT_EQ(loads[0].evicted, ProbeId::None);
}

TEST(ResidencyPlanner, GrownSlotsComeAfterTheOldOnesAndAreFilledFirstFree) {
    ResidencyPlanner planner = fullPool(2, 5);
    planner.growSlots(4);
    EXPECT_EQ(planner.slots(), 4u);
    // 2 and 3 take the new slots; 4 finds the pool full of probes loaded a frame ago (kept: fresh).
    const auto loads = runFrame(planner, {2, 3, 4});
    ASSERT_EQ(loads.size(), 2u);
    EXPECT_EQ(loads[0].slot, SlotId{2});
    EXPECT_EQ(loads[1].slot, SlotId{3});
    EXPECT_EQ(loads[1].evicted, ProbeId::None);
    EXPECT_TRUE(planner.isResident(ProbeId{0}) && planner.isResident(ProbeId{1}) && !planner.isResident(ProbeId{4}));
}

}  // namespace
