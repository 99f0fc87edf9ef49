// Metrics and AO image files (src/cubeao/metrics): analytic answers with explicit tolerances.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <limits>
#include <random>
#include <string>
#include <sys/wait.h>
#include <vector>

#include "cubeao/core/error.h"
#include "cubeao/metrics/image_io.h"
#include "cubeao/metrics/image_metrics.h"
#include "test_util.h"
#include "test_paths.h"

namespace fs = std::filesystem;
using namespace cubeao;
using namespace cubeao::test;

namespace {

constexpr int kW = 32, kH = 24;

// Smooth structure plus seeded noise, kept in [0.2, 0.8] so offsets of up to 0.2 stay in [0, 1].
Image pattern(int w, int h, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> noise(-0.1f, 0.1f);
    Image im(w, h);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            im.at(x, y) = 0.5f + 0.15f * std::sin(0.37f * x + seed) * std::cos(0.23f * y) + noise(rng);
    return im;
}

Image offset(const Image& im, float d) {
    Image out = im;
    for (float& v : out.pixels) v += d;
    return out;
}

Image withNoise(const Image& im, float sigma, unsigned seed) {
    std::mt19937 rng(seed);
    std::normal_distribution<float> n(0.0f, sigma);
    Image out = im;
    for (float& v : out.pixels) v += n(rng);
    return out;
}

// SSIM straight from the definition (Wang et al. 2004): a full 2D Gaussian window per position,
// normalised in 2D, no separability. An independent check of the optimised implementation.
double ssimDirect(const Image& a, const Image& b) {
    double w[11][11], wsum = 0.0;
    for (int j = 0; j < 11; ++j)
        for (int i = 0; i < 11; ++i) wsum += w[j][i] = std::exp(-((i - 5) * (i - 5) + (j - 5) * (j - 5)) / (2 * 1.5 * 1.5));
    const double c1 = 0.01 * 0.01, c2 = 0.03 * 0.03;
    double total = 0.0;
    int count = 0;
    for (int y0 = 0; y0 + 11 <= a.height; ++y0)
        for (int x0 = 0; x0 + 11 <= a.width; ++x0) {
            double ma = 0, mb = 0, saa = 0, sbb = 0, sab = 0;
            for (int j = 0; j < 11; ++j)
                for (int i = 0; i < 11; ++i) {
                    const double wi = w[j][i] / wsum, va = a.at(x0 + i, y0 + j), vb = b.at(x0 + i, y0 + j);
                    ma += wi * va, mb += wi * vb;
                }
            for (int j = 0; j < 11; ++j)
                for (int i = 0; i < 11; ++i) {
                    const double wi = w[j][i] / wsum, da = a.at(x0 + i, y0 + j) - ma, db = b.at(x0 + i, y0 + j) - mb;
                    saa += wi * da * da, sbb += wi * db * db, sab += wi * da * db;
                }
            total += (2 * ma * mb + c1) * (2 * sab + c2) / ((ma * ma + mb * mb + c1) * (saa + sbb + c2));
            ++count;
        }
    return total / count;
}

}  // namespace

// ---- per-image error figures ------------------------------------------------------------------

TEST(ImageMetrics, ConstantOffsetGivesAnalyticMaeRmsePsnr) {
    const Image a = pattern(kW, kH, 1);
    const ImageDiff d = imageDiff(a, offset(a, 0.1f));
    EXPECT_NEAR(d.mae, 0.1, 1e-6);
    EXPECT_NEAR(d.rmse, 0.1, 1e-6);
    EXPECT_NEAR(d.psnr, 20.0, 1e-4);  // 20 log10(1 / 0.1)
}

TEST(ImageMetrics, MixedErrorsSeparateMaeFromRmse) {
    // Half the pixels off by 0.2, half exact: MAE 0.1, RMSE sqrt(0.02), PSNR 20 log10(1/sqrt(0.02)).
    Image a(kW, kH, 0.5f), b = a;
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW / 2; ++x) b.at(x, y) = 0.75f;  // 0.25 off, exactly representable
    const ImageDiff d = imageDiff(a, b);
    EXPECT_NEAR(d.mae, 0.125, 1e-9);
    EXPECT_NEAR(d.rmse, std::sqrt(0.5 * 0.25 * 0.25), 1e-9);
    EXPECT_NEAR(d.psnr, -20.0 * std::log10(std::sqrt(0.5) * 0.25), 1e-6);
}

