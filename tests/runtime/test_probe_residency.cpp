// The run-time that grows (issue 13): the candidate grid's live updates against grids built from
// scratch, and on the GPU the probe residency under a memory budget (GPU bytes measured by GL, not by
// our own arithmetic), eviction and reload giving identical pixels, and a probe added at run time
// giving the frame the same probe gives when loaded from a cache.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include "common/runtime_layout.h"
#include "cubeao/cache/cache_file.h"
#include "cubeao/runtime/probe_grid.h"
#include "cubeao/runtime/probe_projection.h"
#include "cubeao/runtime/renderer.h"
#include "cubeao/scene/builtin.h"
#include "cubeao/ssao/gtao_fallback.h"
#include "cubeao/ssao/ssao_pass.h"
#include "bake_test_settings.h"
#include "damaged_cache.h"
#include "runtime_test_util.h"
#include "test_util.h"

namespace {

using namespace cubeao;

// A quality that depends on the probe's position and the point, like the real one (nearer is better,
// some probes do not see some points), deterministic so two grids can be compared.
double pseudoQuality(const glm::vec3& probe, const SurfaceSample& x) {
    const float d = glm::length(probe - x.position);
    const auto h = std::uint32_t(std::fabs(probe.x * 73.0f + probe.z * 31.0f + x.position.x * 17.0f + x.position.z * 7.0f));
    if (h % 5 == 0) return 0.0;  // "behind a wall"
    return 1.0 / (1.0 + double(d) * d);
}

struct GridCase {
    std::vector<glm::vec3> probes;
    std::vector<SurfaceSample> points;
    ProbeGridSettings settings{2, 1.0f, 0, 6, 16};  // K = 2, 1 m cells, 6 competitors, 16 points
};

GridCase gridCase(std::size_t probes) {
    GridCase c;
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> u(0.0f, 8.0f);
    for (std::size_t i = 0; i < probes; ++i) c.probes.push_back({u(rng), 1.0f, u(rng)});
    for (int i = 0; i < 400; ++i) c.points.push_back({{u(rng), 0.0f, u(rng)}, {0.0f, 1.0f, 0.0f}});
    return c;
}

ProbeGrid buildGrid(const std::vector<glm::vec3>& probes, const GridCase& c) {
    // The quality looks probes up by id in `probes` as the grid knows them; copy so later adds see theirs.
    auto positions = std::make_shared<std::vector<glm::vec3>>(probes);
    return ProbeGrid({0, 0, 0}, {8, 2, 8}, ProbeSet(probes), c.points,
                     [positions](std::uint32_t p, const SurfaceSample& x) { return pseudoQuality((*positions)[p], x); },
                     c.settings);
}

TEST(ProbeGridLive, AddingAProbeGivesTheTableOfAGridBuiltWithItAndTouchesOnlyNearbyCells) {
    const GridCase c = gridCase(40);
    auto positions = std::make_shared<std::vector<glm::vec3>>(c.probes.begin(), c.probes.end() - 1);
    ProbeSet set(*positions);
    ProbeGrid live({0, 0, 0}, {8, 2, 8}, set, c.points,
                   [positions](std::uint32_t p, const SurfaceSample& x) { return pseudoQuality((*positions)[p], x); },
                   c.settings);
    positions->push_back(c.probes.back());
    const ProbeId added = set.add(c.probes.back());
    EXPECT_EQ(added, ProbeId{39});
    const std::vector<std::size_t> changed = live.addProbe(set, added);
    const ProbeGrid scratch = buildGrid(c.probes, c);
    EXPECT_EQ(live.table(), scratch.table());
    EXPECT_GT(changed.size(), 0u);
    EXPECT_LT(changed.size(), live.cellCount()) << "40 probes, 6 competitors per cell: a probe reaches few cells";
    EXPECT_EQ(set.liveCount(), 40u);
}

TEST(ProbeGridLive, RemovingAProbeGivesTheTableOfAGridBuiltWithoutIt) {
    const GridCase c = gridCase(40);
    ProbeSet set(c.probes);
    ProbeGrid live = buildGrid(c.probes, c);
    const std::uint32_t removed = 17;
    ASSERT_TRUE(std::find(live.table().begin(), live.table().end(), removed) != live.table().end())
        << "the test needs a probe some cell lists";
    set.remove(ProbeId{removed});
    const std::vector<std::size_t> changed = live.removeProbe(set, ProbeId{removed});
    EXPECT_LT(changed.size(), live.cellCount());
    std::vector<glm::vec3> rest = c.probes;
    rest.erase(rest.begin() + removed);
    const ProbeGrid scratch = buildGrid(rest, c);
    // Ids above the removed one are one less in the scratch grid.
    std::vector<std::uint32_t> expected = scratch.table();
    for (std::uint32_t& id : expected)
        if (id != kernel::kNoProbe && id >= removed) ++id;
    EXPECT_EQ(live.table(), expected);
    EXPECT_THROW(set.remove(ProbeId{removed}), Error) << "a removed probe stays removed";
}

// ---- GPU -----------------------------------------------------------------------------------------

// Six probes down the box room's length, baked small: enough for a budget of two to matter.
const std::vector<glm::vec3>& roomProbes() {
    static const std::vector<glm::vec3> p = {{1.0f, 1.2f, 1.5f}, {3.0f, 1.2f, 1.5f}, {5.0f, 1.2f, 1.5f},
                                             {7.0f, 1.2f, 1.5f}, {2.0f, 2.0f, 3.0f}, {6.0f, 2.0f, 3.0f}};
    return p;
}

class ResidencyGl : public GlTest {
protected:
    void SetUp() override {
        GlTest::SetUp();
        if (IsSkipped()) return;
        dir_ = std::make_unique<test::TempDir>("residency");
        const BakeSettings s = test::bakeSettings(Estimator::Traced, 16, 1.0f, 4);
        const std::span<const glm::vec3> all(roomProbes());
        full_ = (*dir_ / "all.cubeao").string();
        test::bakeCache(test::boxRoom(), all, s, full_);
        lessOne_ = (*dir_ / "less.cubeao").string();
        test::bakeCache(test::boxRoom(), all.first(all.size() - 1), s, lessOne_);
    }

