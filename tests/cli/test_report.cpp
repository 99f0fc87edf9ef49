// `cubeao report` (tools/cubeao/cmd_report.cpp, issue 17): the pieces with known answers (base64, colour
// scales, chart axes), a directory that is not a run, and a tiny run of builtin:box-room turned into a page
// that headless Chromium opens: the screenshot is not blank, every <img> decoded, no script error.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>

#include "../tools/cubeao/report_html.h"
#include "cli_run.h"
#include "cubeao/core/image.h"
#include "cubeao/metrics/image_io.h"
#include "test_util.h"

namespace {

namespace fs = std::filesystem;
using namespace cubeao;
using namespace cubeao::test;
namespace report = cubeao::cli::report;

std::string readText(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

TEST(ReportHtml, Base64KnownAnswers) {
    // RFC 4648 §10 test vectors.
    EXPECT_EQ(report::base64(""), "");
    EXPECT_EQ(report::base64("f"), "Zg==");
    EXPECT_EQ(report::base64("fo"), "Zm8=");
    EXPECT_EQ(report::base64("foo"), "Zm9v");
    EXPECT_EQ(report::base64("foob"), "Zm9vYg==");
    EXPECT_EQ(report::base64("fooba"), "Zm9vYmE=");
    EXPECT_EQ(report::base64("foobar"), "Zm9vYmFy");
    const unsigned char high[] = {0xff, 0xfe, 0xfd};  // bytes above 127 must not sign-extend
    EXPECT_EQ(report::base64(high, 3), "//79");
}

TEST(ReportHtml, EncodedPngRoundTripsThroughADataUri) {
    Image im(5, 3);
    for (std::size_t i = 0; i < im.pixels.size(); ++i) im.pixels[i] = float(i) / 14.0f;
    const std::vector<unsigned char> png = encodePng(im.width, im.height, 1, im.pixels);
    ASSERT_GT(png.size(), 8u);
    EXPECT_EQ(std::string(png.begin() + 1, png.begin() + 4), "PNG");
    EXPECT_EQ(report::pngDataUri(png).rfind("data:image/png;base64,iVBORw0KGgo", 0), 0u);
    EXPECT_THROW(encodePng(5, 3, 2, im.pixels), Error);
}

TEST(ReportHtml, HeatColourAtZeroAndAtTheTopOfTheScale) {
    const report::Rgb zero = report::heatColour(0.0), top = report::heatColour(1.0);
    EXPECT_EQ(report::cssColour(zero), "#000004");  // no error: black
    EXPECT_EQ(report::cssColour(top), "#fcffa4");   // kHeatMax and above: pale yellow
    EXPECT_EQ(report::heatColour(-0.5), zero);
    EXPECT_EQ(report::heatColour(7.0), top);
    EXPECT_EQ(report::heatColour(std::nan("")), zero);
    // Brightness grows along the scale, so a larger error never looks smaller.
    double last = -1.0;
    for (int i = 0; i <= 20; ++i) {
        const report::Rgb c = report::heatColour(i / 20.0);
        const double luma = 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2];
        EXPECT_GT(luma, last) << "at " << i / 20.0;
        last = luma;
    }
}

TEST(ReportHtml, NiceTicksAndTheChartScale) {
    EXPECT_DOUBLE_EQ(report::niceStep(0.047, 5), 0.01);
    EXPECT_DOUBLE_EQ(report::niceStep(47.0, 8), 10.0);
    EXPECT_DOUBLE_EQ(report::niceStep(0.3, 5), 0.1);
    const std::vector<double> t = report::niceTicks(0.0, 0.047, 5);
    ASSERT_EQ(t.size(), 6u);
    EXPECT_DOUBLE_EQ(t.front(), 0.0);
    EXPECT_NEAR(t.back(), 0.05, 1e-12);
    EXPECT_EQ(report::tickLabel(0.05, 0.01), "0.05");
    EXPECT_EQ(report::tickLabel(20.0, 5.0), "20");

    report::LineChart c;
    c.width = 600, c.height = 300, c.left = 60, c.right = 140, c.top = 30, c.bottom = 40;
    c.series.push_back({"a", "#f00", {2, 3, 4, 5, 6}, {0.01, 0.02, 0.047, 0.03, 0.0}});
    const report::ChartScales s = report::chartScales(c);
    // x: the data's first and last frame at the plot's left and right edges.
    EXPECT_DOUBLE_EQ(s.x(2.0), 60.0);
    EXPECT_DOUBLE_EQ(s.x(6.0), 460.0);
    EXPECT_DOUBLE_EQ(s.x(4.0), 260.0);
    // y: 0 at the bottom, the round tick above the largest value (0.05) at the top.
    EXPECT_DOUBLE_EQ(s.y(0.0), 260.0);
    EXPECT_NEAR(s.y(0.05), 30.0, 1e-9);
    EXPECT_NEAR(s.y(0.025), 145.0, 1e-9);
    const std::string svg = report::lineChartSvg(c);
    EXPECT_TRUE(contains(svg, "points=\"60.0,214.0 160.0,168.0 260.0,43.8 360.0,122.0 460.0,260.0\"")) << svg;
    EXPECT_TRUE(contains(svg, ">0.05</text>"));
    EXPECT_TRUE(contains(svg, ">a</text>")) << "legend";
    // Names are escaped.
    c.series[0].name = "<b>&";
    EXPECT_TRUE(contains(report::lineChartSvg(c), "&lt;b&gt;&amp;"));
}

TEST(CliReport, ADirectoryThatIsNotARunNamesTheMissingFile) {
    TempDir dir;
    const std::string out = " --out " + (dir / "r.html").string();
    CliRun r = runCli("report " + dir.path().string() + out, true);
    EXPECT_EQ(r.code, 1);
    EXPECT_TRUE(contains(r.out, "info.json is missing")) << r.out;
    dir.write("info.json", "{\"scene\":\"builtin:box-room\"}");
    dir.write("probes.json", "{\"probes\":[]}");
    r = runCli("report " + dir.path().string() + out, true);
    EXPECT_EQ(r.code, 1);
    EXPECT_TRUE(contains(r.out, "reference.json is missing")) << r.out;
    dir.write("reference.json", "");
    r = runCli("report " + dir.path().string() + out, true);
    EXPECT_TRUE(contains(r.out, "reference.json is empty")) << r.out;
    dir.write("reference.json", "{}");
    fs::create_directories(dir / "reference");
    r = runCli("report " + dir.path().string() + out, true);
    EXPECT_TRUE(contains(r.out, "no compare-METHOD.json")) << r.out;
    dir.write("compare-gtao.json", "{\"frames\":[]}");
    r = runCli("report " + dir.path().string() + out, true);
    EXPECT_TRUE(contains(r.out, "render-gtao/ is missing")) << r.out;
    EXPECT_FALSE(fs::exists(dir / "r.html"));
    EXPECT_EQ(runCli("report " + dir.path().string() + out + " --frames 1,x").code, 2);
    EXPECT_EQ(runCli("report /no/such/run" + out).code, 1);
}

// A run as tools/demo.sh lays it out, made small: builtin:box-room, 2 probes at 16² per face, 3 frames at
// 64x36, the probes and GTAO against a 16-ray reference.
class ReportRun : public ::testing::Test {
protected:
    static void SetUpTestSuite() {
        dir_ = new TempDir("report");
        const fs::path d = dir_->path();
        auto step = [&](const std::string& args, const std::string& jsonFile) {
            const CliRun r = runCli(args + " --json");
            if (r.code != 0) {
                failed_ = "cubeao " + args + ": exit " + std::to_string(r.code);
                return false;
            }
            std::ofstream(d / jsonFile) << lastLine(r.out).dump() << "\n";
            return true;
        };
        const std::string walk = " --frames 0:3 --width 64 --height 36";
        const std::string cache = (d / "bake-traced.cubeao").string();
        (void)(step("info builtin:box-room", "info.json") &&
               step("place builtin:box-room --camera builtin:box-room --budget 2 --res 16 --samples 2000 --out " +
                        (d / "probes.json").string(),
                    "place.json") &&
               step("bake builtin:box-room --probes " + (d / "probes.json").string() + " --out " + cache +
                        " --res 16 --spp 8 --device cpu",
                    "bake-traced.json") &&
               step("info " + cache + " --verify", "bake-traced-info.json") &&
               step("render builtin:box-room --method probes --cache " + cache + walk + " --out " +
                        (d / "render-probes").string(),
                    "render-probes.json") &&
               step("render builtin:box-room --method gtao" + walk + " --out " + (d / "render-gtao").string(),
                    "render-gtao.json") &&
               step("reference builtin:box-room --spp 16" + walk + " --out " + (d / "reference").string(),
                    "reference.json") &&
               step("compare " + (d / "render-probes").string() + " " + (d / "reference").string(),
                    "compare-probes.json") &&
               step("compare " + (d / "render-gtao").string() + " " + (d / "reference").string(), "compare-gtao.json"));
    }
    static void TearDownTestSuite() {
        delete dir_;
        dir_ = nullptr;
    }
    void SetUp() override { ASSERT_TRUE(failed_.empty()) << failed_; }

