// What `render` and `bench render` share to set up and report run-time frames (header-only, like
// cli_util.h): the AO pass for a method, one path frame's view, the preview's composite settings
// and the per-pass medians of a run.
#pragma once

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <memory>
#include <random>
#include <string>
#include <system_error>
#include <vector>

#include <unistd.h>

#include <glm/common.hpp>

#include <nlohmann/json.hpp>

#include "cli_util.h"
#include "cubeao/cache/cache_file.h"
#include "cubeao/runtime/probe_projection.h"
#include "cubeao/runtime/renderer.h"
#include "cubeao/scene/scene.h"
#include "cubeao/ssao/gtao_fallback.h"
#include "cubeao/ssao/ssao_pass.h"

namespace cubeao::cli {

// --gpu-budget-mb and --upload-mb, MiB, as `render`, `bench render` and cubeao-view take them: their
// problems (empty: both fine; 1 TiB is beyond any GPU made, the lower bound is checked against the cache
// once it is read), and the ResidencySettings they give.
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
inline ResidencySettings residencySettings(double gpuBudgetMb, double uploadMb) {
    constexpr double kMib = 1024.0 * 1024.0;
    return {std::size_t(gpuBudgetMb * kMib), std::size_t(uploadMb * kMib)};
}

// The method as a pass from the camera G-buffer to raw AO; blur and composite are shared. With a
// cache: the probe projection (grid over the scene's bounds, residency per `probes`), its uncovered
// pixels filled by GTAO with `ssao`'s settings unless `fallback` is off; without: the baseline `ssao`
// names (resolved settings). The cache must outlive the pass (probes stream from it).
inline std::unique_ptr<AoPass> makeAoPass(const SsaoSettings& ssao, const CacheReader* cache, const Scene& scene,
                                          const ProbeProjectionSettings& probes = {}, bool fallback = true) {
    if (!cache) return std::make_unique<SsaoPass>(ssao);
    auto pass = std::make_unique<ProbeProjectionPass>(*cache, scene.positions, scene.indices, probes);
    if (fallback) {
        SsaoSettings gtao = ssao;
        gtao.method = SsaoMethod::Gtao;
        pass->setFallback(std::make_unique<GtaoFallback>(gtao));
    }
    return pass;
}

// What the probes' residency did over a run (render's and bench render's `residency`).
inline nlohmann::json residencyJson(const ProbeProjectionPass& p) {
    const ResidencyStats& r = p.residency().stats();
    return {{"gpu_bytes", p.gpuBytes()},
            {"slots", r.slots},
            {"resident", r.resident},
            {"loads", r.loads},
            {"evictions", r.evictions},
            {"upload_bound_bytes", p.residency().uploadBound()},
            {"max_frame_upload_bytes", r.maxFrameUploadBytes},
            {"damaged", r.damaged}};
}

// The camera path's frame `frame` at width × height.
inline CameraView frameView(const CameraPath& path, std::size_t frame, int width, int height) {
    return CameraView::fromPinhole(PinholeCamera(path, frame, width, height), path.nearPlane);
}

// The preview's lighting for `scene`: the default light around its up axis, AO strength alpha.
inline CompositeSettings compositeFor(const Scene& scene, float alpha) {
    CompositeSettings c;
    c.alpha = alpha;
    c.lightDirection = defaultLightDirection(scene.up);
    return c;
}

// Points scattered around a walk, the benchmarks' probe positions: a uniform point of the eye
// polyline, a uniform direction, a uniform distance up to reach(eye, direction) (Embree's free
// distance for `bench render`, a fixed spread for cubeao-gpubench). Deterministic (fixed seed).
template <class Reach>
std::vector<glm::vec3> scatterAroundWalk(const CameraPath& path, std::size_t count, Reach reach) {
    std::mt19937 rng(1);
    const auto uniform = [&] { return float(rng() >> 8) * (1.0f / 16777216.0f); };
    std::vector<glm::vec3> out;
    while (out.size() < count) {
        const float u = uniform() * float(path.frames.size() - 1);
        const std::size_t i = std::size_t(u), j = std::min(i + 1, path.frames.size() - 1);
        const glm::vec3 eye = glm::mix(path.frames[i].eye, path.frames[j].eye, u - float(i));
        const float z = 1.0f - 2.0f * uniform(), phi = 6.2831853f * uniform(), r = std::sqrt(std::max(0.0f, 1.0f - z * z));
        const glm::vec3 dir(r * std::cos(phi), z, r * std::sin(phi));
        const float far = reach(eye, dir);
        out.push_back(eye + dir * (uniform() * far));
    }
    return out;
}

// A scratch directory named PREFIX-PID under the temporary directory, removed with what it holds.
struct ScratchDir {
    std::filesystem::path path;
    explicit ScratchDir(const std::string& prefix)
        : path(std::filesystem::temp_directory_path() / (prefix + "-" + std::to_string(::getpid()))) {
        std::filesystem::create_directories(path);
    }
    ScratchDir(const ScratchDir&) = delete;
    ScratchDir& operator=(const ScratchDir&) = delete;
    ~ScratchDir() {
        std::error_code ignored;
        std::filesystem::remove_all(path, ignored);
    }
};

// Median ms per pass over a run's frames (each pass's own median; ao_blur and gpu_total are the
// medians of the per-frame sums): what `timings_ms` reports.
inline nlohmann::json timingsJson(const std::vector<PassTimings>& t) {
    std::vector<double> g, ao, blur, comp, read, aoBlur, total;
    for (const PassTimings& p : t) {
        g.push_back(p.gbuffer), ao.push_back(p.ao), blur.push_back(p.blur), comp.push_back(p.composite);
        read.push_back(p.readback), aoBlur.push_back(p.ao + p.blur);
        total.push_back(p.gbuffer + p.ao + p.blur + p.composite);
    }
    return {{"gbuffer", median(g)},       {"ao", median(ao)},         {"blur", median(blur)},
            {"composite", median(comp)},  {"readback", median(read)}, {"ao_blur", median(aoBlur)},
            {"gpu_total", median(total)}};
}

}  // namespace cubeao::cli