    std::unique_ptr<FrameRenderer> renderer(std::unique_ptr<AoPass> pass) const {
        const Scene& scene = test::boxRoom();
        BlurSettings blur;
        blur.radius = 0;
        return std::make_unique<FrameRenderer>(scene.positions, scene.indices, std::move(pass), blur,
                                               test::compositeSettings());
    }
    static std::unique_ptr<ProbeProjectionPass> pass(const CacheReader& cache, std::size_t budgetBytes = 0,
                                                     std::size_t uploadBytes = 0) {
        ProbeProjectionSettings s;
        s.residency.gpuBudgetBytes = budgetBytes;
        s.residency.uploadBytesPerFrame = uploadBytes;
        return std::make_unique<ProbeProjectionPass>(cache, test::boxRoom().positions, test::boxRoom().indices, s);
    }
    static std::unique_ptr<ProbeProjectionPass> pass(const CacheReader& cache, const ProbeProjectionSettings& s) {
        return std::make_unique<ProbeProjectionPass>(cache, test::boxRoom().positions, test::boxRoom().indices, s);
    }
    // An unbudgeted pass's bytes with the staging ring a budgeted one holds from the start (it makes
    // its own only when a probe comes after the first frame).
    static std::size_t withStaging(const ProbeProjectionPass& p) { return p.gpuBytes() + p.residency().stagingBytes(); }
    static CameraView view(glm::vec3 eye, glm::vec3 target) {
        return test::viewOf(test::singleFrame(eye, target), 0, 48, 32);
    }

