// The cubeao binary end to end: exit codes, JSON as the last line, files written (DESIGN.md §5).
#include <gtest/gtest.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <sys/wait.h>

#include <nlohmann/json.hpp>

#include "test_util.h"

namespace {

namespace fs = std::filesystem;
using cubeao::test::TempDir;

struct CliRun {
    int code = -1;
    std::string out;
};

CliRun run(const std::string& args) {
    const std::string cmd = std::string(CUBEAO_BINARY) + " " + args + " 2>/dev/null";
    CliRun r;
    FILE* p = popen(cmd.c_str(), "r");
    if (!p) return r;
    std::array<char, 4096> buf{};
    while (std::size_t n = std::fread(buf.data(), 1, buf.size(), p)) r.out.append(buf.data(), n);
    const int status = pclose(p);
    r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    return r;
}

nlohmann::json lastLine(const std::string& out) {
    std::string s = out;
    while (!s.empty() && s.back() == '\n') s.pop_back();
    return nlohmann::json::parse(s.substr(s.rfind('\n') + 1));
}

TEST(Cli, InfoJsonFields) {
    const CliRun r = run("info builtin:cloister --json");
    ASSERT_EQ(r.code, 0) << r.out;
    const auto j = lastLine(r.out);
    for (const char* key : {"triangles", "vertices", "bbox", "problems"}) EXPECT_TRUE(j.contains(key)) << key;
    EXPECT_GT(j["triangles"].get<int>(), 20000);
}

TEST(Cli, ReferenceWritesFramesNamedByPathIndex) {
    TempDir dir;
    const CliRun r = run("reference builtin:box-room --frames 5:7 --width 24 --height 16 --spp 4 --out " +
                      dir.path().string() + " --json");
    ASSERT_EQ(r.code, 0) << r.out;
    const auto j = lastLine(r.out);
    EXPECT_GT(j["rays_per_s"].get<double>(), 0.0);
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
    const CliRun r = run("place builtin:box-room --budget 3 --out " + probes.string() + " --json");
    ASSERT_EQ(r.code, 0) << r.out;
    EXPECT_EQ(lastLine(r.out)["probes"].get<int>(), 3);
    const CliRun b = run("bake builtin:box-room --probes " + probes.string() + " --out " +
                         (dir.path() / "bake").string() + " --res 4 --spp 2 --device cpu --json");
    ASSERT_EQ(b.code, 0) << b.out;
    EXPECT_EQ(lastLine(b.out)["probes"].get<int>(), 3);
    EXPECT_EQ(run("place builtin:box-room --method voting --out " + probes.string()).code, 2);
    EXPECT_EQ(run("place builtin:box-room --budget 0 --out " + probes.string()).code, 2);
}

TEST(Cli, BakeCpuWritesProbesAndVerifies) {
    TempDir dir;
    const std::string probes = dir.write("probes.json", R"({"version":1,"probes":[{"pos":[3,1.4,2.5]},{"pos":[6,1.5,1.5]}]})");
    const fs::path out = dir.path() / "bake", dump = dir.path() / "dump";
    const CliRun r = run("bake builtin:box-room --probes " + probes + " --out " + out.string() + " --dump " +
                         dump.string() + " --res 8 --spp 8 --device cpu --verify --json");
    ASSERT_EQ(r.code, 0) << r.out;
    const auto j = lastLine(r.out);
    EXPECT_EQ(j["probes"].get<int>(), 2);
    EXPECT_GT(j["ms_per_probe"].get<double>(), 0.0);
    EXPECT_EQ(j["verify_mae"].get<double>(), 0.0) << "CPU traced and its Embree twin trace the same rays";
    ASSERT_EQ(j["per_probe"].size(), 2u);
    EXPECT_TRUE(fs::exists(out / "bake.json"));
    EXPECT_TRUE(fs::exists(out / "probe_0001_ao.exr"));
    EXPECT_TRUE(fs::exists(dump / "probe_0001_cross.png"));

    // A shard bakes every N-th probe, keeping the global probe index in its file names.
    const fs::path shard = dir.path() / "shard";
    const CliRun s = run("bake builtin:box-room --probes " + probes + " --out " + shard.string() +
                         " --res 8 --estimator hsplit --device cpu --shard 1/2 --json");
    ASSERT_EQ(s.code, 0) << s.out;
    EXPECT_EQ(lastLine(s.out)["probes"].get<int>(), 1);
    EXPECT_TRUE(fs::exists(shard / "probe_0001_ao.exr"));
    EXPECT_FALSE(fs::exists(shard / "probe_0000_ao.exr"));
}

TEST(Cli, BakeRejectsBadInput) {
    TempDir dir;
    const std::string good = dir.write("good.json", R"({"version":1,"probes":[{"pos":[3,1.4,2.5]}]})");
    const std::string out = " --out " + (dir.path() / "out").string() + " --device cpu --res 8";
    EXPECT_EQ(run("bake builtin:box-room --probes " + good + out + " --estimator ssao").code, 2);
    EXPECT_EQ(run("bake builtin:box-room --probes " + good + out + " --res 2").code, 2);
    EXPECT_EQ(run("bake builtin:box-room --probes " + good + out + " --shard 2/2").code, 2);
    EXPECT_EQ(run("bake builtin:box-room --probes " + good + out + " --device tpu").code, 2);
    EXPECT_EQ(run("bake builtin:box-room --probes " + dir.write("v2.json", R"({"version":2,"probes":[]})") + out).code, 1);
    EXPECT_EQ(run("bake builtin:box-room --probes " + dir.write("nan.json", R"({"version":1,"probes":[{"pos":[1,"x",2]}]})") + out).code, 1);
    EXPECT_EQ(run("bake builtin:box-room --probes " + (dir.path() / "missing.json").string() + out).code, 1);
}

}  // namespace