TEST(ImageMetrics, IdenticalImagesHaveInfinitePsnrWrittenAsNull) {
    const Image a = pattern(kW, kH, 2);
    const ImageDiff d = imageDiff(a, a);
    EXPECT_EQ(d.mae, 0.0);
    EXPECT_EQ(d.rmse, 0.0);
    EXPECT_TRUE(std::isinf(d.psnr) && d.psnr > 0);
    FrameMetrics f{"ao_0000.exr", 0, d.mae, d.rmse, d.psnr, 1.0};
    EXPECT_TRUE(toJson(f)["psnr"].is_null());
}

TEST(ImageMetrics, SizeMismatchThrowsWithBothSizes) {
    const Image a(kW, kH, 0.5f), b(16, 12, 0.5f);
    for (const std::string& msg : {errorMessage([&] { imageDiff(a, b); }), errorMessage([&] { ssim(a, b); })}) {
        EXPECT_NE(msg.find("32x24"), std::string::npos) << msg;
        EXPECT_NE(msg.find("16x12"), std::string::npos) << msg;
    }
}

// ---- SSIM ---------------------------------------------------------------------------------------

TEST(Ssim, IdenticalImagesGiveOne) {
    const Image a = pattern(kW, kH, 3);
    EXPECT_NEAR(ssim(a, a), 1.0, 1e-12);
}

TEST(Ssim, ConstantImagesGiveTheLuminanceTerm) {
    // No variance anywhere: the contrast-structure term is C2/C2 = 1 and SSIM is the luminance term
    // (2 mu_a mu_b + C1) / (mu_a^2 + mu_b^2 + C1) of Wang et al. eq. 13.
    const double c1 = 1e-4, ma = 0.5, mb = 0.6;
    const double expected = (2 * ma * mb + c1) / (ma * ma + mb * mb + c1);
    EXPECT_NEAR(ssim(Image(kW, kH, 0.5f), Image(kW, kH, 0.6f)), expected, 1e-6);
}

TEST(Ssim, MatchesDirectTwoDimensionalWindow) {
    const Image a = pattern(kW, kH, 4), b = withNoise(a, 0.05f, 5);
    EXPECT_NEAR(ssim(a, b), ssimDirect(a, b), 1e-9);
}

TEST(Ssim, IsSymmetric) {
    const Image a = pattern(kW, kH, 6), b = withNoise(a, 0.1f, 7);
    EXPECT_DOUBLE_EQ(ssim(a, b), ssim(b, a));
}

TEST(Ssim, DecreasesWithNoise) {
    const Image a = pattern(kW, kH, 8);
    double previous = 1.0;
    for (float sigma : {0.01f, 0.03f, 0.1f, 0.3f}) {
        const double s = ssim(a, withNoise(a, sigma, 9));
        EXPECT_LT(s, previous) << "sigma " << sigma;
        EXPECT_GT(s, -1.0);
        previous = s;
    }
}

TEST(Ssim, RejectsImagesSmallerThanTheWindow) {
    const Image a(10, 24, 0.5f);
    EXPECT_NE(errorMessage([&] { ssim(a, a); }).find("11x11"), std::string::npos);
}

// ---- flicker ------------------------------------------------------------------------------------

TEST(Flicker, ZeroForIdenticalSequencesAndSingleFrames) {
    const std::vector<Image> a = {pattern(kW, kH, 10), pattern(kW, kH, 11), pattern(kW, kH, 12)};
    EXPECT_EQ(temporalFlicker(a, a), 0.0);
    EXPECT_EQ(temporalFlicker({a[0]}, {pattern(kW, kH, 13)}), 0.0);  // no pair
}

