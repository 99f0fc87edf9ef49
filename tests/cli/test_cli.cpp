// The cubeao binary end to end: exit codes, JSON as the last line, files written (DESIGN.md §5).
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <tuple>
#include <set>
#include <sstream>
#include <thread>
#include <vector>

#include <fcntl.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <glm/geometric.hpp>
#include <nlohmann/json.hpp>

#include "cubeao/cache/cache_file.h"
#include "cubeao/core/image.h"
#include "cubeao/metrics/image_io.h"
#include "cubeao/scene/import.h"
#include "cli_run.h"
#include "test_util.h"
#include "test_paths.h"

namespace {

namespace fs = std::filesystem;
using cubeao::test::TempDir;

using cubeao::test::CliRun;
using cubeao::test::lastLine;

CliRun run(const std::string& args, bool withStderr = false) { return cubeao::test::runCli(args, withStderr); }

TEST(Cli, InfoJsonFields) {
    const CliRun r = run("info builtin:cloister --json");
    ASSERT_EQ(r.code, 0) << r.out;
    const auto j = lastLine(r.out);
    for (const char* key : {"triangles", "vertices", "bbox", "problems", "peak_rss_mb"})
        EXPECT_TRUE(j.contains(key)) << key;
    EXPECT_GT(j["triangles"].get<int>(), 20000);
    // Every --json command reports its peak memory (printJson): at least the scene's own arrays.
    const double sceneMib = (j["vertices"].get<double>() * 24.0 + j["triangles"].get<double>() * 12.0) / (1 << 20);
    EXPECT_GT(j["peak_rss_mb"].get<double>(), sceneMib);
}

// The triangles of two loads, corner by corner: the same positions, normals within float rounding (a
// normal read from a file is normalised again). Vertex numbering may differ: OpenMesh's reader splits
// non-manifold vertices, which repair then merges.
void expectSameTriangles(const cubeao::Scene& a, const cubeao::Scene& b) {
    ASSERT_EQ(a.triangleCount(), b.triangleCount());
    std::size_t positions = 0, normals = 0;
    for (std::size_t i = 0; i < a.indices.size(); ++i) {
        positions += a.toFile(a.positions[a.indices[i]]) != b.toFile(b.positions[b.indices[i]]);
        normals += glm::length(a.normals[a.indices[i]] - b.normals[b.indices[i]]) > 1e-6f;
    }
    EXPECT_EQ(positions, 0u) << "of " << a.indices.size() << " corners";
    EXPECT_EQ(normals, 0u) << "of " << a.indices.size() << " corners";
}

// `info --write-obj`: the triangles as loaded, which load back to the same triangles and normals, from
// a built-in scene and from a georeferenced file far from its origin.
TEST(Cli, InfoWritesTheSceneAsAnObjThatLoadsBackToTheSameGeometry) {
    TempDir dir;
    const fs::path obj = dir.path() / "cloister.obj";
    const CliRun a = run("info builtin:cloister --json --write-obj " + obj.string());
    ASSERT_EQ(a.code, 0) << a.out;
    const CliRun b = run("info " + obj.string() + " --json");
    ASSERT_EQ(b.code, 0) << b.out;
    EXPECT_EQ(lastLine(b.out)["problems"]["normals_computed"], false);
    expectSameTriangles(cubeao::loadScene("builtin:cloister"), cubeao::loadScene(obj.string()));
    // 300 km from the file's origin: re-centred on load, written back in file coordinates.
    const fs::path far = dir.path() / "far.obj";
    {
        std::ofstream out(far);
        out << "v 300000 10 0\nv 300004 10 0\nv 300000 10 3\nv 300000 12 0\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";
    }
    const fs::path back = dir.path() / "far-again.obj";
    const CliRun c = run("info " + far.string() + " --json --write-obj " + back.string());
    ASSERT_EQ(c.code, 0) << c.out;
    ASSERT_TRUE(lastLine(c.out).contains("origin"));
    const CliRun d = run("info " + back.string() + " --json");
    ASSERT_EQ(d.code, 0) << d.out;
    EXPECT_EQ(lastLine(d.out)["bbox"], lastLine(c.out)["bbox"]);
    expectSameTriangles(cubeao::loadScene(far.string()), cubeao::loadScene(back.string()));
    // A cache has no triangles to write; a directory that does not exist is named.
    EXPECT_EQ(run("info " + far.string() + " --write-obj " + (dir.path() / "no/such/dir.obj").string()).code, 1);
    EXPECT_FALSE(fs::exists(dir.path() / "no"));
}

TEST(Cli, ReferenceWritesFramesNamedByPathIndex) {
    TempDir dir;
    const CliRun r = run("reference builtin:box-room --frames 5:7 --width 24 --height 16 --spp 4 --out " +
                      dir.path().string() + " --json");
    ASSERT_EQ(r.code, 0) << r.out;
    const auto j = lastLine(r.out);
    EXPECT_GT(j["rays_per_s"].get<double>(), 0.0);
    EXPECT_GT(j["peak_rss_mb"].get<double>(), 1.0);
    ASSERT_EQ(j["frames"].size(), 2u);
    EXPECT_EQ(j["frames"][0]["index"].get<int>(), 5);
    EXPECT_TRUE(fs::exists(dir.path() / "ao_0005.exr"));
    EXPECT_TRUE(fs::exists(dir.path() / "ao_0006.png"));
    EXPECT_FALSE(fs::exists(dir.path() / "ao_0000.exr"));
    // Same frames, same pixels: comparing the run with itself is exact.
    const CliRun c = run("compare " + dir.path().string() + " " + dir.path().string() + " --json");
    ASSERT_EQ(c.code, 0) << c.out;
    EXPECT_EQ(lastLine(c.out)["mae"].get<double>(), 0.0);
}

// compare --where-differs: the MAE of A and of C against B over exactly the pixels where A and C differ.
TEST(Cli, CompareWhereDiffers) {
    TempDir dir;
    // 16 × 16 (SSIM's window needs 11 × 11); C differs from A in two pixels.
    const auto frame = [&](const std::string& sub, float value, std::vector<std::pair<int, float>> changes) {
        fs::create_directories(dir.path() / sub);
        cubeao::Image image(16, 16);
        std::fill(image.pixels.begin(), image.pixels.end(), value);
        for (const auto& [i, v] : changes) image.pixels[std::size_t(i)] = v;
        cubeao::writeExr(dir.path() / sub / "ao_0000.exr", image);
    };
    frame("a", 0.5f, {});
    frame("b", 0.4f, {});
    frame("c", 0.5f, {{17, 1.0f}, {200, 0.45f}});
    const CliRun c = run("compare " + (dir.path() / "a").string() + " " + (dir.path() / "b").string() +
                         " --where-differs " + (dir.path() / "c").string() + " --json", true);
    ASSERT_EQ(c.code, 0) << c.out;
    const auto w = lastLine(c.out)["where_differs"];
    EXPECT_DOUBLE_EQ(w["fraction"].get<double>(), 2.0 / 256.0);
    EXPECT_NEAR(w["mae_a"].get<double>(), 0.1, 1e-6);
    EXPECT_NEAR(w["mae_c"].get<double>(), (0.6 + 0.05) / 2.0, 1e-6);
    EXPECT_EQ(run("compare " + (dir.path() / "a").string() + " " + (dir.path() / "b").string() + " --where-differs " +
                  (dir.path() / "none").string()).code, 1);
}

TEST(Cli, ExitCodes) {
    TempDir dir;
    EXPECT_EQ(run("").code, 2);
    EXPECT_EQ(run("reference builtin:box-room --frames 7:5 --out " + dir.path().string()).code, 2);
    EXPECT_EQ(run("reference /no/such/scene.obj --camera x.json --out " + dir.path().string()).code, 1);
    EXPECT_EQ(run("info builtin:nope").code, 1);
    EXPECT_EQ(run("reference builtin:box-room --falloff linear --out " + dir.path().string()).code, 2);
}

TEST(Cli, PlaceAlongThePathWritesAProbeSetBakeReads) {
    TempDir dir;
    const fs::path probes = dir.path() / "probes.json";
    const CliRun r = run("place builtin:box-room --method path --budget 3 --out " + probes.string() + " --json");
    ASSERT_EQ(r.code, 0) << r.out;
    EXPECT_EQ(lastLine(r.out)["probes"].get<int>(), 3);
    EXPECT_GT(lastLine(r.out)["coverage"].get<double>(), 0.0);
    const CliRun b = run("bake builtin:box-room --probes " + probes.string() + " --out " +
                         (dir.path() / "bake.cubeao").string() + " --res 4 --spp 2 --device cpu --json");
    ASSERT_EQ(b.code, 0) << b.out;
    EXPECT_EQ(lastLine(b.out)["probes"].get<int>(), 3);
    EXPECT_EQ(run("place builtin:box-room --method nearest --out " + probes.string()).code, 2);
    EXPECT_EQ(run("place builtin:box-room --method path --budget 0 --out " + probes.string()).code, 2);
    EXPECT_EQ(run("place builtin:box-room --coverage-target 1.5 --out " + probes.string()).code, 2);
    EXPECT_EQ(run("place builtin:box-room --budget -1 --out " + probes.string()).code, 2);
    EXPECT_EQ(run("place builtin:box-room --target-error -0.1 --out " + probes.string()).code, 2);
    // The reports name what they are (issue 31): the predicted walk MAE, the served share, the fine coverage.
    const nlohmann::json path = lastLine(r.out);
    EXPECT_GT(path["predicted_mae"].get<double>(), 0.0);
    EXPECT_GE(path["served"].get<double>(), path["coverage"].get<double>());
    const CliRun check = run("info builtin:box-room --probes " + probes.string() + " --camera builtin:box-room --json");
    ASSERT_EQ(check.code, 0) << check.out;
    EXPECT_NEAR(lastLine(check.out)["probe_check"]["predicted_mae"].get<double>(), path["predicted_mae"].get<double>(),
                1e-9) << "info --probes predicts what place reported for the same probes";
    // The viewer's live placement along the built-in walk: probes on the same objective, reported alike.
    const CliRun live = run("place builtin:box-room --method live --samples 4000 --out " + probes.string() + " --json");
    ASSERT_EQ(live.code, 0) << live.out;
    EXPECT_EQ(lastLine(live.out)["method"].get<std::string>(), "live");
    EXPECT_GT(lastLine(live.out)["probes"].get<int>(), 0);
    EXPECT_LT(lastLine(live.out)["predicted_mae"].get<double>(), path["predicted_mae"].get<double>())
        << "placing until a probe removes under 1 % beats 3 eyes of the walk";
    EXPECT_GT(lastLine(live.out)["figures"]["frames_counted"].get<int>(), 0);
    // The automatic stop holds for every probe of the set: a probe that removes under 1 % given the
    // others is dropped after the moves, and the summary says how many (the built-in walk drops one).
    const CliRun automatic = run("place builtin:box-room --camera builtin:box-room --samples 4000 --out " +
                                 probes.string() + " --json");
    ASSERT_EQ(automatic.code, 0) << automatic.out;
    EXPECT_EQ(lastLine(automatic.out)["stop"].get<std::string>(), "automatic");
    const int pruned = lastLine(automatic.out)["figures"]["pruned"].get<int>();
    EXPECT_GE(pruned, 1) << automatic.out;
    EXPECT_NE(automatic.out.find(std::to_string(pruned) + (pruned == 1 ? " probe that" : " probes that") +
                                 " removed under 1 % given the others dropped"),
              std::string::npos)
        << automatic.out;
    // A target error screen space alone meets: nothing to place, and the error says why.
    const CliRun target = run("place builtin:box-room --camera builtin:box-room --target-error 0.5 --samples 2000 --out " +
                              probes.string(), /*withStderr=*/true);
    EXPECT_EQ(target.code, 1) << target.out;
    EXPECT_NE(target.out.find("is met without any probe"), std::string::npos) << target.out;
    // A missing directory is made; one that cannot be (a file in the way) fails before any work.
    const fs::path nested = dir.path() / "a" / "b" / "probes.json";
    EXPECT_EQ(run("place builtin:box-room --method path --budget 2 --out " + nested.string()).code, 0);
    EXPECT_TRUE(fs::exists(nested));
    EXPECT_EQ(run("place builtin:box-room --method path --budget 2 --out " + (probes / "x.json").string()).code, 1);
}

TEST(Cli, BakeCpuWritesProbesAndVerifies) {
    TempDir dir;
    const std::string probes = dir.write("probes.json", R"({"version":1,"probes":[{"pos":[3,1.4,2.5]},{"pos":[6,1.5,1.5]}]})");
    const fs::path out = dir.path() / "bake.cubeao", dump = dir.path() / "dump";
    const CliRun r = run("bake builtin:box-room --probes " + probes + " --out " + out.string() + " --dump " +
                         dump.string() + " --res 8 --spp 8 --device cpu --verify --json");
    ASSERT_EQ(r.code, 0) << r.out;
    const auto j = lastLine(r.out);
    EXPECT_EQ(j["probes"].get<int>(), 2);
    EXPECT_GT(j["ms_per_probe"].get<double>(), 0.0);
    // The reference is independent (another seed, 4× the 8 rays): a correct traced bake differs from
    // it by the two estimates' noise, below 1.78× the reference's (test_bake_cpu.cpp CpuBakeVerify).
    EXPECT_EQ(j["verify_spp"].get<int>(), 32);
    EXPECT_GT(j["verify_noise"].get<double>(), 0.0);
    EXPECT_GT(j["verify_mae"].get<double>(), 0.1 * j["verify_noise"].get<double>());
    EXPECT_LT(j["verify_mae"].get<double>(), 1.78 * j["verify_noise"].get<double>());
    EXPECT_FALSE(j.contains("twin_mae")) << "on the CPU path the twin is the bake itself";
    EXPECT_FALSE(j.contains("timings_ms")) << "stage timings only with --timings";
    ASSERT_EQ(j["per_probe"].size(), 2u);
    EXPECT_TRUE(j["per_probe"][1].contains("verify_mae"));
    EXPECT_EQ(cubeao::CacheReader(out).probeCount(), 2u);
    EXPECT_TRUE(fs::exists(dump / "probe_0001_cross.png"));

    // A shard bakes every N-th probe, keeping the global probe index.
    const fs::path shard = dir.path() / "shard.cubeao";
    const CliRun s = run("bake builtin:box-room --probes " + probes + " --out " + shard.string() +
                         " --res 8 --estimator hsplit --device cpu --shard 1/2 --json");
    ASSERT_EQ(s.code, 0) << s.out;
    EXPECT_EQ(lastLine(s.out)["probes"].get<int>(), 1);
    const cubeao::CacheReader shardCache(shard);
    ASSERT_EQ(shardCache.probeCount(), 1u);
    EXPECT_EQ(shardCache.index(0), 1u);
}

// DESIGN.md §5: `--verify` measures the bake's error on every path. The GPU and CPU traced paths
// trace the same rays, so against the same independent reference their verify_mae differ by at most
// what the two bakes differ by, the GPU path's twin_mae (|gpu − ref| − |cpu − ref| ≤ |gpu − cpu| per
// texel; the CPU G-buffer's surface points differ from the GPU's by float rounding, hence a little
// slack), which is near 0 and well inside the reference's noise.
TEST(Cli, BakeVerifyAgreesOnGpuAndCpu) {
    TempDir dir;
    const std::string probes = dir.write("probes.json", R"({"version":1,"probes":[{"pos":[3,1.4,2.5]},{"pos":[6,1.5,1.5]}]})");
    const auto bake = [&](const char* device) {
        return run("bake builtin:box-room --probes " + probes + " --out " + (dir.path() / device).string() +
                       ".cubeao --res 16 --spp 16 --radius 1 --verify --json --device " + device,
                   true);
    };
    const CliRun gpu = bake("gpu");
    if (gpu.code != 0 && cubeao::test::contains(gpu.out, "no OpenGL 4.5 context")) GTEST_SKIP() << gpu.out;
    ASSERT_EQ(gpu.code, 0) << gpu.out;
    const CliRun cpu = bake("cpu");
    ASSERT_EQ(cpu.code, 0) << cpu.out;
    const auto g = lastLine(gpu.out), c = lastLine(cpu.out);
    std::printf("verify_mae gpu %.5f cpu %.5f (noise %.5f), twin_mae %.5f\n", g["verify_mae"].get<double>(),
                c["verify_mae"].get<double>(), c["verify_noise"].get<double>(), g["twin_mae"].get<double>());
    EXPECT_GT(c["verify_mae"].get<double>(), 0.0);
    const double noise = c["verify_noise"].get<double>(), twin = g["twin_mae"].get<double>();
    EXPECT_LE(twin, 0.005);  // grazing-ray flips only (docs/ALGORITHMS.md)
    EXPECT_NEAR(g["verify_mae"].get<double>(), c["verify_mae"].get<double>(), twin + 0.05 * noise);
    EXPECT_LT(twin + 0.05 * noise, 0.25 * noise) << "the bound must be tighter than the noise to mean anything";
    EXPECT_FALSE(c.contains("twin_mae"));
}

TEST(Cli, BakeRejectsBadInput) {
    TempDir dir;
    const std::string good = dir.write("good.json", R"({"version":1,"probes":[{"pos":[3,1.4,2.5]}]})");
    const std::string out = " --out " + (dir.path() / "out.cubeao").string() + " --device cpu --res 8";
    EXPECT_EQ(run("bake builtin:box-room --probes " + good + out + " --estimator ssao").code, 2);
    EXPECT_EQ(run("bake builtin:box-room --probes " + good + out + " --res 2").code, 2);
    EXPECT_EQ(run("bake builtin:box-room --probes " + good + out + " --res 10").code, 2);  // BC5: multiple of 4
    EXPECT_EQ(run("bake builtin:box-room --probes " + good + out + " --depth-format r8").code, 2);
    EXPECT_EQ(run("bake builtin:box-room --probes " + good + out + " --shard 2/2").code, 2);
    EXPECT_EQ(run("bake builtin:box-room --probes " + good + out + " --device tpu").code, 2);
    EXPECT_EQ(run("bake builtin:box-room --probes " + dir.write("v2.json", R"({"version":2,"probes":[]})") + out).code, 1);
    // 2^32 + 1: read as an int it wrapped to version 1 and passed.
    EXPECT_EQ(run("bake builtin:box-room --probes " + dir.write("v-wrap.json", R"({"version":4294967297,"probes":[{"pos":[3,1.4,2.5]}]})") + out).code, 1);
    EXPECT_EQ(run("bake builtin:box-room --probes " + dir.write("nan.json", R"({"version":1,"probes":[{"pos":[1,"x",2]}]})") + out).code, 1);
    EXPECT_EQ(run("bake builtin:box-room --probes " + (dir.path() / "missing.json").string() + out).code, 1);
}

// ---- the probe cache: bake → info, resume, shards → merge, damage ---------------------------------

using cubeao::CacheParams;
using cubeao::CacheReader;
using cubeao::ProbeView;
using cubeao::WriteOptions;
using cubeao::test::contains;

std::string probeSet(const TempDir& dir, const std::string& name, int count) {
    const char* positions[] = {"[3,1.4,2.5]", "[6,1.5,1.5]", "[1.5,1.2,4]", "[7,1,3.5]"};
    std::string json = R"({"version":1,"probes":[)";
    for (int i = 0; i < count; ++i) json += std::string(i ? "," : "") + R"({"pos":)" + positions[i] + "}";
    return dir.write(name, json + "]}");
}

// A tiny CPU bake of the box room's `probes` into dir/out (the shard and merge tests).
CliRun smallBake(const TempDir& dir, const std::string& probes, const std::string& out, const std::string& extra) {
    return run("bake builtin:box-room --probes " + probes + " --out " + (dir.path() / out).string() +
               " --res 8 --spp 4 --device cpu " + extra);
}

std::vector<std::uint8_t> fileBytes(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), {}};
}

