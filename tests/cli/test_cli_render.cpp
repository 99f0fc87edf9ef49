// `cubeao render` end to end (tools/cubeao/cmd_render.cpp): usage errors, probes from a baked cache,
// a baseline's frames against `cubeao reference`.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <map>
#include <string>
#include <vector>

#include <glm/geometric.hpp>

#include <nlohmann/json.hpp>

#include "cli_run.h"
#include "cubeao/core/camera.h"
#include "damaged_cache.h"
#include "cubeao/core/image.h"
#include "cubeao/metrics/image_io.h"
#include "cubeao/reference/embree_scene.h"
#include "runtime_test_util.h"
#include "test_util.h"

namespace {

namespace fs = std::filesystem;
using namespace cubeao;
using namespace cubeao::test;

TEST(RenderCli, UsageErrors) {
    TempDir dir;
    const std::string out = " --out " + dir.path().string();
    EXPECT_EQ(runCli("render builtin:box-room --method probes" + out).code, 2) << "probes need --cache";
    EXPECT_EQ(runCli("render builtin:box-room --method probes --cache " + (dir.path() / "none.cubeao").string() + out).code, 1);
    EXPECT_EQ(runCli("render builtin:box-room --method ssao" + out).code, 2);
    EXPECT_EQ(runCli("render builtin:box-room --falloff linear" + out).code, 2);
    EXPECT_EQ(runCli("render builtin:box-room --blur -1" + out).code, 2);
    EXPECT_EQ(runCli("render builtin:box-room --frames 5:5" + out).code, 2);
    EXPECT_EQ(runCli("render builtin:box-room --gpu-budget-mb -1" + out).code, 2);
    EXPECT_EQ(runCli("render builtin:box-room --upload-mb -3" + out).code, 2);
    EXPECT_EQ(runCli("render builtin:box-room --fallback open" + out).code, 2);
    EXPECT_EQ(runCli("render /no/such/scene.obj --camera x.json" + out).code, 1);
}

// The fraction of the pixels of `frames` (box-room's own walk at w × h) whose surface point no probe
// sees: Embree primary rays, then a shadow ray from each probe to the point (lifted off its surface by
// a few epsilons towards the camera). The projection's uncovered_fraction estimates the same with
// depth cubes and a candidate grid, so the two agree up to pixels at occluder silhouettes (measured
// 0.0212 against 0.0170 for the two probes below at 32²; bound 0.01, 13 of the 1,296 pixels).
double embreeUncoveredFraction(const std::vector<glm::vec3>& probes, std::size_t frames, int w, int h) {
    const EmbreeScene rt(boxRoom());
    const float lift = 4.0f * rt.surfaceEpsilon();
    std::size_t hidden = 0;
    for (std::size_t f = 0; f < frames; ++f) {
        const PinholeCamera cam(boxRoomPath(), f, w, h);
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                const glm::vec3 dir = cam.rayDirection(x, y);
                const RayHit hit = rt.intersect(cam.eye, dir, 0.0f, std::numeric_limits<float>::infinity());
                if (!hit.hit) continue;  // no surface: not uncovered (the room is closed anyway)
                const glm::vec3 n = glm::dot(hit.normal, dir) > 0.0f ? -hit.normal : hit.normal;
                const glm::vec3 p = cam.eye + hit.t * dir + lift * n;
                bool seen = false;
                for (const glm::vec3& q : probes) {
                    const float d = glm::length(p - q);
                    seen = seen || !rt.occluded(q, (p - q) / d, 0.0f, d);
                }
                hidden += seen ? 0 : 1;
            }
    }
    return double(hidden) / double(frames * std::size_t(w) * std::size_t(h));
}