TEST(Flicker, ZeroForAConstantPerPixelOffset) {
    // b_t = a_t + o(x, y): a static bias, which MAE measures, is not flicker.
    const Image o = withNoise(Image(kW, kH, 0.0f), 0.05f, 14);
    std::vector<Image> a, b;
    for (unsigned t = 0; t < 4; ++t) {
        a.push_back(pattern(kW, kH, 20 + t));
        b.push_back(a.back());
        for (std::size_t i = 0; i < o.pixelCount(); ++i) b.back().pixels[i] += o.pixels[i];
    }
    EXPECT_NEAR(temporalFlicker(a, b), 0.0, 1e-6);  // float rounding of a + o only
}

TEST(Flicker, HandComputedCase) {
    // 2x2 frames. A is static at 0.5. B's pixel (0,0) goes 0.5 -> 0.75 -> 0.5, the rest stays.
    // Pair 1: |0 - 0.25| at one pixel of 4 -> 0.0625; pair 2: |0 - (-0.25)| -> 0.0625. Mean 0.0625.
    const std::vector<Image> a(3, Image(2, 2, 0.5f));
    std::vector<Image> b = a;
    b[1].at(0, 0) = 0.75f;
    EXPECT_DOUBLE_EQ(temporalFlicker(a, b), 0.0625);
    EXPECT_DOUBLE_EQ(flickerPair(a[0], a[1], b[0], b[1]), 0.0625);
}

TEST(Flicker, DifferentLengthsThrow) {
    const std::vector<Image> a(3, Image(2, 2, 0.5f)), b(2, Image(2, 2, 0.5f));
    EXPECT_NE(errorMessage([&] { temporalFlicker(a, b); }).find("3 vs 2"), std::string::npos);
}

// ---- files --------------------------------------------------------------------------------------

TEST(ImageIo, ExrRoundTripIsBitExact) {
    TempDir dir("exr");
    Image a = pattern(kW, kH, 30);
    a.at(0, 0) = -0.25f;                                // out-of-range values survive too
    a.at(1, 0) = 1.5f;
    a.at(2, 0) = std::numeric_limits<float>::denorm_min();
    a.at(3, 0) = 0.1f;                                  // not exactly representable in half
    writeExr(dir / "ao_0000.exr", a);
    const Image b = readImage(dir / "ao_0000.exr");
    ASSERT_EQ(b.width, kW);
    ASSERT_EQ(b.height, kH);
    EXPECT_EQ(std::memcmp(a.pixels.data(), b.pixels.data(), a.pixels.size() * sizeof(float)), 0);
    // The atomic write leaves no temporary file behind.
    EXPECT_EQ(std::distance(fs::directory_iterator(dir.path()), fs::directory_iterator()), 1);
}

TEST(ImageIo, PngPreviewIsLinear8Bit) {
    TempDir dir("png");
    Image a(4, 1);
    a.pixels = {0.0f, 0.5f, 1.0f, 2.0f};
    writePng(dir / "preview.png", a);
    const Image b = readImage(dir / "preview.png");
    ASSERT_EQ(b.pixelCount(), 4u);
    EXPECT_NEAR(b.pixels[0], 0.0f, 1e-6);
    EXPECT_NEAR(b.pixels[1], 128.0f / 255.0f, 1e-6);  // linear: round(0.5 * 255) = 128, no sRGB curve
    EXPECT_NEAR(b.pixels[2], 1.0f, 1e-6);
    EXPECT_NEAR(b.pixels[3], 1.0f, 1e-6);  // clamped
    EXPECT_NE(errorMessage([&] { writePngRgb(dir / "rgb.png", 2, 2, std::vector<float>(5)); }).find("rgb.png"),
              std::string::npos);
    writePngRgb(dir / "rgb.png", 2, 1, {1, 0, 0, 0, 0, 1});
    EXPECT_NEAR(readImage(dir / "rgb.png").pixels[0], 1.0f, 1e-6);  // first channel (red)
}

TEST(ImageIo, ErrorsNameTheFile) {
    TempDir dir("ioerr");
    EXPECT_NE(errorMessage([&] { readImage(dir / "missing.exr"); }).find("missing.exr"), std::string::npos);
    EXPECT_NE(errorMessage([&] { writeExr(dir / "no_such_dir" / "x.exr", Image(2, 2)); }).find("x.exr"),
              std::string::npos);
}

