// The walkthrough viewer (issue 14): its script language (pure), and the program itself in a real
// window: under Xvfb in CI (tools/test.sh runs the suite under xvfb-run when there is no display).
// The window tests skip with the reason when there is no X display.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

#include "bake_test_settings.h"
#include "cli_run.h"
#include "damaged_cache.h"
#include "cubeao-view/script.h"
#include "cubeao-view/view_modes.h"
#include "cubeao/cache/cache_file.h"
#include "cubeao/core/error.h"
#include "cubeao/metrics/image_io.h"
#include "cubeao/scene/builtin.h"
#include "cubeao/scene/import.h"
#include "test_paths.h"

namespace cubeao::viewer {
namespace {

namespace fs = std::filesystem;

TEST(ViewerScript, ParsesEveryCommand) {
    const auto c = parseScript(
        "# a walk\n"
        "size 160 90\n"
        "path 3   # start\n"
        "play 0 12\n"
        "walk 0 0 1.5 10\n"
        "turn -30 5\n"
        "MODE ao\n"
        "live on\n"
        "settle 200\n"
        "screenshot out/a.png\n"
        "save out/live.cubeao\n"
        "record walk.json\n"
        "record stop\n"
        "\n"
        "quit\n");
    ASSERT_EQ(c.size(), 13u);
    EXPECT_EQ(c[0].verb, Verb::Size);
    EXPECT_EQ(c[0].numbers, (std::vector<double>{160, 90}));
    EXPECT_EQ(c[1].line, 3);
    EXPECT_EQ(c[3].numbers, (std::vector<double>{0, 0, 1.5, 10}));
    EXPECT_EQ(c[4].numbers[0], -30.0);
    EXPECT_EQ(c[5].verb, Verb::Mode);
    EXPECT_EQ(c[5].text, "ao");
    EXPECT_EQ(c[8].text, "out/a.png");
    EXPECT_EQ(c[12].verb, Verb::Quit);
    EXPECT_EQ(c[10].verb, Verb::Record);
    EXPECT_STREQ(verbName(c[10].verb), "record");
}

// Each bad line is refused with the script's name, its line and what was expected.
TEST(ViewerScript, RefusesBadLinesNamingThem) {
    const auto message = [](const std::string& text) {
        try {
            parseScript(text, "walk.txt");
        } catch (const UsageError& e) {
            return std::string(e.what());
        }
        return std::string("accepted");
    };
    EXPECT_NE(message("frames 2\nfly 1 2 3\n").find("walk.txt:2: unknown command \"fly\""), std::string::npos);
    EXPECT_NE(message("path\n").find("walk.txt:1: expected \"path F\""), std::string::npos);
    EXPECT_NE(message("eye 1 two 3\n").find("\"two\" is not a number"), std::string::npos);
    EXPECT_NE(message("frames -1\n").find("whole number"), std::string::npos);
    EXPECT_NE(message("frames 2.5\n").find("whole number"), std::string::npos);
    EXPECT_NE(message("play 5 2\n").find("end frame"), std::string::npos);
    EXPECT_NE(message("size 4 4\n").find("width"), std::string::npos);
    EXPECT_NE(message("live maybe\n").find("live on"), std::string::npos);
    // Names are checked before the window opens, not when the line is reached.
    EXPECT_NE(message("frames 9\nmode sepia\n").find("walk.txt:2: \"sepia\" is not a view mode"), std::string::npos);
    EXPECT_NE(message("baseline ssao\n").find("walk.txt:1: baseline \"ssao\""), std::string::npos);
    EXPECT_NE(message("eye 1 inf 3\n").find("finite"), std::string::npos);
    EXPECT_EQ(message("# only a comment\n\n"), "accepted");
}

TEST(ViewerScript, ViewModeNamesRoundTrip) {
    for (ViewMode m : allViewModes()) {
        const auto parsed = parseViewMode(viewModeName(m));
        ASSERT_TRUE(parsed.has_value()) << viewModeName(m);
        EXPECT_EQ(*parsed, m);
    }
    EXPECT_FALSE(parseViewMode("sepia").has_value());
}

// ---- the program in a window ------------------------------------------------------------------

using ProgramRun = test::CliRun;

// A command line with its stderr on stdout (the viewer logs through spdlog to stderr).
ProgramRun runProgram(const std::string& command) { return test::runCommand(command + " 2>&1"); }

class ViewerWindow : public ::testing::Test {
protected:
    void SetUp() override {
        if (!std::getenv("DISPLAY"))
            GTEST_SKIP() << "no X display (DISPLAY unset): run the suite through tools/test.sh, which starts Xvfb";
        dir_ = fs::temp_directory_path() / ("cubeao_viewer_" + std::to_string(::getpid()) + "_" +
                                            ::testing::UnitTest::GetInstance()->current_test_info()->name());
        fs::remove_all(dir_);
        fs::create_directories(dir_);
    }
    void TearDown() override {
        if (!dir_.empty() && !HasFailure()) fs::remove_all(dir_);
    }