TEST_F(RuntimeGl, RenderProbesFromABakedCacheAndRefuseAnotherScenesCache) {
    TempDir dir;
    const std::string probes = dir.write("probes.json", R"({"version":1,"probes":[{"pos":[3,1.4,2.5]},{"pos":[6,1.5,1.5]}]})");
    const fs::path cache = dir.path() / "c.cubeao", render = dir.path() / "render";
    // 32² faces: at 8² the distance cubes are too coarse for this room's depth test (uncovered 0.22
    // against 0.017 truly hidden; 16²: 0.032; 32² and 64²: 0.021, the rest silhouette pixels).
    ASSERT_EQ(runCli("bake builtin:box-room --probes " + probes + " --out " + cache.string() + " --res 32 --spp 8 --device cpu").code, 0);
    const CliRun r = runCli("render builtin:box-room --method probes --cache " + cache.string() +
                            " --frames 0:2 --width 48 --height 27 --out " + render.string() + " --json");
    ASSERT_EQ(r.code, 0) << r.out;
    const auto j = lastLine(r.out);
    EXPECT_EQ(j["method"], "probes");
    EXPECT_EQ(j["probes"].get<int>(), 2);
    const double hidden = embreeUncoveredFraction({{3, 1.4f, 2.5f}, {6, 1.5f, 1.5f}}, 2, 48, 27);
    std::printf("[ info ] uncovered: projection %.4f, Embree visibility %.4f\n", j["uncovered_fraction"].get<double>(), hidden);
    EXPECT_NEAR(j["uncovered_fraction"].get<double>(), hidden, 0.01) << "pixels no probe sees";
    EXPECT_LT(j["uncovered_fraction"].get<double>(), 0.5);
    EXPECT_TRUE(fs::exists(render / "ao_0001.exr"));
    // Where the pixels came from: uncovered ones were filled by the screen-space fallback (all of
    // them), no probe was ever missing (everything resident), and the shares add up.
    const auto& px = j["pixels"];
    EXPECT_DOUBLE_EQ(px["screen_space"].get<double>(), px["uncovered"].get<double>());
    EXPECT_EQ(px["fallback_probe"].get<double>(), 0.0);
    EXPECT_GT(px["probes"].get<double>(), 0.5);
    EXPECT_EQ(j["residency"]["resident"].get<int>(), 2);
    EXPECT_EQ(j["residency"]["evictions"].get<int>(), 0);
    EXPECT_GT(j["peak_rss_mb"].get<double>(), 0.0);
    // A budget that cannot hold one probe: refused, saying what it would take.
    const CliRun tiny = runCli("render builtin:box-room --cache " + cache.string() + " --gpu-budget-mb 0.001 --frames 0:1 --out " +
                               (dir.path() / "tiny").string(), true);
    EXPECT_EQ(tiny.code, 1);
    EXPECT_NE(tiny.out.find("cannot hold one probe"), std::string::npos) << tiny.out;
    // The same cache against another scene: refused, naming both hashes.
    EXPECT_EQ(runCli("render builtin:cloister --method probes --cache " + cache.string() + " --frames 0:1 --out " +
                     (dir.path() / "wrong").string()).code, 1);
    EXPECT_EQ(runCli("render builtin:box-room --method probes --cache " + cache.string() + " --radius 0.3 --out " +
                     (dir.path() / "radius").string()).code, 2) << "the probes carry their own R";
    // A probe whose bytes fail their checksum: left out, the walk rendered from the other, and said
    // so on stderr after the summary and in render.json.
    const fs::path damaged = dir.path() / "damaged.cubeao";
    const std::vector<std::size_t> first{0};
    writeWithDamagedAo(cache, first, damaged);
    const std::string damagedArgs = "render builtin:box-room --cache " + damaged.string() +
                                    " --frames 0:2 --width 48 --height 27 --json --out " + (dir.path() / "damaged").string();
    const CliRun d = runCli(damagedArgs, true);
    ASSERT_EQ(d.code, 0) << d.out;
    EXPECT_NE(d.out.find("render: 1 damaged probe of 2 left out"), std::string::npos) << d.out;
    const auto dj = lastLine(d.out);
    EXPECT_EQ(dj["residency"]["damaged"].get<int>(), 1);
    EXPECT_EQ(dj["residency"]["resident"].get<int>(), 1);
    EXPECT_EQ(j["residency"]["damaged"].get<int>(), 0) << "the sound cache";
}