TEST(ImageIo, HstackPlacesImagesSideBySide) {
    const Image a(3, 2, 0.0f), b(2, 4, 0.5f);
    const Image s = hstack({a, b}, 1);
    ASSERT_EQ(s.width, 6);
    ASSERT_EQ(s.height, 4);
    EXPECT_EQ(s.at(2, 1), 0.0f);  // a
    EXPECT_EQ(s.at(3, 0), 1.0f);  // gap, filled white
    EXPECT_EQ(s.at(4, 3), 0.5f);  // b
    EXPECT_EQ(s.at(0, 3), 1.0f);  // below the shorter a
    EXPECT_TRUE(hstack({}, 4).empty());
}

// ---- directories --------------------------------------------------------------------------------

TEST(CompareDirs, PairsFramesByNameWithAnalyticFigures) {
    TempDir a("pairA"), b("pairB");
    // Frame 5: B = A + 0.1; frame 6: B = A + 0.3. The per-pixel difference jumps by 0.2 -> flicker 0.2.
    const Image a5 = pattern(kW, kH, 40), a6 = pattern(kW, kH, 41);
    writeExr(a / "ao_0005.exr", a5);
    writeExr(a / "ao_0006.exr", a6);
    writeExr(b / "ao_0005.exr", offset(a5, 0.1f));
    writeExr(b / "ao_0006.exr", offset(a6, 0.3f));
    writePng(a / "ao_0005.png", a5);  // previews and other files are ignored

    const SequenceMetrics m = compareDirs(a.path(), b.path());
    ASSERT_EQ(m.frames.size(), 2u);
    EXPECT_EQ(m.frames[0].name, "ao_0005.exr");
    EXPECT_EQ(m.frames[0].frame, 5);
    EXPECT_EQ(m.frames[1].frame, 6);
    EXPECT_NEAR(m.frames[0].mae, 0.1, 1e-6);
    EXPECT_NEAR(m.frames[1].rmse, 0.3, 1e-6);
    EXPECT_NEAR(m.frames[0].psnr, 20.0, 1e-4);
    EXPECT_NEAR(m.mae, 0.2, 1e-6);
    EXPECT_NEAR(m.rmse, std::sqrt(0.05), 1e-6);  // over all pixels: sqrt((0.1^2 + 0.3^2) / 2)
    EXPECT_NEAR(m.psnr, -20.0 * std::log10(std::sqrt(0.05)), 1e-4);
    EXPECT_NEAR(m.ssim, (m.frames[0].ssim + m.frames[1].ssim) / 2, 1e-12);
    EXPECT_NEAR(m.flicker, 0.2, 1e-6);

    const nlohmann::json j = toJson(m);
    for (const char* key : {"mae", "rmse", "psnr", "ssim", "flicker"}) EXPECT_TRUE(j.at(key).is_number()) << key;
    ASSERT_EQ(j.at("frames").size(), 2u);
    for (const char* key : {"name", "frame", "mae", "rmse", "psnr", "ssim"})
        EXPECT_TRUE(j["frames"][1].contains(key)) << key;
}

TEST(CompareDirs, SortsByFrameIndexNotByText) {
    TempDir a("sortA"), b("sortB");
    for (const char* name : {"ao_10000.exr", "ao_9999.exr"}) {
        writeExr(a / name, Image(kW, kH, 0.5f));
        writeExr(b / name, Image(kW, kH, 0.5f));
    }
    const SequenceMetrics m = compareDirs(a.path(), b.path());
    ASSERT_EQ(m.frames.size(), 2u);
    EXPECT_EQ(m.frames[0].frame, 9999);
    EXPECT_EQ(m.frames[1].frame, 10000);
    EXPECT_TRUE(std::isinf(m.psnr));
    EXPECT_NEAR(m.ssim, 1.0, 1e-12);
}

