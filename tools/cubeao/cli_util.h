// Small helpers several subcommands share (header-only: the CLI is one executable).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <type_traits>
#include <vector>

#include "cubeao/core/error.h"
#include "cubeao/scene/camera_path.h"

namespace cubeao::cli {

// Median of timings (0 for none): what every `timings_ms` reports, robust to one slow first frame.
inline double median(std::vector<double> v) {
    if (v.empty()) return 0.0;
    std::sort(v.begin(), v.end());
    const std::size_t n = v.size();
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

// A number as a message shows it: integers exactly, floating point with %g.
template <class T>
std::string numberText(T v) {
    if constexpr (std::is_integral_v<T>) {
        return std::to_string(v);
    } else {
        char buf[32];
        std::snprintf(buf, sizeof buf, "%g", double(v));
        return buf;
    }
}
// checkRange refuses an absurd numeric option before any work or allocation (issue 15), naming the
// option and the range: UsageError "--res must be between 4 and 4096 (got 65536)". `note` follows the
// range, e.g. " (0: the default)". NaN fails both comparisons, so it is refused too. (CLI11's
// CLI::Range and CLI::PositiveNumber say "Value 0 not in range 0.000000 to 1.79769e+308" for some
// types.) rangeProblem is its message, or "" when `value` lies in [lo, hi], for commands that list
// every problem at once.
template <class T, class U>
std::string rangeProblem(const std::string& option, T value, U lo, U hi, const std::string& note = "") {
    if (value >= T(lo) && value <= T(hi)) return "";
    return option + " must be between " + numberText(T(lo)) + " and " + numberText(T(hi)) + note + " (got " +
           numberText(value) + ")";
}
template <class T, class U>
void checkRange(const std::string& option, T value, U lo, U hi, const std::string& note = "") {
    if (std::string problem = rangeProblem(option, value, lo, hi, note); !problem.empty()) throw UsageError(problem);
}

// A length or factor where 0 picks the default: finite and ≥ 0 (inf, NaN and negatives refused).
inline void checkFiniteNonNegative(const std::string& option, float value, const std::string& note = "") {
    if (std::isfinite(value) && value >= 0.0f) return;
    throw UsageError(option + " must be a finite number >= 0" + note + " (got " + numberText(value) + ")");
}

// Largest image side any command renders: the smallest GL_MAX_TEXTURE_SIZE OpenGL 4.5 guarantees.
constexpr int kMaxImageSide = 16384;

// --width/--height as given (0: from the camera file); a command checks them before it loads anything.
inline void checkImageSizeOptions(int width, int height) {
    checkRange("--width", width, 0, kMaxImageSide, " (0: from the camera file)");
    checkRange("--height", height, 0, kMaxImageSide, " (0: from the camera file)");
}

// --width/--height: either, both or neither; the missing one keeps the camera file's aspect, so
// `reference` and `render` write images of the same size.
inline void resolveImageSize(int width, int height, const CameraPath& path, int& w, int& h) {
    checkImageSizeOptions(width, height);
    w = width, h = height;
    if (!w && !h) w = path.width, h = path.height;
    if (!w) w = std::max(1, int(std::lround(double(h) * path.width / path.height)));
    if (!h) h = std::max(1, int(std::lround(double(w) * path.height / path.width)));
    // The side the camera file's aspect gives the other one.
    checkRange("the image width (--width, or --height times the camera's aspect)", w, 1, kMaxImageSide);
    checkRange("the image height (--height, or --width over the camera's aspect)", h, 1, kMaxImageSide);
}

// --gpu-budget-mb and --upload-mb, MiB, as `render`, `bench render`, cubeao-gpubench and cubeao-view take
// them (ResidencySettings::fromMib): their problems (empty: both fine; 1 TiB is beyond any GPU made, the
// lower bound is checked against the cache once it is read). A negative count would wrap to a huge budget.
inline std::vector<std::string> residencyOptionProblems(double gpuBudgetMb, double uploadMb) {
    std::vector<std::string> problems;
    if (!(gpuBudgetMb >= 0.0 && gpuBudgetMb <= 1024.0 * 1024.0))
        problems.push_back("--gpu-budget-mb must lie in [0, 1048576] (0 = every probe resident)");
    if (!(uploadMb >= 0.0 && uploadMb <= 65536.0))
        problems.push_back("--upload-mb must lie in [0, 65536] (0 = the default, 8)");
    return problems;
}
inline void checkResidencyOptions(double gpuBudgetMb, double uploadMb) {
    if (const auto problems = residencyOptionProblems(gpuBudgetMb, uploadMb); !problems.empty())
        throw UsageError(problems.front());
}

// "ao_0005.exr": the camera path's frame index, so `compare` pairs files by name.
inline std::string frameName(const char* prefix, std::size_t index, const char* ext) {
    char buf[48];
    std::snprintf(buf, sizeof buf, "%s_%04zu.%s", prefix, index, ext);
    return buf;
}

}  // namespace cubeao::cli