// Probe bytes (AO and depth sections) by index, to compare caches whatever their table order.
std::map<std::uint32_t, std::vector<std::uint8_t>> probesByIndex(const fs::path& p) {
    const CacheReader cache(p);
    std::map<std::uint32_t, std::vector<std::uint8_t>> out;
    for (std::size_t i = 0; i < cache.probeCount(); ++i) {
        const cubeao::ProbeView v = cache.probe(i);
        auto& bytes = out[v.index];
        bytes.assign(v.aoConfidence.begin(), v.aoConfidence.end());
        bytes.insert(bytes.end(), v.depth.begin(), v.depth.end());
    }
    return out;
}

TEST(CliCache, BakeWritesACacheThatInfoDescribes) {
    TempDir dir;
    const fs::path probes = dir.path() / "probes.json", cache = dir.path() / "box.cubeao";
    ASSERT_EQ(run("place builtin:box-room --method path --budget 3 --out " + probes.string()).code, 0);
    const CliRun b = run("bake builtin:box-room --probes " + probes.string() + " --out " + cache.string() +
                         " --res 16 --spp 8 --device cpu --timings --json");
    ASSERT_EQ(b.code, 0) << b.out;
    const auto baked = lastLine(b.out);
    EXPECT_EQ(baked["probes"].get<int>(), 3);
    EXPECT_GE(baked["ao_psnr"].get<double>(), 40.0);
    EXPECT_TRUE(baked["timings_ms"].contains("encode"));

    const CliRun i = run("info " + cache.string() + " --json");
    ASSERT_EQ(i.code, 0) << i.out;
    const auto info = lastLine(i.out);
    EXPECT_EQ(info["probes"].get<int>(), 3);
    EXPECT_EQ(info["res"].get<int>(), 16);
    EXPECT_EQ(info["depth_res"].get<int>(), 4);
    EXPECT_EQ(info["depth_format"].get<std::string>(), "r16unorm");
    EXPECT_EQ(info["estimator"].get<std::string>(), "traced");
    EXPECT_EQ(info["spp"].get<int>(), 8);
    EXPECT_EQ(info["scene_hash"], lastLine(run("info builtin:box-room --json").out)["hash"]);
    // Header 128 + 8, per probe a 64-byte entry, 6·16² / 2 BC4 bytes (traced: AO alone) and 6·4²
    // r16unorm texels.
    EXPECT_EQ(info["ao_format"].get<std::string>(), "bc4");
    EXPECT_EQ(info["format_version"].get<int>(), 4);
    const double expected = (136.0 + 3 * (64 + 6 * 256 / 2 + 6 * 16 * 2)) / (3 * 6 * 256);
    EXPECT_DOUBLE_EQ(info["bytes_per_texel"].get<double>(), expected);
    EXPECT_DOUBLE_EQ(baked["bytes_per_texel"].get<double>(), expected);
    EXPECT_FALSE(info.contains("verified"));
}

