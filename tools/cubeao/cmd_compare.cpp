// `cubeao compare DIR_A DIR_B [--where-differs DIR_C] [--json]`: per-frame and overall MAE, RMSE, PSNR, SSIM and flicker of
// two directories of ao_NNNN.exr frames, paired by file name (DESIGN.md §5). Usually DIR_A is a
// render and DIR_B the Embree reference; the figures are symmetric, so the order does not matter.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>

#include "commands.h"
#include "cubeao/core/error.h"
#include "cubeao/metrics/image_io.h"
#include "cubeao/metrics/image_metrics.h"

namespace cubeao::cli {
namespace {

namespace fs = std::filesystem;

struct CompareOptions {
    std::string dirA, dirB, whereDiffers;
    bool json = false;
};

// MAE against B of A and of C over the pixels where A and C differ: how two renders that differ in
// a few pixels only (e.g. `render --fallback gtao` and `--fallback none`, which differ where no
// probe saw the surface and around it) compare there, where the whole-frame MAE dilutes it.
nlohmann::json maeWhereDiffers(const SequenceMetrics& m, const CompareOptions& opt) {
    double sumA = 0.0, sumC = 0.0, pixels = 0.0, total = 0.0;
    for (const FrameMetrics& f : m.frames) {
        const Image a = readImage(fs::path(opt.dirA) / f.name), b = readImage(fs::path(opt.dirB) / f.name);
        const Image c = readImage(fs::path(opt.whereDiffers) / f.name);
        if (c.width != a.width || c.height != a.height)
            throw Error(opt.whereDiffers + "/" + f.name + ": " + std::to_string(c.width) + "x" + std::to_string(c.height) +
                        ", " + opt.dirA + " has " + std::to_string(a.width) + "x" + std::to_string(a.height));
        total += double(a.pixels.size());
        for (std::size_t i = 0; i < a.pixels.size(); ++i) {
            if (std::fabs(a.pixels[i] - c.pixels[i]) <= 1e-6f) continue;
            sumA += std::fabs(double(a.pixels[i]) - b.pixels[i]), sumC += std::fabs(double(c.pixels[i]) - b.pixels[i]);
            pixels += 1.0;
        }
    }
    const double n = std::max(pixels, 1.0);
    return {{"dir", opt.whereDiffers}, {"fraction", pixels / std::max(total, 1.0)}, {"mae_a", sumA / n}, {"mae_c", sumC / n}};
}

void printTable(const SequenceMetrics& m) {
    std::printf("%6s  %-16s %10s %10s %9s %8s\n", "frame", "name", "MAE", "RMSE", "PSNR dB", "SSIM");
    for (const FrameMetrics& f : m.frames)
        std::printf("%6d  %-16s %10.6f %10.6f %9.2f %8.5f\n", f.frame, f.name.c_str(), f.mae, f.rmse, f.psnr, f.ssim);
    const std::string overall = "overall (" + std::to_string(m.frames.size()) + ")";
    std::printf("%-24s %10.6f %10.6f %9.2f %8.5f\n", overall.c_str(), m.mae, m.rmse, m.psnr, m.ssim);
    std::printf("flicker %.6f\n", m.flicker);
}

void runCompare(const CompareOptions& opt) {
    // compareDirs throws cubeao::Error (exit 1) for missing directories and mismatched frames.
    const SequenceMetrics m = compareDirs(opt.dirA, opt.dirB);
    printTable(m);
    nlohmann::json where;
    if (!opt.whereDiffers.empty()) {
        where = maeWhereDiffers(m, opt);
        std::printf("where %s differs (%.4f of the pixels): MAE %.6f, %s there: %.6f\n", opt.whereDiffers.c_str(),
                    where["fraction"].get<double>(), where["mae_a"].get<double>(), opt.whereDiffers.c_str(),
                    where["mae_c"].get<double>());
    }
    if (opt.json) {
        nlohmann::json j = toJson(m);
        if (!where.is_null()) j["where_differs"] = where;
        j["a"] = opt.dirA;
        j["b"] = opt.dirB;
        std::fflush(stdout);  // table (stdio) before the JSON line (iostream), even if stdio sync is off
        printJson(j);
    }
}

}  // namespace

void addCompare(CLI::App& app) {
    auto opt = std::make_shared<CompareOptions>();
    CLI::App* cmd = app.add_subcommand(
        "compare", "Per-frame and overall MAE, RMSE, PSNR, SSIM and flicker of two directories of ao_NNNN.exr");
    // Plain strings, not CLI::ExistingDirectory: a missing directory is a failure (exit 1), not bad usage.
    cmd->add_option("DIR_A", opt->dirA, "Directory of ao_NNNN.exr frames (e.g. a render)")->required();
    cmd->add_option("DIR_B", opt->dirB, "Directory with the same frame files (e.g. the reference)")->required();
    cmd->add_option("--where-differs", opt->whereDiffers,
                    "DIR_C: also the MAE against DIR_B of DIR_A and of DIR_C over the pixels where they differ");
    cmd->add_flag("--json", opt->json, "Print the figures as one JSON object on the last line of stdout");
    cmd->callback([opt] { runCompare(*opt); });
}

}  // namespace cubeao::cli