    // Runs cubeao-view with a script; fails the test on a non-zero exit or any logged error (GL debug
    // output reports GL errors at error level).
    ProgramRun view(const std::string& args, const std::string& script) {
        const fs::path file = dir_ / "script.txt";
        std::ofstream(file) << script;
        const ProgramRun r = runProgram(std::string(cubeao::test::viewerBinary()) + " " + args + " --width 320 --height 240 --script " +
                                 file.string() + " --stats " + (dir_ / "stats.json").string());
        EXPECT_EQ(r.code, 0) << r.out;
        EXPECT_EQ(r.out.find("[error]"), std::string::npos) << r.out;
        return r;
    }
    nlohmann::json stats() const {
        std::ifstream in(dir_ / "stats.json");
        return nlohmann::json::parse(in);
    }

    fs::path dir_;
};

// A few frames of builtin:cloister with a cache, then the AO of path frame 5 as a screenshot: the same
// as `cubeao render` of that camera (the same frame pipeline; every probe resident in both).
TEST_F(ViewerWindow, ScreenshotMatchesRender) {
    const Scene scene = loadScene("builtin:cloister");
    const CameraPath path = resolveCameraPath("", "builtin:cloister");
    std::vector<glm::vec3> probes;
    for (std::size_t f = 0; f < path.frames.size(); f += 8) probes.push_back(path.frames[f].eye);
    const fs::path cache = dir_ / "cloister.cubeao";
    test::bakeCache(scene, probes, test::bakeSettings(Estimator::HorizonSplit, 16, scene.defaultRadius(), 0), cache);

    view("builtin:cloister --cache " + cache.string(),
         "size 160 90\npath 0\nframes 2\nplay 1 6\nframes 2\nscreenshot " + (dir_ / "view.exr").string() +
             "\nscreenshot " + (dir_ / "view.png").string() + "\nquit\n");
    const ProgramRun render = runProgram(std::string(cubeao::test::cubeaoBinary()) + " render builtin:cloister --cache " + cache.string() +
                                  " --frames 5:6 --width 160 --height 90 --out " + (dir_ / "render").string());
    ASSERT_EQ(render.code, 0) << render.out;

    const Image shot = readImage(dir_ / "view.exr");
    const Image ref = readImage(dir_ / "render" / "ao_0005.exr");
    ASSERT_TRUE(shot.sameSize(ref));
    double sum = 0.0, worst = 0.0;
    for (std::size_t i = 0; i < ref.pixels.size(); ++i) {
        const double d = std::abs(double(shot.pixels[i]) - double(ref.pixels[i]));
        sum += d, worst = std::max(worst, d);
    }
    // Stated tolerance: the two run the same passes on the same inputs, so only the order of float
    // work on the GPU may differ; measured 0 on llvmpipe.
    EXPECT_LT(sum / double(ref.pixels.size()), 1e-4);
    EXPECT_LT(worst, 1e-3);
    EXPECT_TRUE(fs::exists(dir_ / "view.png"));
}

// Every view mode draws in the window without a GL error (the viewer logs GL debug errors at error
// level; view() fails on any) and its screenshot is written.
TEST_F(ViewerWindow, EveryViewModeRendersWithoutGlErrors) {
    const Scene scene = loadScene("builtin:box-room");
    const CameraPath path = resolveCameraPath("", "builtin:box-room");
    const fs::path cache = dir_ / "box.cubeao";
    const std::vector<glm::vec3> probes = {path.frames[0].eye, path.frames[path.frames.size() / 2].eye};
    test::bakeCache(scene, probes, test::bakeSettings(Estimator::HorizonSplit, 16, scene.defaultRadius(), 0), cache);
    // A reference for the difference mode: the render itself stands in (the mode only needs an image).
    const ProgramRun render = runProgram(std::string(cubeao::test::cubeaoBinary()) + " render builtin:box-room --cache " + cache.string() +
                                  " --frames 2:3 --width 96 --height 54 --out " + (dir_ / "ref").string());
    ASSERT_EQ(render.code, 0) << render.out;
    std::string script = "size 96 54\npath 2\nframes 1\n";
    for (ViewMode m : allViewModes())
        script += std::string("mode ") + viewModeName(m) + "\nframes 1\nscreenshot " +
                  (dir_ / (std::string(viewModeName(m)) + ".png")).string() + "\n";
    script += "screenshot-window " + (dir_ / "window.png").string() + "\nquit\n";
    view("builtin:box-room --cache " + cache.string() + " --reference " + (dir_ / "ref").string(), script);
    for (ViewMode m : allViewModes()) EXPECT_TRUE(fs::exists(dir_ / (std::string(viewModeName(m)) + ".png"))) << viewModeName(m);
    EXPECT_TRUE(fs::exists(dir_ / "window.png"));
}

// Live placement over an opened cache baked with other than the default rays and AO filter: the live
// traced bake takes the cache's own settings, so the cache's probes are adopted (they were refused:
// "baked with other parameters than the live bake") and saved back with the cache's parameters. A
// damaged probe is left out by the view and by live placement, which adopts the others. (The coverage
// objective at a target of 0.01 places nothing beside them: adoption is what is tested.)
TEST_F(ViewerWindow, LivePlacementAdoptsACacheBakedWithItsOwnSettings) {
    const Scene scene = loadScene("builtin:box-room");
    const CameraPath path = resolveCameraPath("", "builtin:box-room");
    const fs::path cache = dir_ / "box.cubeao", saved = dir_ / "saved.cubeao";
    BakeSettings s = test::bakeSettings(Estimator::Traced, 16, scene.defaultRadius(), 8);
    s.denoise = 0;
    const std::vector<glm::vec3> probes = {path.frames[0].eye, path.frames[path.frames.size() / 2].eye};
    test::bakeCache(scene, probes, s, cache);
    const CacheReader opened(cache);
    ASSERT_EQ(opened.params().spp, 8u);
    ASSERT_EQ(opened.params().denoise, 0u);
    ASSERT_EQ(opened.params().aoFormat, AoFormat::Bc4);
    // Walked without live placement the pass holds the cache's BC4; "live on" makes it hold BC5 (the
    // live horizon probes carry a confidence): the AO atlas doubles.
    view("builtin:box-room --cache " + cache.string(), "size 96 54\npath 0\nframes 2\nquit\n");
    const std::size_t bc4Bytes = stats()["gpu_bytes"].get<std::size_t>();
    view("builtin:box-room --cache " + cache.string() + " --bake-ms 1000 --live-objective coverage --coverage-target 0.01",
         "size 96 54\npath 0\nlive on\nframes 2\nsave " + saved.string() + "\nquit\n");
    const nlohmann::json st = stats();
    EXPECT_GE(st["gpu_bytes"].get<std::size_t>(), bc4Bytes + probes.size() * 6 * 16 * 16 / 2) << st.dump(2);
    ASSERT_TRUE(st.contains("live")) << st.dump(2);
    EXPECT_EQ(st["probes"].get<std::size_t>(), probes.size()) << st.dump(2);
    EXPECT_EQ(st["damaged"].get<std::size_t>(), 0u);
    const CacheReader back(saved);
    EXPECT_EQ(back.probeCount(), probes.size());
    EXPECT_TRUE(back.params() == opened.params()) << "saved with the opened cache's parameters";

    // A damaged probe: left out by live placement, which starts before the first frame here (--live),
    // and by the pass; the other probe is adopted and saved.
    const std::vector<std::size_t> second{1};
    test::writeWithDamagedAo(cache, second, dir_ / "damaged.cubeao");
    const ProgramRun damaged = view("builtin:box-room --cache " + (dir_ / "damaged.cubeao").string() +
                                        " --live --bake-ms 1000 --live-objective coverage --coverage-target 0.01",
                                    "size 96 54\npath 0\nframes 2\nsave " + saved.string() + "\nquit\n");
    EXPECT_NE(damaged.out.find("probe 1: checksum mismatch"), std::string::npos) << damaged.out;
    EXPECT_EQ(stats()["probes"].get<std::size_t>(), 1u);
    EXPECT_EQ(stats()["damaged"].get<std::size_t>(), 1u) << "counted once, whichever of the pass and live placement "
                                                            "found it (the panel shows this count)";
    EXPECT_EQ(CacheReader(saved).probeCount(), 1u);
}

// Live placement from no probes on builtin:box-room, on the predicted error (the default): probes are
// placed and baked, the walk so far's predicted error is reported, and an unknown objective is refused.
TEST_F(ViewerWindow, LivePlacementOnTheErrorFromNoProbes) {
    const fs::path saved = dir_ / "live.cubeao";
    view("builtin:box-room --live --live-res 16 --bake-ms 1000",
         "size 96 54\nplay 0 8\nsettle 400\nsave " + saved.string() + "\nquit\n");
    const nlohmann::json s = stats();
    ASSERT_TRUE(s.contains("live")) << s.dump(2);
    const nlohmann::json& live = s["live"];
    EXPECT_EQ(live["objective"].get<std::string>(), "error");
    EXPECT_GT(live["placed"].get<int>(), 0);
    EXPECT_EQ(live["baked"].get<int>(), live["placed"].get<int>());
    EXPECT_GT(live["frames_counted"].get<int>(), 0);
    EXPECT_GT(live["predicted_mae"].get<double>(), 0.0) << "the box room's corners stay a little off";
    EXPECT_LT(live["predicted_mae"].get<double>(), 0.05) << s.dump(2);
    EXPECT_EQ(CacheReader(saved).probeCount(), live["placed"].get<std::size_t>());

    const ProgramRun bad =
        runProgram(std::string(cubeao::test::viewerBinary()) + " builtin:box-room --live --live-objective pixels");
    EXPECT_NE(bad.code, 0);
    EXPECT_NE(bad.out.find("--live-objective"), std::string::npos) << bad.out;
}

// Live placement from no probes on builtin:box-room with the coverage objective: the walk ends above
// the coverage target, every placed probe is baked and in the pass, and the saved cache verifies.
TEST_F(ViewerWindow, LivePlacementFromNoProbes) {
    const fs::path saved = dir_ / "live.cubeao";
    view("builtin:box-room --live --live-objective coverage --live-res 16 --bake-ms 1000 --coverage-target 0.9",
         "size 96 54\nplay 0 24\nsettle 400\nsave " + saved.string() + "\nquit\n");
    const nlohmann::json s = stats();
    ASSERT_TRUE(s.contains("live")) << s.dump(2);
    const nlohmann::json& live = s["live"];
    EXPECT_GT(live["placed"].get<int>(), 0);
    EXPECT_EQ(live["queued"].get<int>(), 0);
    EXPECT_EQ(live["baked"].get<int>(), live["placed"].get<int>());
    EXPECT_EQ(s["probes"].get<int>(), live["placed"].get<int>());
    EXPECT_GE(live["walk_coverage_mean"].get<double>(), 0.9) << s.dump(2);
    EXPECT_EQ(s["frame_log"]["frames"].size(), s["frames"].get<std::size_t>());

    CacheReader reader(saved);
    EXPECT_EQ(reader.probeCount(), live["placed"].get<std::size_t>());
    EXPECT_NO_THROW(reader.verifyAll());
    const ProgramRun info = runProgram(std::string(cubeao::test::cubeaoBinary()) + " info " + saved.string() + " --verify");
    EXPECT_EQ(info.code, 0) << info.out;
}

}  // namespace
}  // namespace cubeao::viewer
