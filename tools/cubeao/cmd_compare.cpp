// `cubeao compare DIR_A DIR_B [--json]`: per-frame and overall MAE, RMSE, PSNR, SSIM and flicker of
// two directories of ao_NNNN.exr frames, paired by file name (DESIGN.md §5). Usually DIR_A is a
// render and DIR_B the Embree reference; the figures are symmetric, so the order does not matter.
#include <cstdio>
#include <memory>
#include <string>

#include "commands.h"
#include "cubeao/metrics/image_metrics.h"

namespace cubeao::cli {
namespace {

struct CompareOptions {
    std::string dirA, dirB;
    bool json = false;
};

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
    if (opt.json) {
        nlohmann::json j = toJson(m);
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
    cmd->add_flag("--json", opt->json, "Print the figures as one JSON object on the last line of stdout");
    cmd->callback([opt] { runCompare(*opt); });
}

}  // namespace cubeao::cli