TEST(CompareDirs, MismatchedFrameSetsListWhatIsMissingWhere) {
    TempDir a("setA"), b("setB");
    for (const char* name : {"ao_0005.exr", "ao_0006.exr", "ao_0007.exr"}) writeExr(a / name, Image(kW, kH, 0.5f));
    for (const char* name : {"ao_0005.exr", "ao_0006.exr", "ao_0008.exr"}) writeExr(b / name, Image(kW, kH, 0.5f));
    const std::string msg = errorMessage([&] { compareDirs(a.path(), b.path()); });
    EXPECT_NE(msg.find("missing in '" + a.path().string() + "': ao_0008.exr"), std::string::npos) << msg;
    EXPECT_NE(msg.find("missing in '" + b.path().string() + "': ao_0007.exr"), std::string::npos) << msg;

    fs::remove(b / "ao_0008.exr");  // now only the count differs: 3 vs 2
    const std::string count = errorMessage([&] { compareDirs(a.path(), b.path()); });
    EXPECT_NE(count.find("missing in '" + b.path().string() + "': ao_0007.exr"), std::string::npos) << count;
    EXPECT_EQ(count.find("missing in '" + a.path().string() + "'"), std::string::npos) << count;
}

TEST(CompareDirs, EmptyOrMissingDirectoriesThrow) {
    TempDir a("emptyA"), b("emptyB");
    writeExr(a / "ao_0000.exr", Image(kW, kH, 0.5f));
    EXPECT_NE(errorMessage([&] { compareDirs(a.path(), b.path()); }).find("no frame files"), std::string::npos);
    EXPECT_NE(errorMessage([&] { compareDirs(a.path(), b / "nope"); }).find("does not exist"), std::string::npos);
}

TEST(CompareDirs, SizeMismatchNamesBothFilesAndSizes) {
    TempDir a("sizeA"), b("sizeB");
    writeExr(a / "ao_0001.exr", Image(kW, kH, 0.5f));
    writeExr(b / "ao_0001.exr", Image(16, 12, 0.5f));
    const std::string msg = errorMessage([&] { compareDirs(a.path(), b.path()); });
    EXPECT_NE(msg.find((a / "ao_0001.exr").string() + "' is 32x24"), std::string::npos) << msg;
    EXPECT_NE(msg.find((b / "ao_0001.exr").string() + "' is 16x12"), std::string::npos) << msg;
}

TEST(CompareDirs, NonFiniteValuesAreRefused) {
    TempDir a("nanA"), b("nanB");
    Image bad(kW, kH, 0.5f);
    bad.at(3, 2) = std::numeric_limits<float>::quiet_NaN();
    writeExr(a / "ao_0001.exr", bad);
    writeExr(b / "ao_0001.exr", Image(kW, kH, 0.5f));
    const std::string msg = errorMessage([&] { compareDirs(a.path(), b.path()); });
    EXPECT_NE(msg.find("ao_0001.exr"), std::string::npos) << msg;
    EXPECT_NE(msg.find("(3, 2)"), std::string::npos) << msg;
}

// The CLI end to end: table, then the JSON object as the last line; a missing directory exits 1.
TEST(CompareCli, PrintsJsonLastAndFailsOnMissingDirs) {
    TempDir a("cliA"), b("cliB");
    writeExr(a / "ao_0000.exr", Image(kW, kH, 0.5f));
    writeExr(b / "ao_0000.exr", Image(kW, kH, 0.6f));
    const std::string cmd = std::string(cubeao::test::cubeaoBinary()) + " compare '" + a.path().string() + "' '" +
                            b.path().string() + "' --json";
    FILE* p = ::popen(cmd.c_str(), "r");
    ASSERT_NE(p, nullptr);
    std::string out, last;
    std::array<char, 4096> buf{};
    while (std::fgets(buf.data(), buf.size(), p)) out += buf.data();
    ASSERT_EQ(WEXITSTATUS(::pclose(p)), 0) << out;
    out.pop_back();  // trailing newline
    last = out.substr(out.rfind('\n') + 1);
    const nlohmann::json j = nlohmann::json::parse(last);
    EXPECT_NEAR(j.at("mae").get<double>(), 0.1, 1e-6);
    EXPECT_EQ(j.at("frames").size(), 1u);

    const std::string bad = std::string(cubeao::test::cubeaoBinary()) + " compare '" + (a / "nope").string() + "' '" +
                            b.path().string() + "' 2>/dev/null";
    EXPECT_EQ(WEXITSTATUS(std::system(bad.c_str())), 1);
}
