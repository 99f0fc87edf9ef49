// Small helpers several subcommands share (header-only: the CLI is one executable).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
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

// --width/--height: either, both or neither; the missing one keeps the camera file's aspect, so
// `reference` and `render` write images of the same size.
inline void resolveImageSize(int width, int height, const CameraPath& path, int& w, int& h) {
    w = width, h = height;
    if (w < 0 || h < 0) throw UsageError("--width and --height must be positive");
    if (!w && !h) w = path.width, h = path.height;
    if (!w) w = std::max(1, int(std::lround(double(h) * path.width / path.height)));
    if (!h) h = std::max(1, int(std::lround(double(w) * path.height / path.width)));
}

// "ao_0005.exr": the camera path's frame index, so `compare` pairs files by name.
inline std::string frameName(const char* prefix, std::size_t index, const char* ext) {
    char buf[48];
    std::snprintf(buf, sizeof buf, "%s_%04zu.%s", prefix, index, ext);
    return buf;
}

}  // namespace cubeao::cli