// `bake --ao`: traced stores BC4 by default and BC5 when asked; BC4 for an estimator with a
// confidence is a usage error; a BC5 traced cache (an earlier build's) resumes with --ao bc5, the
// default names that way; `merge --ao bc4` converts it into the cache a BC4 bake writes, byte for byte.
TEST(CliCache, BakeAndMergeChooseTheAoFormat) {
    TempDir dir;
    const std::string probes = probeSet(dir, "two.json", 2), four = probeSet(dir, "four.json", 4);
    const fs::path bc5 = dir.path() / "t5.cubeao", bc4 = dir.path() / "t4.cubeao", merged = dir.path() / "m.cubeao";
    const std::string traced = "bake builtin:box-room --res 8 --spp 4 --device cpu --probes ";
    ASSERT_EQ(run(traced + four + " --out " + bc4.string()).code, 0);
    const CliRun b5 = run(traced + probes + " --out " + bc5.string() + " --ao bc5 --json");
    ASSERT_EQ(b5.code, 0) << b5.out;
    EXPECT_EQ(lastLine(b5.out)["settings"]["ao_format"], "bc5") << b5.out;
    EXPECT_EQ(CacheReader(bc4).params().aoFormat, cubeao::AoFormat::Bc4);
    EXPECT_EQ(CacheReader(bc5).params().aoFormat, cubeao::AoFormat::Bc5);

    const CliRun hsplit = run("bake builtin:box-room --res 8 --estimator hsplit --device cpu --ao bc4 --probes " + probes +
                                  " --out " + (dir.path() / "h.cubeao").string(),
                              true);
    EXPECT_EQ(hsplit.code, 2);
    EXPECT_TRUE(contains(hsplit.out, "--ao bc4") && contains(hsplit.out, "use bc5")) << hsplit.out;
    EXPECT_EQ(run("bake builtin:box-room --ao bc6 --probes " + probes + " --out " + bc5.string(), true).code, 2);

    const CliRun resumed = run(traced + four + " --out " + bc5.string(), true);
    EXPECT_EQ(resumed.code, 1);
    EXPECT_TRUE(contains(resumed.out, "ao format bc5 vs bc4") && contains(resumed.out, "--ao bc5 resumes it")) << resumed.out;
    ASSERT_EQ(run(traced + four + " --out " + bc5.string() + " --ao bc5").code, 0);
    const CliRun m = run("merge " + merged.string() + " " + bc5.string() + " --ao bc4 --json");
    ASSERT_EQ(m.code, 0) << m.out;
    EXPECT_EQ(lastLine(m.out)["ao_format"], "bc4");
    EXPECT_EQ(fileBytes(merged), fileBytes(bc4)) << "BC5 -> BC4 is the red half of each block: what the bake writes";
}