    static TempDir* dir_;
    static std::string failed_;
};
TempDir* ReportRun::dir_ = nullptr;
std::string ReportRun::failed_;

TEST_F(ReportRun, WritesOneSelfContainedPage) {
    const fs::path html = dir_->path() / "report.html";
    const CliRun r = runCli("report " + dir_->path().string() + " --out " + html.string() + " --frames 0,2 --json");
    ASSERT_EQ(r.code, 0) << r.out;
    EXPECT_EQ(lastLine(r.out)["images"].get<int>(), 2 * (1 + 2 * 2) + 1) << "2 frames x (reference + 2 x 2) + plan";
    const std::string page = readText(html);
    // Nothing from outside: every src is a data: URI, no stylesheet or script is linked.
    const std::regex src("src=\"([^\"]{0,32})");
    int sources = 0;
    for (auto it = std::sregex_iterator(page.begin(), page.end(), src); it != std::sregex_iterator(); ++it, ++sources)
        EXPECT_EQ((*it)[1].str().rfind("data:image/png;base64,", 0), 0u) << (*it)[1].str();
    EXPECT_EQ(sources, 11);
    EXPECT_FALSE(contains(page, "<link")) << "no external stylesheet";
    EXPECT_FALSE(contains(page, "<script src")) << "no external script";
    for (const char* part : {"probes (traced bake)", "gtao", "MAE per frame", "Flicker per frame",
                             "the error each removed", "predicted MAE", "ms/probe", "image-rendering:pixelated",
                             "than the best screen-space baseline"})
        EXPECT_TRUE(contains(page, part)) << part;
    // Each frame side by side: reference | probes | best baseline in one row (here the run's two methods,
    // so nothing is folded away under them).
    std::size_t rows = 0;
    for (std::size_t at = page.find("<div class=\"trio\">"); at != std::string::npos;
         at = page.find("<div class=\"trio\">", at + 1))
        ++rows;
    EXPECT_EQ(rows, 2u);
    EXPECT_FALSE(contains(page, "<details"));
    EXPECT_EQ(runCli("report " + dir_->path().string() + " --out " + html.string() + " --frames 7").code, 1)
        << "frame 7 is not in the run";
    // No temporary file left beside the page.
    for (const auto& e : fs::directory_iterator(dir_->path()))
        EXPECT_FALSE(contains(e.path().filename().string(), ".tmp")) << e.path();
}

// The page in headless Chromium (Debian's `chromium`; skipped without it).
TEST_F(ReportRun, PageRendersInHeadlessChromium) {
    if (runCommand("command -v chromium >/dev/null 2>&1").code != 0)
        GTEST_SKIP() << "chromium is not installed (apt-get install chromium; tools/install-deps.sh lists it)";
    const fs::path html = dir_->path() / "chromium.html", shot = dir_->path() / "shot.png";
    ASSERT_EQ(runCli("report " + dir_->path().string() + " --out " + html.string()).code, 0);
    // A profile of its own: no clash with a browser the user runs, nor with a parallel test.
    // Chromium is not ours: under the sanitizers (tools/test-sanitize.sh) it must not inherit the preloaded
    // ASan runtime and its options, under which it aborted at start.
    const std::string chromium = "timeout 120 env -u LD_PRELOAD -u ASAN_OPTIONS -u LSAN_OPTIONS -u UBSAN_OPTIONS "
                                 "chromium --headless --no-sandbox --disable-gpu --user-data-dir=" +
                                 (dir_->path() / "chromium-profile").string() + " --window-size=1280,2400 ";
    const CliRun s = runCommand(chromium + "--screenshot=" + shot.string() + " file://" + html.string() + " 2>&1");
    ASSERT_EQ(s.code, 0) << s.out;
    // The screenshot is read by OpenImageIO's iinfo in a process of its own, not through the image
    // plugin here: under the sanitizers, this process dlopen'ing the plugin crashed LeakSanitizer's tracer
    // at its exit in three ci-like runs of four (docs/RELIABILITY.md). The first channel (red) is
    // enough to tell a blank page.
    const CliRun stats = runCommand("env -u LD_PRELOAD -u ASAN_OPTIONS -u LSAN_OPTIONS -u UBSAN_OPTIONS iinfo --stats " +
                                    shot.string() + " 2>&1");
    ASSERT_EQ(stats.code, 0) << stats.out;
    EXPECT_NE(stats.out.find(": 1280 x 2400,"), std::string::npos) << stats.out;
    std::smatch sd;
    ASSERT_TRUE(std::regex_search(stats.out, sd, std::regex("Stats StdDev: ([0-9.]+)"))) << stats.out;
    const double deviation = std::stod(sd[1].str()) / 255.0;
    EXPECT_GT(deviation * deviation, 0.01) << "the screenshot looks blank:\n" << stats.out;
    // The page's own script marks the body once loaded: images decoded / images, and any script error.
    // --enable-logging=stderr prints console messages as CONSOLE lines.
    const CliRun dom =
        runCommand(chromium + "--virtual-time-budget=3000 --enable-logging=stderr --v=0 --dump-dom file://" +
                   html.string() + " 2>" + (dir_->path() / "console.txt").string());
    ASSERT_EQ(dom.code, 0);
    std::smatch m;
    ASSERT_TRUE(std::regex_search(dom.out, m, std::regex("data-images-ok=\"(\\d+)/(\\d+)\"")))
        << "no marker in the DOM";
    EXPECT_EQ(m[1].str(), m[2].str()) << "images that did not load";
    EXPECT_EQ(m[2].str(), std::to_string(3 * (1 + 2 * 2) + 1)) << "3 frames x (reference + 2 x 2) + plan";
    EXPECT_FALSE(contains(dom.out, "data-errors")) << "a script error";
    const std::string console = readText(dir_->path() / "console.txt");
    EXPECT_FALSE(contains(console, "CONSOLE")) << console;
}

}  // namespace
