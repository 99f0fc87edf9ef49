// Image and sequence metrics; definitions and conventions are in image_metrics.h.
#include "cubeao/metrics/image_metrics.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numeric>
#include <regex>
#include <set>

#include "cubeao/core/error.h"
#include "cubeao/metrics/image_io.h"
#include "cubeao/metrics/oiio_module.h"

namespace cubeao {
namespace fs = std::filesystem;

namespace {

std::string sizeString(const Image& im) { return std::to_string(im.width) + "x" + std::to_string(im.height); }

void requireSameSize(const Image& a, const Image& b, const char* what) {
    if (!a.sameSize(b))
        throw Error(std::string(what) + ": image sizes differ: " + sizeString(a) + " vs " + sizeString(b));
    if (a.empty())
        throw Error(std::string(what) + ": images are empty");
}

// ---- SSIM (Wang et al. 2004) -------------------------------------------------------------------
constexpr int kSsimRadius = 5;  // 11x11 window
constexpr int kSsimTaps = 2 * kSsimRadius + 1;
constexpr double kSsimSigma = 1.5;
constexpr double kC1 = (0.01 * 1.0) * (0.01 * 1.0);  // (K1 L)^2, L = 1
constexpr double kC2 = (0.03 * 1.0) * (0.03 * 1.0);  // (K2 L)^2

std::array<double, kSsimTaps> gaussianWindow() {
    std::array<double, kSsimTaps> w{};
    for (int i = 0; i < kSsimTaps; ++i) {
        const double d = i - kSsimRadius;
        w[i] = std::exp(-d * d / (2.0 * kSsimSigma * kSsimSigma));
    }
    const double sum = std::accumulate(w.begin(), w.end(), 0.0);
    for (double& v : w) v /= sum;  // the 2D window w_i w_j then sums to 1 as well
    return w;
}

// Local moments of a window: E[a], E[b], E[a^2], E[b^2], E[ab].
using Moments = std::array<double, 5>;

// Sum of the SSIM map over output row `oy` (windows covering input rows oy..oy+10). The window is
// separable: filter the 11 input rows vertically into `column` (one Moments per input column),
// then horizontally. Each output row needs its own vertical pass, so this costs no more than a
// whole-image separable filter and needs only one row of scratch.
double ssimRowSum(const Image& a, const Image& b, int oy, const std::array<double, kSsimTaps>& w,
                  std::vector<Moments>& column) {
    for (int x = 0; x < a.width; ++x) {
        Moments m{};
        for (int k = 0; k < kSsimTaps; ++k) {
            const double va = a.at(x, oy + k), vb = b.at(x, oy + k);
            m[0] += w[k] * va;
            m[1] += w[k] * vb;
            m[2] += w[k] * va * va;
            m[3] += w[k] * vb * vb;
            m[4] += w[k] * va * vb;
        }
        column[x] = m;
    }
    double sum = 0.0;
    for (int ox = 0; ox + kSsimTaps <= a.width; ++ox) {
        Moments m{};
        for (int k = 0; k < kSsimTaps; ++k)
            for (int c = 0; c < 5; ++c) m[c] += w[k] * column[ox + k][c];
        const double mu_a = m[0], mu_b = m[1];
        const double var_a = m[2] - mu_a * mu_a, var_b = m[3] - mu_b * mu_b, cov = m[4] - mu_a * mu_b;
        // Wang et al. 2004, eq. 13
        sum += ((2.0 * mu_a * mu_b + kC1) * (2.0 * cov + kC2)) /
               ((mu_a * mu_a + mu_b * mu_b + kC1) * (var_a + var_b + kC2));
    }
    return sum;
}

// ---- frame directories -----------------------------------------------------------------------
struct FrameFile {
    int frame;
    std::string name;
    bool operator<(const FrameFile& o) const { return frame != o.frame ? frame < o.frame : name < o.name; }
};

// Built with += because g++ 12 -O2 gives a false -Wrestrict on "'" + std::string (GCC PR 105329).
std::string quoted(const fs::path& p) {
    std::string s(1, '\'');
    s += p.string();
    s += '\'';
    return s;
}

std::vector<FrameFile> listFrames(const fs::path& dir) {
    std::error_code ec;
    if (!fs::exists(dir, ec))
        throw Error("compare: directory " + quoted(dir) + " does not exist");
    if (!fs::is_directory(dir, ec))
        throw Error("compare: " + quoted(dir) + " is not a directory");
    static const std::regex kFrameName(R"(ao_(\d{1,9})\.exr)");
    std::vector<FrameFile> frames;
    for (const fs::directory_entry& e : fs::directory_iterator(dir)) {
        const std::string name = e.path().filename().string();
        std::smatch m;
        if (std::regex_match(name, m, kFrameName))
            frames.push_back({std::stoi(m[1].str()), name});
    }
    if (frames.empty())
        throw Error("compare: no frame files ao_NNNN.exr in " + quoted(dir));
    std::sort(frames.begin(), frames.end());
    return frames;
}

// "a, b, c" with at most kShown names, so a wrong directory does not flood the terminal.
std::string nameList(const std::vector<std::string>& names) {
    constexpr std::size_t kShown = 10;
    std::string s;
    for (std::size_t i = 0; i < std::min(names.size(), kShown); ++i) s += (i ? ", " : "") + names[i];
    if (names.size() > kShown) s += ", ... (" + std::to_string(names.size() - kShown) + " more)";
    return s;
}

void requireSameFrames(const fs::path& dirA, const std::vector<FrameFile>& a, const fs::path& dirB,
                       const std::vector<FrameFile>& b) {
    std::set<std::string> namesA, namesB;
    for (const FrameFile& f : a) namesA.insert(f.name);
    for (const FrameFile& f : b) namesB.insert(f.name);
    std::vector<std::string> missingInA, missingInB;
    std::set_difference(namesB.begin(), namesB.end(), namesA.begin(), namesA.end(), std::back_inserter(missingInA));
    std::set_difference(namesA.begin(), namesA.end(), namesB.begin(), namesB.end(), std::back_inserter(missingInB));
    if (missingInA.empty() && missingInB.empty())
        return;
    std::string msg = "compare: frame files differ (" + std::to_string(a.size()) + " in " + quoted(dirA) + ", " +
                      std::to_string(b.size()) + " in " + quoted(dirB) + ")";
    if (!missingInA.empty())
        msg += "; missing in " + quoted(dirA) + ": " + nameList(missingInA);
    if (!missingInB.empty())
        msg += "; missing in " + quoted(dirB) + ": " + nameList(missingInB);
    throw Error(msg);
}

// A NaN or inf would silently turn every figure into NaN: refuse it and say where it is.
Image loadFrame(const fs::path& path) {
    Image im = readImage(path);
    const auto bad = std::find_if(im.pixels.begin(), im.pixels.end(), [](float v) { return !std::isfinite(v); });
    if (bad != im.pixels.end()) {
        const auto i = static_cast<std::size_t>(bad - im.pixels.begin());
        throw Error("compare: " + quoted(path) + " has a non-finite value at pixel (" + std::to_string(i % im.width) +
                    ", " + std::to_string(i / im.width) + ")");
    }
    return im;
}

void requirePairedSize(const fs::path& pathA, const Image& a, const fs::path& pathB, const Image& b) {
    if (!a.sameSize(b))
        throw Error("compare: image sizes differ: " + quoted(pathA) + " is " + sizeString(a) + ", " + quoted(pathB) +
                    " is " + sizeString(b));
}

nlohmann::json psnrJson(double psnr) { return std::isfinite(psnr) ? nlohmann::json(psnr) : nlohmann::json(nullptr); }

}  // namespace

double psnrFromRmse(double rmse) {
    return rmse > 0.0 ? 20.0 * std::log10(1.0 / rmse) : std::numeric_limits<double>::infinity();
}

ImageDiff imageDiff(const Image& a, const Image& b) {
    requireSameSize(a, b, "imageDiff");
    double mean = 0.0, rms = 0.0;
    const std::string why = oiio::api().compare(a.pixels.data(), b.pixels.data(), a.width, a.height, &mean, &rms);
    if (!why.empty())
        throw Error("imageDiff: OpenImageIO compare failed: " + why);
    // OIIO's PSNR is the same 20 log10(1/rms) for peak 1; recompute it so the rms = 0 case follows
    // our documented +infinity convention.
    return {mean, rms, psnrFromRmse(rms)};
}

double ssim(const Image& a, const Image& b) {
    requireSameSize(a, b, "ssim");
    if (a.width < kSsimTaps || a.height < kSsimTaps)
        throw Error("ssim: needs at least 11x11 pixels (the Gaussian window), got " + sizeString(a));
    const auto w = gaussianWindow();
    const int rows = a.height - kSsimTaps + 1, cols = a.width - kSsimTaps + 1;
    // Per-row sums, added in order afterwards, so the result does not depend on the thread count.
    std::vector<double> rowSums(rows);
    tbb::parallel_for(tbb::blocked_range<int>(0, rows), [&](const tbb::blocked_range<int>& range) {
        std::vector<Moments> column(a.width);
        for (int oy = range.begin(); oy != range.end(); ++oy) rowSums[oy] = ssimRowSum(a, b, oy, w, column);
    });
    return std::accumulate(rowSums.begin(), rowSums.end(), 0.0) / (static_cast<double>(rows) * cols);
}

double flickerPair(const Image& aPrev, const Image& a, const Image& bPrev, const Image& b) {
    requireSameSize(aPrev, a, "flicker");
    requireSameSize(bPrev, b, "flicker");
    requireSameSize(a, b, "flicker");
    double sum = 0.0;
    for (std::size_t i = 0; i < a.pixelCount(); ++i) {
        const double changeA = double(a.pixels[i]) - aPrev.pixels[i];
        const double changeB = double(b.pixels[i]) - bPrev.pixels[i];
        sum += std::abs(changeA - changeB);
    }
    return sum / static_cast<double>(a.pixelCount());
}

double temporalFlicker(const std::vector<Image>& a, const std::vector<Image>& b) {
    if (a.size() != b.size())
        throw Error("flicker: sequences differ in length: " + std::to_string(a.size()) + " vs " +
                    std::to_string(b.size()) + " frames");
    if (a.size() < 2)
        return 0.0;  // no consecutive pair, nothing can flicker
    double sum = 0.0;
    for (std::size_t t = 1; t < a.size(); ++t) sum += flickerPair(a[t - 1], a[t], b[t - 1], b[t]);
    return sum / static_cast<double>(a.size() - 1);
}

SequenceMetrics compareDirs(const fs::path& dirA, const fs::path& dirB) {
    const std::vector<FrameFile> framesA = listFrames(dirA), framesB = listFrames(dirB);
    requireSameFrames(dirA, framesA, dirB, framesB);

    SequenceMetrics out;
    double absSum = 0.0, sqSum = 0.0, ssimSum = 0.0, flickerSum = 0.0, pixels = 0.0;
    Image prevA, prevB;
    fs::path prevPath;
    for (const FrameFile& f : framesA) {
        const fs::path pathA = dirA / f.name, pathB = dirB / f.name;
        Image a = loadFrame(pathA), b = loadFrame(pathB);
        requirePairedSize(pathA, a, pathB, b);
        if (!prevA.empty()) {
            requirePairedSize(prevPath, prevA, pathA, a);  // flicker needs one size along the sequence
            flickerSum += flickerPair(prevA, a, prevB, b);
        }
        const ImageDiff d = imageDiff(a, b);
        const double s = ssim(a, b);
        out.frames.push_back({f.name, f.frame, d.mae, d.rmse, d.psnr, s});
        const double n = static_cast<double>(a.pixelCount());
        absSum += d.mae * n;
        sqSum += d.rmse * d.rmse * n;
        ssimSum += s;
        pixels += n;
        prevA = std::move(a), prevB = std::move(b), prevPath = pathA;
    }
    const double frames = static_cast<double>(out.frames.size());
    out.mae = absSum / pixels;
    out.rmse = std::sqrt(sqSum / pixels);
    out.psnr = psnrFromRmse(out.rmse);
    out.ssim = ssimSum / frames;
    out.flicker = frames > 1 ? flickerSum / (frames - 1) : 0.0;
    return out;
}

nlohmann::json toJson(const FrameMetrics& f) {
    return {{"name", f.name}, {"frame", f.frame}, {"mae", f.mae},
            {"rmse", f.rmse}, {"psnr", psnrJson(f.psnr)}, {"ssim", f.ssim}};
}

nlohmann::json toJson(const SequenceMetrics& m) {
    nlohmann::json frames = nlohmann::json::array();
    for (const FrameMetrics& f : m.frames) frames.push_back(toJson(f));
    return {{"mae", m.mae},   {"rmse", m.rmse},       {"psnr", psnrJson(m.psnr)},
            {"ssim", m.ssim}, {"flicker", m.flicker}, {"frames", std::move(frames)}};
}

}  // namespace cubeao