// bake --levels: the chain on disk (format 5, info names it), level 0 the bake without levels; the
// wrong count is a usage error naming what the resolution allows; resuming with another count is
// refused; export writes level 0.
TEST(CliCache, BakeStoresLevelsOfDetail) {
    TempDir dir;
    const std::string probes = probeSet(dir, "two.json", 2);
    const fs::path plain = dir.path() / "p.cubeao", levels = dir.path() / "l.cubeao";
    const std::string bake = "bake builtin:box-room --res 32 --spp 4 --device cpu --probes " + probes;
    ASSERT_EQ(run(bake + " --out " + plain.string()).code, 0);
    const CliRun b = run(bake + " --out " + levels.string() + " --levels max --json");
    ASSERT_EQ(b.code, 0) << b.out;
    EXPECT_EQ(lastLine(b.out)["settings"]["levels"], 2) << b.out;
    const CacheReader p(plain), l(levels);
    EXPECT_EQ(l.formatVersion(), 5u);
    EXPECT_EQ(l.params().levels, 2u);
    for (std::size_t i = 0; i < 2; ++i) {
        const cubeao::ProbeView a = p.probe(i), b0 = levelView(l.probe(i), l.params(), 0);
        EXPECT_TRUE(std::equal(a.aoConfidence.begin(), a.aoConfidence.end(), b0.aoConfidence.begin(), b0.aoConfidence.end()));
        EXPECT_TRUE(std::equal(a.depth.begin(), a.depth.end(), b0.depth.begin(), b0.depth.end()));
    }
    const CliRun info = run("info " + levels.string() + " --json");
    ASSERT_EQ(info.code, 0) << info.out;
    EXPECT_TRUE(contains(info.out, "2 levels of detail per probe, 32² to 16² faces")) << info.out;
    EXPECT_EQ(lastLine(info.out)["levels"], 2);

    const CliRun tooMany = run(bake + " --out " + (dir.path() / "x.cubeao").string() + " --levels 3", true);
    EXPECT_EQ(tooMany.code, 2);
    EXPECT_TRUE(contains(tooMany.out, "--levels 3: expected 1..2 at res 32")) << tooMany.out;
    EXPECT_EQ(run(bake + " --out " + (dir.path() / "x.cubeao").string() + " --levels two", true).code, 2);
    const CliRun resumed = run(bake + " --out " + plain.string() + " --levels 2", true);
    EXPECT_EQ(resumed.code, 1);
    EXPECT_TRUE(contains(resumed.out, "levels 1 vs 2") || contains(resumed.out, "levels 2 vs 1")) << resumed.out;

    // Fewer levels are a prefix of each section: merge --levels 1 gives the bake without levels back;
    // more than the inputs have is refused, naming bake --levels.
    const fs::path one = dir.path() / "one.cubeao";
    const CliRun m = run("merge " + one.string() + " " + levels.string() + " --levels 1 --json");
    ASSERT_EQ(m.code, 0) << m.out;
    EXPECT_EQ(lastLine(m.out)["levels"], 1);
    EXPECT_EQ(fileBytes(one), fileBytes(plain));
    const CliRun more =
        run("merge " + (dir.path() / "more.cubeao").string() + " " + plain.string() + " --levels 2", true);
    EXPECT_EQ(more.code, 1);
    EXPECT_TRUE(contains(more.out, "cannot merge 2 levels of detail from a cache of 1") &&
                contains(more.out, "bake --levels 2"))
        << more.out;
    EXPECT_FALSE(fs::exists(dir.path() / "more.cubeao"));

    const fs::path ep = dir.path() / "ep", el = dir.path() / "el";
    ASSERT_EQ(run("export " + plain.string() + " --out " + ep.string()).code, 0);
    ASSERT_EQ(run("export " + levels.string() + " --out " + el.string()).code, 0);
    EXPECT_EQ(fileBytes(ep / "probe_0000_ao.dds"), fileBytes(el / "probe_0000_ao.dds"));
    EXPECT_EQ(fileBytes(ep / "probe_0001_distance.dds"), fileBytes(el / "probe_0001_distance.dds"));
}

