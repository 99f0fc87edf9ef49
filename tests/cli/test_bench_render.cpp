// `cubeao bench render` end to end at a tiny size (the full-size figures: docs/BENCHMARKS.md).
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <functional>
#include <filesystem>
#include <string>
#include <utility>
#include <unistd.h>

#include <nlohmann/json.hpp>

#include "cli_run.h"
#include "cubeao/cache/bc4.h"
#include "cubeao/cache/synthetic_probes.h"
#include "cubeao/core/error.h"
#include "gl_fixture.h"
#include "test_paths.h"

namespace {

using cubeao::test::CliRun;
using cubeao::test::lastLine;
using cubeao::test::runCli;
using cubeao::test::runCommand;

// runCli with the wall time of the command around it.
std::pair<CliRun, double> timedCli(const std::function<CliRun()>& run) {
    const auto start = std::chrono::steady_clock::now();
    CliRun r = run();
    return {std::move(r), std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count()};
}

// A method's median pass timings, in milliseconds: each positive; `samples` of them fit inside the
// wall time of the command that measured them (a unit slip, µs or ns reported as ms, breaks that);
// and a sum is at least its parts (per frame ao + blur ≤ the whole frame, so the medians keep that
// order: a pass left out of a sum, or a sum taken twice, breaks it).
void expectPassTimings(const nlohmann::json& t, double samples, double wallMs, const std::string& what) {
    for (const char* pass : {"gbuffer", "ao", "blur", "composite", "ao_blur", "gpu_total"}) {
        EXPECT_GT(t[pass].get<double>(), 0.0) << what << " " << pass;
        EXPECT_LT(t[pass].get<double>() * samples, wallMs) << what << " " << pass << ": " << samples << " frames";
    }
    EXPECT_LE(t["ao"].get<double>(), t["ao_blur"].get<double>()) << what;
    EXPECT_LE(t["blur"].get<double>(), t["ao_blur"].get<double>()) << what;
    for (const char* pass : {"gbuffer", "composite", "ao_blur"})
        EXPECT_LE(t[pass].get<double>(), t["gpu_total"].get<double>()) << what << " " << pass;
}

TEST(BenchRenderCli, UsageErrors) {
    EXPECT_EQ(runCli("bench render --methods probes,ssao").code, 2);
    EXPECT_EQ(runCli("bench render --res 6").code, 2) << "BC5 needs a multiple of 4";
    EXPECT_EQ(runCli("bench render --probes 10,0").code, 2);
    EXPECT_EQ(runCli("bench render --frames 0").code, 2);
    EXPECT_EQ(runCli("bench render --gpu-budget-mb -1").code, 2);
    EXPECT_EQ(runCli("bench render --upload-mb -1").code, 2);
}

// 400 probes are 2,400 cube faces: more than the 2,048 array layers llvmpipe allows, so the sweep
// also checks that the projection's atlas (ProbeAtlasLayout) takes caches past that.
TEST_F(GlTest, BenchRenderTimesEveryMethodAndTheProbeSweep) {
    const auto [r, wallMs] = timedCli([] {
        return runCli("bench render --scene builtin:box-room --width 64 --height 36 --probes 400,10 --res 8 "
                      "--frames 1 --json");
    });
    ASSERT_EQ(r.code, 0) << r.out;
    const nlohmann::json j = lastLine(r.out);
    for (const char* method : {"probes", "gtao", "hbao", "alchemy"}) {
        const nlohmann::json& m = j["methods"][method];
        expectPassTimings(m["timings_ms"], 3.0, wallMs, method);  // 1 frame × 3 rounds (the default)
        EXPECT_GT(m["fetches_per_pixel"].get<double>(), 0.0) << method;
    }
    ASSERT_EQ(j["sweep"].size(), 2u);
    EXPECT_EQ(j["sweep"][0]["probes"].get<int>(), 10) << "counts in increasing order";
    EXPECT_EQ(j["sweep"][1]["probes"].get<int>(), 400);
    EXPECT_EQ(j["methods"]["probes"]["probes"].get<int>(), 400) << "\"probes\" is the largest count";
    for (const nlohmann::json& s : j["sweep"]) {
        expectPassTimings(s["timings_ms"], 3.0, wallMs, "sweep");
        EXPECT_GT(s["prep_ms"].get<double>(), 0.0);
        EXPECT_LT(s["prep_ms"].get<double>(), wallMs);
        EXPECT_GT(s["gpu_bytes"].get<double>(), 0.0);
        EXPECT_GT(s["cache_bytes"].get<double>(), 0.0);
        EXPECT_LT(s["uncovered_fraction"].get<double>(), 0.2) << s["probes"] << " probes: the projection reads them all";
    }
    // The targets are what the rows above say: recompute them from the reported timings.
    const nlohmann::json& t = j["targets"];
    const double ratio = j["methods"]["probes"]["timings_ms"]["ao_blur"].get<double>() /
                         j["methods"]["gtao"]["timings_ms"]["ao_blur"].get<double>();
    EXPECT_NEAR(t["probes_to_gtao_ao_blur"].get<double>(), ratio, 1e-9 * ratio);
    EXPECT_EQ(t["probes_within_gtao"].get<bool>(), ratio <= 1.0);
    const auto spread = [&](const char* pass) {  // max/min − 1 over the sweep
        const double a = j["sweep"][0]["timings_ms"][pass].get<double>(), b = j["sweep"][1]["timings_ms"][pass].get<double>();
        return std::max(a, b) / std::min(a, b) - 1.0;
    };
    EXPECT_NEAR(t["sweep_spread"].get<double>(), spread("gpu_total"), 1e-9) << "the whole frame";
    EXPECT_NEAR(t["sweep_spread_ao_blur"].get<double>(), spread("ao_blur"), 1e-9);
    EXPECT_NEAR(t["sweep_spread_ao"].get<double>(), spread("ao"), 1e-9);
    EXPECT_EQ(t["sweep_flat"].get<bool>(), spread("gpu_total") <= 0.2) << "issue 6: flat within 20 %";
}

// Issue 13's sweep at a tiny size: synthetic payloads, a budget that holds fewer slots than the larger
// cache has probes (so the pool streams and evicts), the residency's stats per count, the ratios to
// the smallest count, and --keep-caches keeping the files for a second run to reuse.
TEST_F(GlTest, BenchRenderSyntheticSweepUnderABudget) {
    namespace fs = std::filesystem;
    const fs::path dir = fs::temp_directory_path() / ("cubeao-test-bench-render-" + std::to_string(::getpid()));
    fs::remove_all(dir);
    const std::string args = "bench render --scene builtin:box-room --width 64 --height 36 --probes 300,10 --res 8 "
                             "--frames 3 --rounds 1 --methods probes --synthetic --gpu-budget-mb 0.72 --upload-mb 0.01 "
                             "--keep-caches " + dir.string() + " --json";
    const auto [r, wallMs] = timedCli([&] { return runCli(args); });
    ASSERT_EQ(r.code, 0) << r.out;
    const nlohmann::json j = lastLine(r.out);
    EXPECT_TRUE(j["sweep_caches"]["synthetic"].get<bool>());
    ASSERT_EQ(j["sweep"].size(), 2u);
    for (const nlohmann::json& s : j["sweep"]) {
        const std::size_t n = s["probes"].get<std::size_t>();
        const nlohmann::json& res = s["residency"];
        EXPECT_FALSE(s["cache_reused"].get<bool>()) << n;
        EXPECT_GT(res["slots"].get<std::size_t>(), 0u) << n;
        EXPECT_LE(res["resident"].get<std::size_t>(), std::min(n, res["slots"].get<std::size_t>())) << n;
        EXPECT_GE(res["loads"].get<std::size_t>(), res["resident"].get<std::size_t>()) << n;
        EXPECT_LE(res["max_frame_upload_bytes"].get<std::size_t>(), res["upload_bound_bytes"].get<std::size_t>()) << n;
        EXPECT_LE(s["gpu_bytes"].get<double>(), 0.72 * 1024 * 1024) << n << " probes: within the budget";
        expectPassTimings(s["timings_ms"], 3.0, wallMs, std::to_string(n) + " probes");  // 3 frames × 1 round
        EXPECT_NEAR(s["frame_ratio"].get<double>(), s["timings_ms"]["gpu_total"].get<double>() /
                    j["sweep"][0]["timings_ms"]["gpu_total"].get<double>(), 1e-9) << n;
        EXPECT_TRUE(fs::exists(dir / ("synthetic_8_" + std::to_string(n) + ".cubeao"))) << n << ": kept";
    }
    EXPECT_LT(j["sweep"][1]["residency"]["slots"].get<std::size_t>(), 300u) << "the budget holds part of the cache";
    EXPECT_LT(j["sweep"][0]["uncovered_fraction"].get<double>(), 0.05) << "10 synthetic probes see the surfaces";
    EXPECT_NEAR(j["targets"]["sweep_max_frame_ratio"].get<double>(),
                std::max(1.0, j["sweep"][1]["frame_ratio"].get<double>()), 1e-9);

    const CliRun again = runCli(args);
    ASSERT_EQ(again.code, 0) << again.out;
    // Named: in `for (x : lastLine(...)["sweep"])` the parsed object died before the loop (ASan).
    const nlohmann::json second = lastLine(again.out);
    for (const nlohmann::json& s : second["sweep"])
        EXPECT_TRUE(s["cache_reused"].get<bool>()) << s["probes"] << ": the kept cache is read again";
    fs::remove_all(dir);
}

// The made-up payloads both benchmarks time (cache/synthetic_probes.h): what they promise the
// projection (every distance far, confidence 1 as in a traced cache, varied AO), deterministic,
// round-robin over the positions.
TEST(SyntheticProbes, FarDistancesNonZeroConfidenceSharedRoundRobin) {
    using namespace cubeao;
    CacheParams params;
    params.res = 8;
    params.depthRes = 2;
    params.radius = 1.0f;
    const std::vector<ProbeRecord> a = syntheticPayloads(params, 50.0f, 3), b = syntheticPayloads(params, 50.0f, 3);
    ASSERT_EQ(a.size(), 3u);
    for (std::size_t k = 0; k < a.size(); ++k) {
        EXPECT_EQ(a[k].aoConfidence, b[k].aoConfidence) << "deterministic";
        EXPECT_EQ(a[k].depth, b[k].depth);
        ASSERT_EQ(a[k].aoConfidence.size(), aoSectionSize(params));
        ASSERT_EQ(a[k].depth.size(), depthSectionSize(params));
        EXPECT_EQ(a[k].maxDistance, 50.0f);
        for (std::size_t t = 0; t < a[k].depth.size(); t += 2)
            EXPECT_GE(a[k].depth[t] | a[k].depth[t + 1] << 8, 60000) << "r16unorm: beyond 0.9155 of maxDistance";
        std::vector<glm::vec2> rg;
        ASSERT_TRUE(bc::decodeBc5Cube(a[k].aoConfidence.data(), a[k].aoConfidence.size(), 8, rg));
        float lo = 1.0f, hi = 0.0f;
        for (const glm::vec2& v : rg) {
            EXPECT_EQ(v.y, 1.0f) << "confidence 1, as a traced bake's";
            lo = std::min(lo, v.x), hi = std::max(hi, v.x);
        }
        EXPECT_LT(lo, hi) << "varied AO";
    }
    EXPECT_NE(a[0].aoConfidence, a[1].aoConfidence) << "distinct payloads";
    const std::vector<glm::vec3> positions{glm::vec3(1.0f), glm::vec3(2.0f), glm::vec3(3.0f), glm::vec3(4.0f)};
    const std::vector<ProbeView> views = syntheticProbeViews(positions, a);
    ASSERT_EQ(views.size(), 4u);
    for (std::size_t i = 0; i < views.size(); ++i) {
        EXPECT_EQ(views[i].index, i);
        EXPECT_EQ(views[i].position, positions[i]);
        EXPECT_EQ(views[i].aoConfidence.data(), a[i % 3].aoConfidence.data()) << "shared, not copied";
    }
    params.depthFormat = DepthFormat::R32Float;
    EXPECT_THROW(syntheticPayloads(params, 50.0f, 1), Error);
}

// cubeao-gpubench, the binary that travels to a GPU machine: usage errors, then a tiny run through
// each clock. On llvmpipe "auto" is the measuring renderer (wall clock); "pipeline" runs the frame
// loop (no glFinish per pass, timer queries collected frames later), whose times mean nothing here,
// so only its bookkeeping is checked.
CliRun runGpuBench(const std::string& args) {
    return runCommand(std::string(cubeao::test::gpubenchBinary()) + " " + args + " 2>/dev/null");
}

TEST(GpuBenchCli, UsageErrors) {
    EXPECT_EQ(runGpuBench("--scene scene.obj").code, 2) << "only built-in scenes travel";
    EXPECT_EQ(runGpuBench("--res 6").code, 2);
    EXPECT_EQ(runGpuBench("--probes 0").code, 2);
    EXPECT_EQ(runGpuBench("--methods probes,hbao").code, 2);
    EXPECT_EQ(runGpuBench("--clock gpu").code, 2);
    EXPECT_EQ(runGpuBench("--frames 0").code, 2);
    EXPECT_EQ(runGpuBench("--gpu-budget-mb -1").code, 2);
}

TEST_F(GlTest, GpuBenchTimesTheProbesAndGtaoThroughEitherClock) {
    const std::string base = "--scene builtin:box-room --res 8 --width 64 --height 36 --warmup 1 --json ";
    const auto [wall, wallMs] = timedCli([&] { return runGpuBench(base + "--probes 30 --frames 2"); });
    ASSERT_EQ(wall.code, 0) << wall.out;
    const nlohmann::json w = lastLine(wall.out);
    EXPECT_EQ(w["clock"], "wall_clock_glfinish") << "llvmpipe's timer queries do not time the work";
    for (const char* method : {"probes", "gtao"}) {
        const nlohmann::json& m = w["methods"][method];
        EXPECT_EQ(m["timed_frames"].get<int>(), 2) << method;
        EXPECT_EQ(m["counted_frames"].get<int>(), 2) << method;
        expectPassTimings(m["timings_ms"], 2.0, wallMs, method);
        EXPECT_GT(m["fetches_per_pixel"].get<double>(), 2.0) << method;
    }
    const nlohmann::json& p = w["methods"]["probes"];
    EXPECT_EQ(p["residency"]["resident"].get<int>(), 30) << "no budget: every probe resident";
    EXPECT_EQ(p["residency"]["damaged"].get<int>(), 0);
    EXPECT_GT(p["gpu_bytes"].get<double>(), 0.0);
    EXPECT_LT(p["uncovered_fraction"].get<double>(), 0.05) << "synthetic distances: the probes see every surface";
    const nlohmann::json& t = w["targets"]["projection_blur_1080p_2000_probes_ms"];
    EXPECT_FALSE(t["applies"].get<bool>()) << "64x36, 30 probes, llvmpipe";
    EXPECT_DOUBLE_EQ(t["value"].get<double>(), p["timings_ms"]["ao_blur"].get<double>());

    const auto [loop, loopMs] = timedCli([&] {
        return runGpuBench(base + "--probes 300 --frames 6 --clock pipeline --methods probes --gpu-budget-mb 0.72 --upload-mb 0.01");
    });
    ASSERT_EQ(loop.code, 0) << loop.out;
    const nlohmann::json l = lastLine(loop.out);
    EXPECT_EQ(l["clock"], "frame_pipeline_timer_queries");
    const nlohmann::json& q = l["methods"]["probes"];
    EXPECT_FALSE(l["methods"].contains("gtao"));
    EXPECT_GE(q["timed_frames"].get<int>(), 1) << "the ring's results, collected frames later";
    EXPECT_LE(q["timed_frames"].get<int>(), 6);
    EXPECT_EQ(q["counted_frames"].get<int>(), 1) << "the counters are read once, after the loop";
    EXPECT_GT(q["issue_ms"]["max"].get<double>(), 0.0);
    EXPECT_LT(q["issue_ms"]["max"].get<double>(), loopMs) << "issue times in milliseconds, inside the run";
    EXPECT_GE(q["issue_ms"]["max"].get<double>(), q["issue_ms"]["median"].get<double>());
    EXPECT_LT(q["residency"]["slots"].get<int>(), 300) << "0.72 MiB holds part of the cache";
    EXPECT_LE(q["gpu_bytes"].get<double>(), 0.72 * 1024 * 1024);
}

}  // namespace