// Issue 6: "box room, one probe: render vs reference within a stated MAE". One traced probe in the
// middle of the room at R = 1 (so that AO matters), 3 frames of the room's walk. Measured: MAE 0.024,
// 8 % of the pixels uncovered (hidden from the probe behind the furniture; they take the GTAO
// fallback: left open, as before issue 13, they were most of the error, MAE 0.043), against an all-open image's MAE that the test computes. Bounds: MAE
// ≤ 0.06, uncovered ≤ 0.15, and clearly better than claiming everything open (that MAE is 0.115).
TEST_F(RuntimeGl, RenderOneProbeInTheBoxRoomAgainstTheReference) {
    TempDir dir;
    const std::string probes = dir.write("probes.json", R"({"version":1,"probes":[{"pos":[4,1.5,3]}]})");
    const fs::path cache = dir.path() / "c.cubeao", render = dir.path() / "render", reference = dir.path() / "reference";
    ASSERT_EQ(runCli("bake builtin:box-room --probes " + probes + " --out " + cache.string() +
                     " --res 32 --spp 128 --radius 1 --device cpu").code, 0);
    const std::string frames = " --frames 0:3 --width 96 --height 54";
    const CliRun r = runCli("render builtin:box-room --method probes --cache " + cache.string() + frames + " --out " +
                            render.string() + " --json");
    ASSERT_EQ(r.code, 0) << r.out;
    EXPECT_LE(lastLine(r.out)["uncovered_fraction"].get<double>(), 0.15);
    ASSERT_EQ(runCli("reference builtin:box-room --spp 256 --radius 1" + frames + " --out " + reference.string()).code, 0);
    const CliRun c = runCli("compare " + render.string() + " " + reference.string() + " --json");
    ASSERT_EQ(c.code, 0) << c.out;
    const double mae = lastLine(c.out)["mae"].get<double>();
    double open = 0.0;
    for (int f = 0; f < 3; ++f) {
        const Image ref = readImage(reference / ("ao_000" + std::to_string(f) + ".exr"));
        for (float v : ref.pixels) open += (1.0 - v) / double(ref.pixels.size() * 3);
    }
    EXPECT_LE(mae, 0.06);
    EXPECT_LT(mae, 0.7 * open) << "all-open MAE " << open;
    // Issue 13: the uncovered pixels take GTAO instead of "open" (the default); open does worse.
    const fs::path openRender = dir.path() / "open";
    ASSERT_EQ(runCli("render builtin:box-room --method probes --fallback none --cache " + cache.string() + frames +
                     " --out " + openRender.string()).code, 0);
    const CliRun co = runCli("compare " + openRender.string() + " " + reference.string() + " --json");
    ASSERT_EQ(co.code, 0) << co.out;
    const double maeOpen = lastLine(co.out)["mae"].get<double>();
    std::printf("[ info ] MAE with the GTAO fallback %.4f, with uncovered pixels open %.4f\n", mae, maeOpen);
    EXPECT_LT(mae, maeOpen);
}

// Issue 34 item 4 on the GPU: one probe in room A of builtin:two-rooms, every level baked; room B's
// walk with --depth-lift takes nothing from it at any level (every pixel falls back), without it
// strips along the 2 cm wall do (the kernel's CPU twin: tests/runtime/test_thin_wall.cpp).
TEST_F(RuntimeGl, RenderWithDepthLiftTakesNothingThroughAThinWall) {
    TempDir dir;
    const std::string probes = dir.write("probes.json", R"({"version":1,"probes":[{"pos":[2,1.5,2]}]})");
    const fs::path cache = dir.path() / "a.cubeao";
    ASSERT_EQ(runCli("bake builtin:two-rooms --probes " + probes + " --out " + cache.string() +
                     " --res 64 --spp 8 --radius 1 --levels max --device cpu").code, 0);
    const auto uncovered = [&](int level, const char* lift) {
        const CliRun r = runCli("render builtin:two-rooms --cache " + cache.string() + " --frames 0:6 --width 64 " +
                                "--height 36 --fallback none --level " + std::to_string(level) + " --depth-lift " + lift +
                                " --out " + (dir.path() / ("r" + std::to_string(level) + lift)).string() + " --json");
        EXPECT_EQ(r.code, 0) << r.out;
        return r.code == 0 ? lastLine(r.out)["uncovered_fraction"].get<double>() : -1.0;
    };
    for (int level : {0, 1, 2}) {  // 64², 32², 16²
        SCOPED_TRACE("level " + std::to_string(level));
        EXPECT_EQ(uncovered(level, "0.71"), 1.0);
    }
    EXPECT_LT(uncovered(2, "0"), 0.99) << "without the lift the coarse level leaks";
    EXPECT_EQ(runCli("render builtin:two-rooms --cache " + cache.string() + " --depth-lift -1 --out " +
                     (dir.path() / "bad").string()).code, 2);
}

