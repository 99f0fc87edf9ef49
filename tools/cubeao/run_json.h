// The JSON figures `render`, `bench render` and cubeao-gpubench report about a run's frames (header-only,
// like cli_util.h): the probes' residency and the per-pass median times.
#pragma once

#include <vector>

#include <nlohmann/json.hpp>

#include "cli_util.h"
#include "cubeao/runtime/probe_projection.h"
#include "cubeao/runtime/renderer.h"

namespace cubeao::cli {

// What the probes' residency did over a run (`residency`).
inline nlohmann::json residencyJson(const ProbeProjectionPass& p) {
    const ResidencyStats& r = p.residency().stats();
    return {{"gpu_bytes", p.gpuBytes()},
            {"slots", r.slots},
            {"resident", r.resident},
            {"loads", r.loads},
            {"evictions", r.evictions},
            {"upload_bound_bytes", p.residency().uploadBound()},
            {"max_frame_upload_bytes", r.maxFrameUploadBytes},
            {"damaged", r.damaged},
            {"coarse_level", r.coarseLevel},
            {"coarse_bytes", r.coarseBytes}};
}

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
