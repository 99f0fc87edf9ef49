// Progress on long jobs (issue 17): the figures each report line carries, the line mode for logs,
// the quiet short job, and a real command's lines.
#include <gtest/gtest.h>

#include <cstdlib>
#include <string>

#include "cli_run.h"
#include "cubeao/core/progress.h"
#include "test_util.h"
#include "test_paths.h"

namespace {

using cubeao::Progress;
using cubeao::test::contains;
using cubeao::test::ScopedEnv;

TEST(Progress, DescribeGivesCountShareRateElapsedAndEta) {
    EXPECT_EQ(Progress::describe(25, 100, 10.0, "probes"), "25/100 probes (25.0 %), 2.5 probes/s, 10.0 s, eta 30.0 s");
    EXPECT_EQ(Progress::describe(1, 2, 100.0, ""), "1/2 (50.0 %), 0.01/s, 1 min 40 s, eta 1 min 40 s");
    EXPECT_EQ(Progress::describe(2, 2, 7200.0, "frames"), "2/2 frames (100.0 %), 0.000278 frames/s, 2 h 00 min, eta 0 s");
    // Nothing done yet: no ETA can be given; an unknown total: no share and no ETA.
    EXPECT_EQ(Progress::describe(0, 10, 1.0, ""), "0/10 (0.0 %), 0/s, 1.0 s, eta ?");
    EXPECT_EQ(Progress::describe(5, 0, 2.0, "spacings"), "5 spacings, 2.5 spacings/s, 2.0 s");
}

TEST(Progress, LinesWhenNotATerminalThenADoneLine) {
    const ScopedEnv mode("CUBEAO_PROGRESS", "lines"), every("CUBEAO_PROGRESS_SECONDS", "0");
    testing::internal::CaptureStderr();
    {
        Progress p("job", 3, "probes");
        for (int i = 0; i < 3; ++i) p.advance();
    }
    const std::string err = testing::internal::GetCapturedStderr();
    EXPECT_TRUE(contains(err, "job: 1/3 probes (33.3 %)")) << err;
    EXPECT_TRUE(contains(err, "job: 3/3 probes (100.0 %)")) << err;
    EXPECT_TRUE(contains(err, "(done)\n")) << err;
    EXPECT_FALSE(contains(err, "\r")) << err;  // no bar redraws in a log
}

TEST(Progress, ShortJobStaysQuietAndOffMeansOff) {
    {
        const ScopedEnv mode("CUBEAO_PROGRESS", "lines"), slow("CUBEAO_PROGRESS_SECONDS", "60");
        testing::internal::CaptureStderr();
        {
            Progress p("job", 10);
            p.advance(10);
        }
        EXPECT_EQ(testing::internal::GetCapturedStderr(), "");
    }
    const ScopedEnv off("CUBEAO_PROGRESS", "off"), every("CUBEAO_PROGRESS_SECONDS", "0");
    testing::internal::CaptureStderr();
    {
        Progress p("job", 10);
        p.advance(10);
    }
    EXPECT_EQ(testing::internal::GetCapturedStderr(), "");
}

TEST(Progress, BarRedrawsInPlace) {
    const ScopedEnv mode("CUBEAO_PROGRESS", "bar");
    testing::internal::CaptureStderr();
    {
        Progress p("bake", 4, "probes");
        p.advance(4);
    }
    const std::string err = testing::internal::GetCapturedStderr();
    EXPECT_TRUE(contains(err, "\rbake")) << err;
    EXPECT_TRUE(contains(err, "[########################]")) << err;
    EXPECT_TRUE(contains(err, "4/4 probes (100.0 %)")) << err;
    EXPECT_EQ(err.back(), '\n');
}

// A command's progress in a log: the reference of a small walk, a line per step.
TEST(Progress, ReferenceReportsLinesToALog) {
    cubeao::test::TempDir dir;
    const cubeao::test::CliRun r = cubeao::test::runCommand(
        "CUBEAO_PROGRESS=lines CUBEAO_PROGRESS_SECONDS=0 " + std::string(cubeao::test::cubeaoBinary()) +
        " reference builtin:box-room --frames 0:2 --width 24 --height 16 --spp 2 --out " + dir.path().string() +
        " 2>&1 >/dev/null");
    ASSERT_EQ(r.code, 0) << r.out;
    EXPECT_TRUE(contains(r.out, "reference: ")) << r.out;
    EXPECT_TRUE(contains(r.out, "/768 pixels (")) << r.out;  // 2 frames of 24 × 16
    EXPECT_TRUE(contains(r.out, "pixels/s")) << r.out;
    EXPECT_TRUE(contains(r.out, "768/768 pixels (100.0 %)")) << r.out;
}

}  // namespace