TEST(CliCache, BakeResumesAndRefusesAnotherBake) {
    TempDir dir;
    const fs::path cache = dir.path() / "box.cubeao";
    const std::string bake = "bake builtin:box-room --out " + cache.string() + " --res 8 --estimator hsplit --device cpu";
    ASSERT_EQ(run(bake + " --probes " + probeSet(dir, "two.json", 2)).code, 0);
    const auto before = probesByIndex(cache);
    ASSERT_EQ(before.size(), 2u);

    const CliRun more = run(bake + " --probes " + probeSet(dir, "four.json", 4) + " --json");
    ASSERT_EQ(more.code, 0) << more.out;
    const auto j = lastLine(more.out);
    EXPECT_EQ(j["probes"].get<int>(), 2);  // baked now
    EXPECT_EQ(j["probes_skipped"].get<int>(), 2);
    EXPECT_EQ(j["probes_in_cache"].get<int>(), 4);
    const auto after = probesByIndex(cache);
    ASSERT_EQ(after.size(), 4u);
    EXPECT_EQ(after.at(0), before.at(0));  // the first two untouched
    EXPECT_EQ(after.at(1), before.at(1));
    EXPECT_TRUE(CacheReader(cache).probe(3).depth.size() > 0);

    const auto bytes = fileBytes(cache);
    CliRun other = run(bake + " --probes " + probeSet(dir, "four2.json", 4) + " --seed 3", true);
    EXPECT_EQ(other.code, 1);
    EXPECT_TRUE(contains(other.out, "other bake parameters") && contains(other.out, "seed 0 vs 3") &&
                contains(other.out, "choose another --out or delete the file"))
        << other.out;
    other = run("bake builtin:cloister --probes " + probeSet(dir, "four3.json", 4) + " --out " + cache.string() +
                    " --res 8 --estimator hsplit --device cpu",
                true);
    EXPECT_EQ(other.code, 1);
    EXPECT_TRUE(contains(other.out, "scene hash")) << other.out;
    const std::string moved = dir.write("moved.json", R"({"version":1,"probes":[{"pos":[3,1.4,2.5]},{"pos":[5,1,1]}]})");
    other = run(bake + " --probes " + moved, true);
    EXPECT_EQ(other.code, 1);
    EXPECT_TRUE(contains(other.out, "probe set changed")) << other.out;
    EXPECT_EQ(fileBytes(cache), bytes);  // refused runs leave the cache as it was

    other = run("bake builtin:box-room --out " + dir.path().string() + " --probes " + moved + " --device cpu", true);
    EXPECT_EQ(other.code, 1);
    EXPECT_TRUE(contains(other.out, "--out is a directory")) << other.out;
}

// Issue 16: merging and checking a cache never hold it in memory. A 338 MiB cache (one payload repeated,
// so the test itself stays small) is merged by `cubeao merge` and checked by `info --verify`, whose peak
// resident sets must stay within a few of the 64 MiB release windows above a merge of a one-probe cache:
// before the mapped pages were released both grew by the whole file.
TEST(CliCache, MergeAndVerifyOfALargeCacheKeepLittleOfItResident) {
    if (cubeao::test::kAddressSanitizer) GTEST_SKIP() << "ASan's shadow memory and quarantine dwarf the figure";
    TempDir dir;
    CacheParams params;
    params.sceneHash = 0x1234;
    params.res = 256;
    params.depthRes = 64;
    params.estimator = 2;
    params.spp = 1;
    params.radius = 1.0f;
    const std::vector<std::uint8_t> ao(cubeao::aoSectionSize(params), 0x5a);
    const std::vector<std::uint8_t> depth(cubeao::depthSectionSize(params), 0x33);
    const auto write = [&](const fs::path& file, std::uint32_t count) {
        std::vector<ProbeView> probes;
        for (std::uint32_t i = 0; i < count; ++i)
            probes.push_back({i, glm::vec3(float(i), 0.0f, 0.0f), 2.0f, ao, depth});
        cubeao::writeCache(file, params, probes);
    };
    write(dir.path() / "small.cubeao", 1);
    write(dir.path() / "large.cubeao", 800);
    const double fileMib = double(fs::file_size(dir.path() / "large.cubeao")) / (1 << 20);
    ASSERT_GT(fileMib, 300.0);
    const auto mergedRss = [&](const std::string& in) {
        const CliRun r = run("merge " + (dir.path() / ("out-" + in)).string() + " " + (dir.path() / in).string() +
                             " --json");
        EXPECT_EQ(r.code, 0) << r.out;
        return r.code == 0 ? lastLine(r.out)["peak_rss_mb"].get<double>() : 0.0;
    };
    const double small = mergedRss("small.cubeao"), large = mergedRss("large.cubeao");
    const double bound = small + 2.5 * double(WriteOptions::kReleaseBytes >> 20);
    EXPECT_LT(large, bound)
        << "merge of a " << fileMib << " MiB cache peaked at " << large << " MiB (one probe: " << small << ")";
    // `info --verify` reads every byte of it too (probe checksums, then the file checksum).
    const CliRun verify = run("info " + (dir.path() / "large.cubeao").string() + " --verify --json");
    ASSERT_EQ(verify.code, 0) << verify.out;
    EXPECT_LT(lastLine(verify.out)["peak_rss_mb"].get<double>(), bound)
        << "info --verify of a " << fileMib << " MiB cache";
    // And it is still the same cache, byte for byte (streamed, not fileBytes: 338 MiB twice).
    std::ifstream a(dir.path() / "large.cubeao", std::ios::binary), b(dir.path() / "out-large.cubeao", std::ios::binary);
    EXPECT_TRUE(std::equal(std::istreambuf_iterator<char>(a), {}, std::istreambuf_iterator<char>(b), {}));
}