TEST_F(RuntimeGl, RenderCliWritesFramesThatCompareWithTheReference) {
    TempDir dir;
    const fs::path render = dir.path() / "render", reference = dir.path() / "reference";
    const CliRun r = runCli("render builtin:box-room --method gtao --frames 0:2 --width 64 --height 36 --out " +
                            render.string() + " --json");
    ASSERT_EQ(r.code, 0) << r.out;
    const auto j = lastLine(r.out);
    EXPECT_EQ(j["method"], "gtao");
    ASSERT_EQ(j["frames"].size(), 2u);
    EXPECT_EQ(j["frames"][1]["index"].get<int>(), 1);
    // Timings for exactly the passes run, each positive in every frame; the summary holds their medians
    // over the frames (so between the frames' values), and those of AO + blur and of the GPU total.
    const std::map<std::string, std::vector<std::string>> summed = {
        {"gbuffer", {"gbuffer"}}, {"ao", {"ao"}}, {"blur", {"blur"}}, {"composite", {"composite"}},
        {"readback", {"readback"}}, {"ao_blur", {"ao", "blur"}}, {"gpu_total", {"gbuffer", "ao", "blur", "composite"}}};
    ASSERT_EQ(j["timings_ms"].size(), summed.size()) << j["timings_ms"];
    for (const auto& frame : j["frames"]) {
        ASSERT_EQ(frame["timings_ms"].size(), 5u) << frame["timings_ms"];
        for (const char* pass : {"gbuffer", "ao", "blur", "composite", "readback"})
            EXPECT_GT(frame["timings_ms"][pass].get<double>(), 0.0) << pass << " frame " << frame["index"];
    }
    for (const auto& [key, passes] : summed) {
        double lo = 1e300, hi = 0.0;
        for (const auto& frame : j["frames"]) {
            double v = 0.0;
            for (const std::string& pass : passes) v += frame["timings_ms"][pass].get<double>();
            lo = std::min(lo, v), hi = std::max(hi, v);
        }
        const double median = j["timings_ms"][key].get<double>();
        EXPECT_GE(median, lo * (1.0 - 1e-12)) << key;
        EXPECT_LE(median, hi * (1.0 + 1e-12)) << key;
    }
    EXPECT_GT(j["fetches_per_pixel"].get<double>(), 2.0);
    EXPECT_NEAR(j["radius"].get<double>(), boxRoom().defaultRadius(), 1e-6);
    for (const char* f : {"ao_0000.exr", "ao_0001.exr", "ao_0000.png", "shaded_0000.png", "shaded_0001.png"})
        EXPECT_TRUE(fs::exists(render / f)) << f;
    EXPECT_FALSE(fs::exists(render / "ao_0002.exr"));

    ASSERT_EQ(runCli("reference builtin:box-room --frames 0:2 --width 64 --height 36 --spp 32 --out " +
                     reference.string()).code, 0);
    const CliRun c = runCli("compare " + render.string() + " " + reference.string() + " --json");
    ASSERT_EQ(c.code, 0) << c.out;
    const auto m = lastLine(c.out);
    EXPECT_EQ(m["frames"].size(), 2u);
    EXPECT_LT(m["mae"].get<double>(), 0.2);
}

// Issue 11: a cache is only of use to the probes, so giving one makes them the default method; an
// explicit --method still wins (and is told the cache goes unused).
TEST_F(RuntimeGl, RenderWithACacheDefaultsToTheProbes) {
    TempDir dir;
    const std::string probes = dir.write("probes.json", R"({"version":1,"probes":[{"pos":[3,1.4,2.5]}]})");
    const fs::path cache = dir.path() / "c.cubeao";
    ASSERT_EQ(runCli("bake builtin:box-room --probes " + probes + " --out " + cache.string() + " --res 8 --spp 8 --device cpu").code, 0);
    const std::string rest = " --frames 0:1 --width 32 --height 18 --json --out ";
    const CliRun byDefault = runCli("render builtin:box-room --cache " + cache.string() + rest + (dir.path() / "a").string(), true);
    ASSERT_EQ(byDefault.code, 0) << byDefault.out;
    EXPECT_EQ(lastLine(byDefault.out)["method"], "probes");
    EXPECT_EQ(lastLine(byDefault.out)["probes"].get<int>(), 1);
    EXPECT_FALSE(contains(byDefault.out, "ignored")) << byDefault.out;
    const CliRun gtao = runCli("render builtin:box-room --method gtao --cache " + cache.string() + rest + (dir.path() / "b").string(), true);
    ASSERT_EQ(gtao.code, 0) << gtao.out;
    EXPECT_EQ(lastLine(gtao.out)["method"], "gtao");
    EXPECT_TRUE(contains(gtao.out, "--cache is used only by --method probes")) << gtao.out;
    const CliRun noCache = runCli("render builtin:box-room" + rest + (dir.path() / "c").string());
    ASSERT_EQ(noCache.code, 0) << noCache.out;
    EXPECT_EQ(lastLine(noCache.out)["method"], "gtao") << "without a cache: gtao";
}

}  // namespace
