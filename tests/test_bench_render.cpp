// `cubeao bench render` end to end at a tiny size (the full-size figures: docs/BENCHMARKS.md).
#include <gtest/gtest.h>

#include <string>

#include <nlohmann/json.hpp>

#include "cli_run.h"
#include "gl_fixture.h"

namespace {

using cubeao::test::CliRun;
using cubeao::test::lastLine;
using cubeao::test::runCli;

TEST(BenchRenderCli, UsageErrors) {
    EXPECT_EQ(runCli("bench render --methods probes,ssao").code, 2);
    EXPECT_EQ(runCli("bench render --res 6").code, 2) << "BC5 needs a multiple of 4";
    EXPECT_EQ(runCli("bench render --probes 10,0").code, 2);
    EXPECT_EQ(runCli("bench render --frames 0").code, 2);
}

// 400 probes are 2,400 cube faces: more than the 2,048 array layers llvmpipe allows, so the sweep
// also checks that the projection's atlas (ProbeAtlasLayout) takes caches past that.
TEST_F(GlTest, BenchRenderTimesEveryMethodAndTheProbeSweep) {
    const CliRun r = runCli("bench render --scene builtin:box-room --width 64 --height 36 --probes 400,10 --res 8 "
                            "--frames 1 --json");
    ASSERT_EQ(r.code, 0) << r.out;
    const nlohmann::json j = lastLine(r.out);
    for (const char* method : {"probes", "gtao", "hbao", "alchemy"}) {
        const nlohmann::json& m = j["methods"][method];
        for (const char* pass : {"gbuffer", "ao", "blur", "composite", "ao_blur", "gpu_total"})
            EXPECT_GT(m["timings_ms"][pass].get<double>(), 0.0) << method << " " << pass;
        EXPECT_GT(m["fetches_per_pixel"].get<double>(), 0.0) << method;
    }
    ASSERT_EQ(j["sweep"].size(), 2u);
    EXPECT_EQ(j["sweep"][0]["probes"].get<int>(), 10) << "counts in increasing order";
    EXPECT_EQ(j["sweep"][1]["probes"].get<int>(), 400);
    EXPECT_EQ(j["methods"]["probes"]["probes"].get<int>(), 400) << "\"probes\" is the largest count";
    for (const nlohmann::json& s : j["sweep"]) {
        EXPECT_GT(s["timings_ms"]["ao_blur"].get<double>(), 0.0);
        EXPECT_GT(s["prep_ms"].get<double>(), 0.0);
        EXPECT_GT(s["gpu_bytes"].get<double>(), 0.0);
        EXPECT_GT(s["cache_bytes"].get<double>(), 0.0);
        EXPECT_LT(s["uncovered_fraction"].get<double>(), 0.2) << s["probes"] << " probes: the projection reads them all";
    }
    EXPECT_GT(j["targets"]["probes_to_gtao_ao_blur"].get<double>(), 0.0);
    EXPECT_GE(j["targets"]["sweep_spread"].get<double>(), 0.0);
    EXPECT_TRUE(j["targets"]["sweep_flat"].is_boolean());
}

}  // namespace