TEST(CliCache, ShardsMergeIntoTheUnshardedCache) {
    TempDir dir;
    const std::string probes = probeSet(dir, "probes.json", 3);
    const auto bake = [&](const std::string& out, const std::string& extra) {
        return smallBake(dir, probes, out, extra);
    };
    ASSERT_EQ(bake("all.cubeao", "").code, 0);
    ASSERT_EQ(bake("s1.cubeao", "--shard 1/2").code, 0);
    ASSERT_EQ(bake("s0.cubeao", "--shard 0/2").code, 0);
    const std::string s0 = (dir.path() / "s0.cubeao").string(), s1 = (dir.path() / "s1.cubeao").string();
    const fs::path merged = dir.path() / "merged.cubeao";
    const CliRun m = run("merge " + merged.string() + " " + s1 + " " + s0 + " --json");
    ASSERT_EQ(m.code, 0) << m.out;
    EXPECT_EQ(lastLine(m.out)["probes"].get<int>(), 3);
    EXPECT_EQ(lastLine(m.out)["out"].get<std::string>(), merged.string());
    EXPECT_EQ(probesByIndex(merged), probesByIndex(dir.path() / "all.cubeao"));
    EXPECT_EQ(fileBytes(merged), fileBytes(dir.path() / "all.cubeao")) << "merge sorts by index";

    CliRun bad = run("merge " + (dir.path() / "x.cubeao").string() + " " + s0 + " " + s0, true);
    EXPECT_EQ(bad.code, 1);
    EXPECT_TRUE(contains(bad.out, "overlapping shards")) << bad.out;
    ASSERT_EQ(bake("other.cubeao", "--shard 1/2 --seed 5").code, 0);
    bad = run("merge " + (dir.path() / "x.cubeao").string() + " " + s0 + " " + (dir.path() / "other.cubeao").string(), true);
    EXPECT_EQ(bad.code, 1);
    EXPECT_TRUE(contains(bad.out, "seed 0 vs 5")) << bad.out;
    EXPECT_FALSE(fs::exists(dir.path() / "x.cubeao"));
}

// `merge --probes`: a cluster bake merges whatever shards exist (tools/slurm/merge.sbatch), so a failed
// shard must end in a refusal naming the missing probes and shards, with OUT untouched.
TEST(CliCache, MergeWithProbesRefusesAnIncompleteSet) {
    TempDir dir;
    const std::string probes = probeSet(dir, "probes.json", 4);
    const auto bake = [&](const std::string& out, const std::string& extra) {
        return smallBake(dir, probes, out, extra);
    };
    ASSERT_EQ(bake("all.cubeao", "").code, 0);
    ASSERT_EQ(bake("s0.cubeao", "--shard 0/2").code, 0);
    ASSERT_EQ(bake("s1.cubeao", "--shard 1/2").code, 0);
    const std::string s0 = (dir.path() / "s0.cubeao").string(), s1 = (dir.path() / "s1.cubeao").string();
    const fs::path out = dir.path() / "out.cubeao";
    const std::string outBytes = "not a cache: a refused merge leaves it as it is";
    dir.write("out.cubeao", outBytes);
    const auto outUntouched = [&] {
        return fileBytes(out) == std::vector<std::uint8_t>(outBytes.begin(), outBytes.end());
    };

    CliRun r = run("merge " + out.string() + " " + s0 + " --probes " + probes + " --shards 2", true);
    EXPECT_EQ(r.code, 1);
    EXPECT_TRUE(contains(r.out, "incomplete: 2 of 4 probes missing: 1, 3 (shard 1/2)")) << r.out;
    EXPECT_TRUE(contains(r.out, out.string() + " not written")) << r.out;
    EXPECT_TRUE(outUntouched());
    r = run("merge " + out.string() + " " + s1 + " --probes " + probes, true);  // without --shards: no shard named
    EXPECT_EQ(r.code, 1);
    EXPECT_TRUE(contains(r.out, "incomplete: 2 of 4 probes missing: 0, 2\n")) << r.out;
    EXPECT_TRUE(outUntouched());

    // Probes the set does not have, and probes baked at other positions (another probes.json).
    r = run("merge " + out.string() + " " + s0 + " " + s1 + " --probes " + probeSet(dir, "three.json", 3), true);
    EXPECT_EQ(r.code, 1);
    EXPECT_TRUE(contains(r.out, s1 + ": probe 3 is not in")) << r.out;
    const std::string moved = dir.write("moved.json", R"({"version":1,"probes":[{"pos":[3,1.4,2.5]},)"
                                                      R"({"pos":[6,1.5,1.5]},{"pos":[1.5,1.2,4]},{"pos":[7,1,3]}]})");
    r = run("merge " + out.string() + " " + s0 + " " + s1 + " --probes " + moved, true);
    EXPECT_EQ(r.code, 1);
    EXPECT_TRUE(contains(r.out, s1 + ": probe 3 at (7, 1, 3.5)")) << r.out;
    EXPECT_TRUE(outUntouched());
    EXPECT_EQ(run("merge " + out.string() + " " + s0 + " --shards 2").code, 2) << "--shards needs --probes";

    r = run("merge " + out.string() + " " + s1 + " " + s0 + " --probes " + probes + " --shards 2 --json");
    ASSERT_EQ(r.code, 0) << r.out;
    EXPECT_EQ(lastLine(r.out)["probes"].get<int>(), 4);
    EXPECT_TRUE(lastLine(r.out)["complete"].get<bool>());
    EXPECT_EQ(fileBytes(out), fileBytes(dir.path() / "all.cubeao"));
}

TEST(CliCache, InfoVerifyFindsDamage) {
    TempDir dir;
    const fs::path cache = dir.path() / "box.cubeao", damaged = dir.path() / "damaged.cubeao";
    ASSERT_EQ(run("bake builtin:box-room --probes " + probeSet(dir, "p.json", 2) + " --out " + cache.string() +
                  " --res 8 --estimator hsplit --device cpu")
                  .code,
              0);
    const CliRun ok = run("info " + cache.string() + " --verify --json");
    ASSERT_EQ(ok.code, 0) << ok.out;
    EXPECT_TRUE(lastLine(ok.out)["verified"].get<bool>());

    auto bytes = fileBytes(cache);
    const std::size_t inProbe1 = 128 + 2 * 64 + (6 * 64 + 6 * 4 * 2 + 15) / 16 * 16 + 10;
    bytes[inProbe1] ^= 0x40;
    std::ofstream(damaged, std::ios::binary).write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
    const CliRun bad = run("info " + damaged.string() + " --verify --json");
    EXPECT_EQ(bad.code, 1);
    const auto j = lastLine(bad.out);
    EXPECT_FALSE(j["verified"].get<bool>());
    EXPECT_TRUE(contains(j["damage"].get<std::string>(), "probe 1: checksum mismatch")) << j["damage"];
    EXPECT_EQ(run("info " + damaged.string() + " --json").code, 0) << "without --verify only the header and table are read";
    EXPECT_EQ(run("info builtin:box-room --verify").code, 2);
}