    std::unique_ptr<test::TempDir> dir_;
    std::string full_, lessOne_;
};

// GPU bytes of the pass's textures and buffers as GL reports them.
TEST_F(ResidencyGl, TheGpuBytesAllocatedNeverExceedTheBudget) {
    const CacheReader cache(full_);
    const std::size_t perProbe = probeGpuBytes(cache.params());
    // The fixed part (grid, table, staging) first: a budget that cannot hold one probe is refused.
    const std::string m = test::errorMessage([&] { pass(cache, 1024); });
    EXPECT_NE(m.find("cannot hold one probe"), std::string::npos) << m;
    // Without a budget the staging holds what the probes there are can fill in a frame (six small
    // probes: far below the 8 MiB bound), and GL's count is the pass's.
    auto unlimited = pass(cache);
    EXPECT_EQ(unlimited->residency().uploadBound(), roomProbes().size() * perProbe);
    EXPECT_EQ(unlimited->allocatedGpuBytes(), unlimited->gpuBytes());
    // Under a budget the staging shrinks with the pool (ResidencyPlanner.TheStagingShrinksWithThePool).
    ProbeProjectionSettings huge;
    huge.residency.gpuBudgetBytes = std::size_t(1) << 30;
    const std::size_t allResident = pass(cache, huge)->gpuBytes();
    for (const std::size_t budget : {allResident, allResident - 2 * perProbe, allResident - 4 * perProbe}) {
        auto p = pass(cache, budget);
        const std::size_t measured = p->allocatedGpuBytes();
        EXPECT_LE(measured, budget) << "budget " << budget;
        EXPECT_EQ(measured, p->gpuBytes()) << "the pass's own count must be what GL allocated";
        EXPECT_GE(p->residency().slots(), 1u);
    }
}

// A cache with levels of detail under a budget that holds two of six probes at full resolution: the
// other four are drawn from the coarse tier (residency_planner.h coarseTierLevel), so no pixel is left
// to the screen-space fallback that all six resident cover, and the frame is close to the all-resident
// one; the plain cache under the same budget leaves pixels to the fallback. The GPU bytes stay within
// the budget.
TEST_F(ResidencyGl, ProbesWithoutASlotAreDrawnAtTheCoarseTier) {
    BakeSettings s = test::bakeSettings(Estimator::Traced, 32, 1.0f, 4);
    s.levels = 2;  // 32², 16²
    s = resolveBakeSettings(s, 1.0f);
    const std::string file = (*dir_ / "levels.cubeao").string();
    test::bakeCache(test::boxRoom(), roomProbes(), s, file);
    const CacheReader cache(file);
    ASSERT_EQ(cache.params().levels, 2u);
    const std::size_t perProbe = probeGpuBytes(levelParams(cache.params(), 0));
    const std::size_t coarse = probeGpuBytes(levelParams(cache.params(), 1));
    // The full-resolution pass less four probes, plus the tier (six at level 1), plus feedback slack;
    // two probes a frame, so that the tier is at most a quarter of what the budget leaves for probes
    // and their staging (coarseTierLevel).
    const std::size_t upload = 2 * perProbe;
    const std::size_t budget = withStaging(*pass(cache, 0, upload)) - (roomProbes().size() - 2) * perProbe +
                               roomProbes().size() * coarse + 1024;
    const CameraView v = view({1.5f, 1.2f, 2.0f}, {7.5f, 0.3f, 0.5f});  // down the room: far probes seen
    const auto settle = [&](FrameRenderer& r) {
        for (int f = 0; f < 12; ++f) r.render(v, 0);
        return r.readRawAo();
    };
    auto all = renderer(pass(cache));
    const Image expected = settle(*all);
    const double allUncovered = dynamic_cast<ProbeProjectionPass&>(all->method()).uncoveredFraction();

    auto tiered = renderer(pass(cache, budget, upload));
    auto& projection = dynamic_cast<ProbeProjectionPass&>(tiered->method());
    const Image drawn = settle(*tiered);
    const auto maeTo = [&](const Image& image) {
        double sum = 0.0;
        for (std::size_t i = 0; i < image.pixels.size(); ++i)
            sum += std::abs(double(image.pixels[i]) - double(expected.pixels[i]));
        return sum / double(image.pixels.size());
    };
    ASSERT_LT(projection.residency().slots(), roomProbes().size());
    EXPECT_EQ(projection.residency().coarseLevel(), 1u);
    EXPECT_EQ(projection.residency().coarseHeld(), roomProbes().size());
    EXPECT_LE(projection.allocatedGpuBytes(), budget);
    EXPECT_EQ(projection.allocatedGpuBytes(), projection.gpuBytes());
    EXPECT_LE(projection.uncoveredFraction(), allUncovered + 1e-9) << "no pixel left that all six cover";
    const double mae = maeTo(drawn);
    EXPECT_GT(mae, 0.0) << "some pixels take a coarse probe";

    // The same budget less the tier, for a cache without levels: no tier, so some pixels take no probe.
    const std::string plainFile = (*dir_ / "plain.cubeao").string();
    BakeSettings one = s;
    one.levels = 1;
    test::bakeCache(test::boxRoom(), roomProbes(), one, plainFile);
    const CacheReader plain(plainFile);
    auto untiered = renderer(pass(plain, budget - roomProbes().size() * coarse, upload));
    auto& plainProjection = dynamic_cast<ProbeProjectionPass&>(untiered->method());
    const double maeWithout = maeTo(settle(*untiered));
    EXPECT_EQ(plainProjection.residency().coarseLevel(), 0u);
    std::printf("[ coarse tier ] uncovered: all resident %.4f, tier %.4f, no tier %.4f; MAE to all resident: "
                "tier %.4f, no tier %.4f\n",
                allUncovered, projection.uncoveredFraction(), plainProjection.uncoveredFraction(), mae, maeWithout);
    EXPECT_LT(mae, 0.5 * maeWithout) << "a coarse probe is closer to its full-resolution self than the fallback";

    // Walking to the other end loads other probes in bounded frames: each one's quality scale (the probe
    // table) rises from its coarse level's, 4^-1, to 1 over a few frames, at full resolution (level 0).
    const auto table = [&] {
        std::vector<kernel::ProbeEntry> entries(roomProbes().size());
        glGetNamedBufferSubData(projection.residency().tableBuffer(), 0,
                                GLsizeiptr(entries.size() * sizeof(entries[0])), entries.data());
        return entries;
    };
    std::vector<float> scales;
    const std::size_t loadsBefore = projection.residency().stats().loads;
    for (int f = 0; f < 40; ++f) {
        const float x = std::min(1.5f + 0.2f * float(f), 6.5f);  // 25 steps, then 15 frames there
        tiered->render(view({x, 1.2f, 2.0f}, {x + 2.0f, 0.3f, 0.5f}), 0);
        for (const kernel::ProbeEntry& e : table())
            if (e.level == 0 && e.tile != kernel::kNoSlot && e.qualityScale < 1.0f) scales.push_back(e.qualityScale);
    }
    EXPECT_GT(projection.residency().stats().loads, loadsBefore) << "the walk loads other probes";
    ASSERT_FALSE(scales.empty()) << "a probe loaded over its coarse level fades in";
    for (const float q : scales) EXPECT_GE(q, 0.25f) << "from the coarse level's quality, never below";
    for (const kernel::ProbeEntry& e : table()) {
        EXPECT_EQ(e.qualityScale, 1.0f) << "settled after the fade";
        if (e.tile != kernel::kNoSlot) {
            EXPECT_TRUE(e.level == 0 || e.level == 1);
        }
    }
    const auto fellBack = [](const ProbeProjectionPass& p) {
        return p.pixelShares().uncovered + p.pixelShares().fallbackProbe;
    };
    EXPECT_GT(fellBack(plainProjection), fellBack(projection)) << "without the tier, pixels fall back";
}

// A walk from one end of the room to the other and back with room for two probes: probes are evicted
// and loaded again, and back at the start the frame is the one rendered there before.
TEST_F(ResidencyGl, ASmallBudgetEvictsAndReloadsAndAReloadedProbeGivesIdenticalPixels) {
    const CacheReader cache(full_);
    const std::size_t perProbe = probeGpuBytes(cache.params());
    // Room for two probes: all six less four, with the same upload bound (the staging ring counts),
    // plus slack for the feedback ring's alignment padding, which the budget reserves at its largest.
    const std::size_t budget = withStaging(*pass(cache, 0, perProbe)) - (roomProbes().size() - 2) * perProbe + 1024;
    auto r = renderer(pass(cache, budget, perProbe));
    auto& projection = dynamic_cast<ProbeProjectionPass&>(r->method());
    ASSERT_LT(projection.residency().slots(), roomProbes().size());
    const CameraView start = view({1.5f, 1.2f, 2.0f}, {0.5f, 0.3f, 0.5f});
    const CameraView end = view({6.5f, 1.2f, 2.0f}, {7.5f, 0.3f, 0.5f});
    // Each frame the GPU's count of every cell's resident candidates is what the grid and the pool say.
    const auto expectCounts = [&] {
        const std::vector<std::uint32_t> counts = projection.readResidentCandidateCounts();
        ASSERT_EQ(counts.size(), projection.grid().cellCount());
        for (std::size_t c = 0; c < counts.size(); ++c) {
            std::uint32_t resident = 0;
            for (const std::uint32_t id : projection.grid().cellCandidates(c))
                if (id != kernel::kNoProbe) resident += projection.residency().isResident(ProbeId{id}) ? 1u : 0u;
            ASSERT_EQ(counts[c], resident) << "cell " << c;
        }
    };
    const auto settle = [&](const CameraView& v) {
        for (int f = 0; f < 12; ++f) {
            r->render(v, 0);
            expectCounts();
        }
        return r->readRawAo();
    };
    const Image before = settle(start);
    const std::size_t loadsBefore = projection.residency().stats().loads;
    settle(end);
    EXPECT_GT(projection.residency().stats().evictions, 0u);
    const Image after = settle(start);
    EXPECT_GT(projection.residency().stats().loads, loadsBefore);
    EXPECT_LE(projection.residency().stats().maxFrameUploadBytes, perProbe) << "one probe per frame at most";
    ASSERT_EQ(before.pixels.size(), after.pixels.size());
    EXPECT_EQ(before.pixels, after.pixels);
    EXPECT_LT(projection.uncoveredFraction(), 0.5) << "the resident probes must cover most of the view";
}

// Probes 0–4 from a cache plus probe 5 added at run time against all six from one cache; and the
// six-probe pass with probe 5 removed against the five-probe cache.
TEST_F(ResidencyGl, AProbeAddedAtRunTimeGivesTheFrameOfTheSameProbeFromACache) {
    const CacheReader full(full_), less(lessOne_);
    const CameraView v = view({4.0f, 1.5f, 2.5f}, {6.0f, 0.5f, 0.5f});
    auto fromCache = renderer(pass(full));
    fromCache->render(v, 0);
    const Image expected = fromCache->readRawAo();

    auto live = renderer(pass(less));
    live->render(v, 0);
    const Image withoutIt = live->readRawAo();
    auto& projection = dynamic_cast<ProbeProjectionPass&>(live->method());
    const std::size_t before = projection.gpuBytes();
    EXPECT_EQ(projection.allocatedGpuBytes(), before) << "no budget, every probe loaded at once: no staging yet";
    const ProbeId id = projection.addProbe(full.copyProbe(roomProbes().size() - 1));
    EXPECT_EQ(index(id), roomProbes().size() - 1);
    for (int f = 0; f < 3; ++f) live->render(v, 0);  // the new probe streams in within the bound
    const Image added = live->readRawAo();
    EXPECT_GT(projection.residency().stagingBytes(), 0u);
    EXPECT_EQ(projection.allocatedGpuBytes(), projection.gpuBytes()) << "the ring it streamed through, counted";
    EXPECT_GE(projection.gpuBytes(), before + projection.residency().stagingBytes());
    EXPECT_NE(added.pixels, withoutIt.pixels) << "the sixth probe must change this view";
    EXPECT_EQ(added.pixels, expected.pixels);

    auto& fullProjection = dynamic_cast<ProbeProjectionPass&>(fromCache->method());
    fullProjection.removeProbe(id);
    fromCache->render(v, 0);
    EXPECT_EQ(fromCache->readRawAo().pixels, withoutIt.pixels);
}

// A viewer placing probes live starts with none: the pass built from the parameters alone, then
// every probe added, renders the frame of the cache that holds them all.
TEST_F(ResidencyGl, AnEmptyStartFilledProbeByProbeRendersTheFullCachesFrame) {
    const CacheReader full(full_);
    const CameraView v = view({4.0f, 1.5f, 2.5f}, {6.0f, 0.5f, 0.5f});
    auto fromCache = renderer(pass(full));
    fromCache->render(v, 0);
    const Image expected = fromCache->readRawAo();

    auto empty = std::make_unique<ProbeProjectionPass>(full.params(), test::boxRoom().positions,
                                                       test::boxRoom().indices, ProbeProjectionSettings{}, 2);
    auto& projection = *empty;
    auto live = renderer(std::move(empty));
    live->render(v, 0);
    EXPECT_EQ(projection.uncoveredFraction(), projection.pixelShares().geometry) << "no probe yet: nothing covered";
    for (std::size_t i = 0; i < full.probeCount(); ++i) {
        EXPECT_EQ(index(projection.addProbe(full.copyProbe(i))), i);
        live->render(v, 0);
    }
    for (int f = 0; f < 3; ++f) live->render(v, 0);
    EXPECT_EQ(live->readRawAo().pixels, expected.pixels);
    EXPECT_EQ(projection.allocatedGpuBytes(), projection.gpuBytes()) << "what GL holds is what the pass counts";
}

// With every probe removed no pixel is covered: with the GTAO fallback each pixel with geometry gets
// exactly what the gtao baseline computes there (same kernel, same jitter), without one it stays open.
TEST_F(ResidencyGl, APixelNoProbeSeesGetsTheScreenSpaceValueNotOne) {
    const CacheReader cache(full_);
    const CameraView v = view({4.0f, 1.5f, 2.5f}, {6.0f, 0.5f, 0.5f});
    const SsaoSettings gtao = test::methodSettings(SsaoMethod::Gtao, cache.params().radius);
    auto baseline = renderer(std::make_unique<SsaoPass>(gtao));
    baseline->render(v, 3);
    const Image expected = baseline->readRawAo();

    auto probes = pass(cache);
    probes->setFallback(std::make_unique<GtaoFallback>(gtao));
    auto& projection = *probes;
    auto r = renderer(std::move(probes));
    r->render(v, 3);
    const Image covered = r->readRawAo();
    for (std::uint32_t id = 0; id < roomProbes().size(); ++id) projection.removeProbe(ProbeId{id});
    r->render(v, 3);
    const Image filled = r->readRawAo();
    EXPECT_GT(projection.uncoveredFraction(), 0.5);
    EXPECT_EQ(projection.uncoveredFraction(), projection.pixelShares().geometry);
    EXPECT_DOUBLE_EQ(projection.fallback()->filledFraction(), projection.uncoveredFraction());
    std::size_t differs = 0;
    for (std::size_t i = 0; i < filled.pixels.size(); ++i) {
        EXPECT_NEAR(filled.pixels[i], expected.pixels[i], 1e-6f) << "pixel " << i;
        differs += std::fabs(covered.pixels[i] - expected.pixels[i]) > 1e-3f ? 1 : 0;
    }
    EXPECT_GT(differs, filled.pixels.size() / 4) << "the probes must have given other values than GTAO";

    projection.setFallback(nullptr);
    r->render(v, 3);
    const Image open = r->readRawAo();
    EXPECT_EQ(*std::min_element(open.pixels.begin(), open.pixels.end()), 1.0f) << "no fallback: open";
}

// The second list (nearest_lists.h). With one candidate per cell some points are seen by none of
// their cell's; those take the resident probes nearest them, here all six, and so get what a grid
// listing every probe in every cell gives them; every other pixel keeps its one candidate's value.
TEST_F(ResidencyGl, APointItsCellsCandidatesDoNotSeeTakesTheResidentProbesNearIt) {
    const CacheReader cache(full_);
    const CameraView v = view({1.5f, 1.6f, 2.8f}, {7.0f, 0.4f, 0.8f});
    struct Frame {
        Image ao;
        std::vector<float> path;  // per pixel: the diagnostics' path (project.comp), 3 = uncovered
        ProbeProjectionPass::PixelShares shares;
    };
    const auto frame = [&](int candidates, int second) {
        ProbeProjectionSettings s;
        s.grid.candidates = candidates;
        s.residentCandidates = second;
        auto probes = pass(cache, s);
        auto& projection = *probes;
        projection.setDiagnostics(true);
        auto r = renderer(std::move(probes));
        r->render(v, 0);
        Frame out{r->readRawAo(), {}, projection.pixelShares()};
        std::vector<float> rgba(std::size_t(4) * std::size_t(v.width) * std::size_t(v.height));
        glGetTextureImage(projection.diagnosticsTexture(), 0, GL_RGBA, GL_FLOAT, GLsizei(rgba.size() * sizeof(float)),
                          rgba.data());
        for (std::size_t i = 3; i < rgba.size(); i += 4) out.path.push_back(rgba[i]);
        return out;
    };
    const Frame all = frame(int(roomProbes().size()), 0), one = frame(1, 0), both = frame(1, 8);
    ASSERT_EQ(one.path.size(), one.ao.pixels.size());
    std::size_t rescued = 0, stillUncovered = 0;
    for (std::size_t i = 0; i < both.ao.pixels.size(); ++i) {
        // Rows of the diagnostics run top-down, the raw AO's too (both are the frame's images).
        if (one.path[i] == 3.0f && all.path[i] != 3.0f) {  // none of its cell's one candidate sees it
            ++rescued;
            EXPECT_EQ(both.path[i], 2.0f) << "pixel " << i << ": counted as the fallback-probe path";
            EXPECT_NEAR(both.ao.pixels[i], all.ao.pixels[i], 1e-6f) << "pixel " << i;
        } else {
            EXPECT_EQ(both.ao.pixels[i], one.ao.pixels[i]) << "pixel " << i;
            stillUncovered += both.path[i] == 3.0f ? 1 : 0;
        }
    }
    EXPECT_GT(rescued, both.ao.pixels.size() / 100) << "the view must hold points one candidate misses";
    EXPECT_EQ(double(stillUncovered) / double(both.ao.pixels.size()), all.shares.uncovered);
    EXPECT_GT(one.shares.uncovered, all.shares.uncovered);
    EXPECT_DOUBLE_EQ(both.shares.uncovered, all.shares.uncovered) << "six probes tried either way";
    EXPECT_DOUBLE_EQ(both.shares.fallbackProbe, one.shares.uncovered - all.shares.uncovered);
}

// A damaged probe (its AO no longer matches its checksum) is found when it is first loaded and left
// out: the frame is the one of a cache without it, and the walk goes on. Building the pass reads no
// AO at all: a cache whose every AO section is damaged still builds, then has no probe to show.
TEST_F(ResidencyGl, ADamagedProbeIsLeftOutAndTheGridBuildReadsNoAo) {
    const CacheReader full(full_), less(lessOne_);
    const std::size_t last = roomProbes().size() - 1;
    const std::vector<std::size_t> one{last}, every{0, 1, 2, 3, 4, 5};
    test::writeWithDamagedAo(full_, one, *dir_ / "one.cubeao");
    test::writeWithDamagedAo(full_, every, *dir_ / "every.cubeao");
    const CacheReader damaged(*dir_ / "one.cubeao"), allDamaged(*dir_ / "every.cubeao");
    EXPECT_TRUE(test::contains(test::errorMessage([&] { damaged.probe(last); }), "checksum mismatch"));

    const CameraView v = view({4.0f, 1.5f, 2.5f}, {6.0f, 0.5f, 0.5f});
    auto expected = renderer(pass(less));
    expected->render(v, 0);
    auto r = renderer(pass(damaged));
    auto& projection = dynamic_cast<ProbeProjectionPass&>(r->method());
    for (int f = 0; f < 3; ++f) {
        r->render(v, 0);
        EXPECT_EQ(r->readRawAo().pixels, expected->readRawAo().pixels) << "frame " << f;
    }
    EXPECT_EQ(projection.residency().stats().damaged, 1u) << "found once, then left out";
    EXPECT_FALSE(projection.source().isLive(ProbeId{std::uint32_t(last)}));
    EXPECT_EQ(projection.residency().stats().resident, last);

    std::unique_ptr<FrameRenderer> none;
    ASSERT_NO_THROW(none = renderer(pass(allDamaged)));
    none->render(v, 0);
    auto& empty = dynamic_cast<ProbeProjectionPass&>(none->method());
    EXPECT_EQ(empty.residency().stats().damaged, roomProbes().size());
    EXPECT_EQ(empty.residency().stats().resident, 0u);
    EXPECT_GT(empty.pixelShares().geometry, 0.5);
    EXPECT_EQ(empty.uncoveredFraction(), empty.pixelShares().geometry) << "no probe left: nothing covered";
}

}  // namespace