// The benchmarks behind the cache's choices run and report (figures: docs/BENCHMARKS.md).
TEST(CliCache, BenchDepthAndBenchCacheReport) {
    TempDir dir;
    const CliRun d = run("bench depth --scene builtin:box-room --res 16 --probes 2 --frames 1 --width 16 --height 9 "
                         "--divisor 1 --divisor 4 --json");
    ASSERT_EQ(d.code, 0) << d.out;
    const auto j = lastLine(d.out);
    EXPECT_GT(j["pairs_visible"].get<int>(), 0);
    EXPECT_EQ(j["variants"].size(), 3u + 6u);  // res/1: 3 formats; res/4: 3 formats × 2 filters
    EXPECT_EQ(j["default"]["bake"]["variant"].get<std::string>(), "res/4 r16unorm min");
    // A larger tolerance accepts more (false hidden never rises), the slope-scaled bias hides fewer
    // grazing pairs than none at the same tolerance, the lifted second half (on by default in the
    // bench's list: lifts 0 and depth::kThinWallLift) only ever hides more, and at full resolution in
    // 32 bits the chosen test hides almost nothing visible.
    std::size_t lifted = 0;
    for (const auto& v : j["variants"]) {
        using Key = std::tuple<bool, double, double>;  // facing, slope, lift
        std::map<Key, std::vector<std::array<double, 3>>> byTest;  // tolerance, false hidden, false visible
        for (const auto& t : v["tests"])
            byTest[{t["facing"].get<bool>(), t["slope"].get<double>(), t["offset"].get<double>()}].push_back(
                {t["tolerance"].get<double>(), t["false_hidden"].get<double>(), t["false_visible"].get<double>()});
        for (auto& [test, rows] : byTest) {
            const auto [facing, slope, lift] = test;
            std::sort(rows.begin(), rows.end());
            for (std::size_t i = 1; i < rows.size(); ++i)
                EXPECT_LE(rows[i][1], rows[i - 1][1]) << v["variant"] << " tolerance " << rows[i][0];
            const auto flat = byTest.find({facing, 0.0, lift});
            if (slope > 0.0 && flat != byTest.end()) {
                for (std::size_t i = 0; i < rows.size() && i < flat->second.size(); ++i)
                    EXPECT_LE(rows[i][1], flat->second[i][1]) << v["variant"] << " slope " << slope;
            }
            const auto unlifted = byTest.find({facing, slope, 0.0});
            if (lift > 0.0 && unlifted != byTest.end()) {
                ++lifted;
                for (std::size_t i = 0; i < rows.size() && i < unlifted->second.size(); ++i) {
                    EXPECT_GE(rows[i][1], unlifted->second[i][1]) << v["variant"] << " lift " << lift;
                    EXPECT_LE(rows[i][2], unlifted->second[i][2]) << v["variant"] << " lift " << lift;
                }
            }
        }
    }
    EXPECT_GT(lifted, 0u);
    EXPECT_LE(j["default"]["full_res"]["false_hidden"].get<double>(), 0.02);
    EXPECT_EQ(j["default"]["full_res"]["false_visible"].get<double>(), 0.0);

    const fs::path cache = dir.path() / "bench.cubeao";
    const CliRun c = run("bench cache --probes 3 --res 8 --runs 1 --keep --out " + cache.string() + " --json");
    ASSERT_EQ(c.code, 0) << c.out;
    const auto k = lastLine(c.out);
    EXPECT_EQ(CacheReader(cache).probeCount(), 3u);
    // A warm load finds every page resident (a cold one none, where the file system can drop pages);
    // load = open + read.
    EXPECT_EQ(k["warm"]["resident_before"].get<double>(), 1.0);
    EXPECT_LE(k["cold"]["resident_before"].get<double>(), k["warm"]["resident_before"].get<double>());
    for (const char* run : {"cold", "warm"})
        EXPECT_NEAR(k[run]["load_ms"].get<double>(), k[run]["open_ms"].get<double>() + k[run]["read_ms"].get<double>(),
                    1e-6)
            << run;
    EXPECT_EQ(k["file_bytes"].get<std::uint64_t>(), fs::file_size(cache));
}

// ---- Counts that lie: every file of Debian's assimp-testmodels (issue 15) -------------------------

// `cubeao info FILE` in child processes with an address-space limit, `parallel` at a time, each killed
// after `timeoutS`: how each ended, its wall time and its peak resident memory (wait4's rusage).
struct InfoRun {
    bool exited = false;
    int code = -1;    // exit code when exited
    int signal = 0;   // the signal that ended it otherwise (SIGKILL after the timeout)
    bool timedOut = false;
    double seconds = 0.0;
    double peakMib = 0.0;
};

std::vector<InfoRun> runInfoLimited(const std::vector<fs::path>& files, std::size_t addressSpaceBytes,
                                    double timeoutS, std::size_t parallel) {
    using Clock = std::chrono::steady_clock;
    std::vector<InfoRun> runs(files.size());
    std::map<pid_t, std::pair<std::size_t, Clock::time_point>> running;  // pid → file, start
    std::size_t next = 0;
    while (next < files.size() || !running.empty()) {
        while (next < files.size() && running.size() < parallel) {
            const pid_t pid = fork();
            if (pid == 0) {
                // AddressSanitizer reserves terabytes of address space for its shadow at start: no cap
                // can apply under it (the peak resident memory is still measured).
                const rlimit limit{addressSpaceBytes, addressSpaceBytes};
                if (!cubeao::test::kAddressSanitizer) setrlimit(RLIMIT_AS, &limit);
                const int devNull = open("/dev/null", O_WRONLY);
                dup2(devNull, 1);
                dup2(devNull, 2);
                execl(cubeao::test::cubeaoBinary(), cubeao::test::cubeaoBinary(), "info", files[next].c_str(), static_cast<char*>(nullptr));
                _exit(127);
            }
            running[pid] = {next++, Clock::now()};
        }
        int status = 0;
        rusage usage{};
        const pid_t done = wait4(-1, &status, WNOHANG, &usage);
        if (done > 0 && running.count(done)) {
            const auto [i, start] = running[done];
            running.erase(done);
            InfoRun& r = runs[i];
            r.seconds = std::chrono::duration<double>(Clock::now() - start).count();
            r.peakMib = double(usage.ru_maxrss) / 1024.0;
            r.exited = WIFEXITED(status);
            if (r.exited) r.code = WEXITSTATUS(status);
            if (WIFSIGNALED(status)) r.signal = WTERMSIG(status);
            continue;
        }
        for (auto& [pid, job] : running)
            if (!runs[job.first].timedOut &&
                std::chrono::duration<double>(Clock::now() - job.second).count() > timeoutS) {
                kill(pid, SIGKILL);
                runs[job.first].timedOut = true;
            }
        std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
    return runs;
}

// Every file the package ships, valid or not, ends `info` with exit 0 (a scene) or 1 (refused with a
// message) within kSeconds, never by a signal, and never above kPeakMib resident (the address space is
// capped at 4 GiB besides, so a runaway allocation fails instead of swapping the machine).
// In four parts (every fourth file each), so ctest spreads them and none nears its timeout.
class CliRobustness : public ::testing::TestWithParam<int> {};
constexpr int kInfoParts = 4;

TEST_P(CliRobustness, InfoOnEveryAssimpTestModelEndsCleanly) {
    const fs::path root = "/usr/share/assimp/models";
    if (!fs::exists(root)) GTEST_SKIP() << root << " is absent (apt-get install assimp-testmodels)";
    // Under AddressSanitizer the bound on memory is left to the plain build: shadow memory and the
    // quarantine of freed blocks are the sanitizer's, not the loader's.
    constexpr double kSeconds = 30.0, kPeakMib = cubeao::test::kAddressSanitizer ? HUGE_VAL : 1024.0;
    std::vector<fs::path> files;
    for (const auto& e : fs::recursive_directory_iterator(root))
        if (e.is_regular_file()) files.push_back(e.path());
    std::sort(files.begin(), files.end());
    ASSERT_GT(files.size(), 400u);
    std::vector<fs::path> part;
    for (std::size_t i = std::size_t(GetParam()); i < files.size(); i += kInfoParts) part.push_back(files[i]);
    files = std::move(part);
    std::size_t loaded = 0, refused = 0;
    double slowest = 0.0, largest = 0.0;
    fs::path slowestFile, largestFile;
    const std::vector<InfoRun> runs = runInfoLimited(files, std::size_t(4) << 30, kSeconds, 3);
    for (std::size_t i = 0; i < files.size(); ++i) {
        const InfoRun& r = runs[i];
        const fs::path& f = files[i];
        EXPECT_TRUE(r.exited && (r.code == 0 || r.code == 1))
            << f << ": " << (r.timedOut ? "timed out" : r.exited ? "exit " + std::to_string(r.code)
                                                                  : "signal " + std::to_string(r.signal));
        EXPECT_LE(r.peakMib, kPeakMib) << f;
        (r.exited && r.code == 0 ? loaded : refused) += 1;
        if (r.seconds > slowest) slowest = r.seconds, slowestFile = f;
        if (r.peakMib > largest) largest = r.peakMib, largestFile = f;
    }
    std::printf("[ info ] %zu files: %zu loaded, %zu refused; slowest %.2f s (%s), largest %.0f MiB (%s)\n",
                files.size(), loaded, refused, slowest, slowestFile.c_str(), largest, largestFile.c_str());
}

INSTANTIATE_TEST_SUITE_P(Parts, CliRobustness, ::testing::Range(0, kInfoParts));

// Every format the installed assimp reads (issue 17): one model of each extension that
// assimp-testmodels ships imports with triangles. The smallest file of each is tried first; the first
// one that gives triangles counts. Three formats fail in Debian's assimp 5.2.5 for every shipped file
// (its Irrlicht XML reader rejects all of them; its TER reader stops at the end of both terrains):
// those must be refused cleanly, naming assimp, and a newer assimp that reads them is reported.
TEST(CliFormats, OneModelOfEachAssimpFormatImports) {
    const fs::path root = "/usr/share/assimp/models";
    if (!fs::exists(root)) GTEST_SKIP() << root << " is absent (apt-get install assimp-testmodels)";
    // The supported list, as the unknown-format error prints it.
    TempDir dir;
    const std::string probe = dir.write("probe.unknownformat", "x\n");
    const CliRun unknown = cubeao::test::runCli("info '" + probe + "'", true);
    const std::size_t from = unknown.out.find("supported: "), to = unknown.out.find(", or builtin");
    ASSERT_TRUE(from != std::string::npos && to != std::string::npos) << unknown.out;
    std::map<std::string, std::vector<fs::path>> byExt;  // every supported extension, its files
    {
        std::istringstream list(unknown.out.substr(from + 11, to - from - 11));
        for (std::string e; list >> e;) byExt[e];
    }
    for (const char* e : {".dxf", ".x3d", ".blend", ".3mf", ".lwo", ".ifc", ".gltf", ".glb", ".fbx"})
        EXPECT_TRUE(byExt.count(e)) << e << " is not among the supported formats: " << unknown.out;
    for (const auto& entry : fs::recursive_directory_iterator(root)) {
        if (!entry.is_regular_file() || entry.path().string().find("/invalid/") != std::string::npos) continue;
        std::string name = entry.path().filename().string();
        std::transform(name.begin(), name.end(), name.begin(), [](unsigned char c) { return char(std::tolower(c)); });
        std::vector<fs::path>* longest = nullptr;  // ".mesh.xml" wins over ".xml"
        std::size_t longestSize = 0;
        for (auto& [ext, files] : byExt)
            if (name.size() > ext.size() && ext.size() > longestSize &&
                name.compare(name.size() - ext.size(), ext.size(), ext) == 0)
                longest = &files, longestSize = ext.size();
        if (longest) longest->push_back(entry.path());
    }
    const std::set<std::string> assimpCannot = {".irr", ".irrmesh", ".ter"};
    std::size_t formats = 0;
    for (auto& [ext, files] : byExt) {
        if (files.empty()) continue;
        ++formats;
        std::sort(files.begin(), files.end(), [](const fs::path& a, const fs::path& b) {
            return std::pair(fs::file_size(a), a) < std::pair(fs::file_size(b), b);
        });
        std::string imported, lastError;
        for (const fs::path& f : files) {
            const CliRun r = cubeao::test::runCommand("timeout 60 " + std::string(cubeao::test::cubeaoBinary()) + " info '" +
                                                      f.string() + "' --json 2>&1");
            if (r.code == 0 && lastLine(r.out).value("triangles", 0) > 0) {
                imported = f.string() + ": " + std::to_string(lastLine(r.out).value("triangles", 0)) + " triangles";
                break;
            }
            lastError = r.out.substr(0, 300);
            if (!assimpCannot.count(ext)) continue;
            EXPECT_EQ(r.code, 1) << f << ": " << r.out;
            EXPECT_TRUE(contains(r.out, "assimp could not import it") || contains(r.out, "no triangles"))
                << f << ": " << r.out;
        }
        if (assimpCannot.count(ext)) {
            if (!imported.empty()) std::printf("[ note ] %s now imports (%s): a newer assimp\n", ext.c_str(), imported.c_str());
            continue;
        }
        EXPECT_FALSE(imported.empty()) << ext << ": none of its " << files.size() << " files imports; the last: "
                                       << lastError;
        std::printf("[ info ] %-9s %s\n", ext.c_str(), imported.c_str());
    }
    EXPECT_GE(formats, 50u) << "assimp-testmodels ships fewer formats than it did";
}

}  // namespace
