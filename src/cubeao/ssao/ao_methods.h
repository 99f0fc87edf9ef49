// The AO methods a frame can run, as passes from the camera G-buffer to raw AO (runtime/ao_pass.h):
// the probe projection with GTAO under the pixels no probe covers, or a screen-space baseline. What
// `cubeao render`, `bench render`, cubeao-gpubench and cubeao-view build their FramePipeline with, so
// each tool's "probes" is the same pass with the same fallback.
#pragma once

#include <cstdint>
#include <memory>
#include <span>

#include <glm/vec3.hpp>

#include "cubeao/cache/cache_file.h"
#include "cubeao/runtime/ao_pass.h"
#include "cubeao/runtime/probe_projection.h"
#include "cubeao/ssao/ssao_settings.h"

namespace cubeao {

// With a cache: the probe projection over the mesh (its residency per `probes`), its uncovered pixels
// filled by GTAO with `ssao`'s settings unless `fallback` is off. Without: the baseline `ssao` names
// (resolved settings). The cache must outlive the pass (probes stream from it). Needs a current GL
// 4.5 context.
std::unique_ptr<AoPass> makeAoPass(const SsaoSettings& ssao, const CacheReader* cache,
                                   std::span<const glm::vec3> positions, std::span<const std::uint32_t> indices,
                                   const ProbeProjectionSettings& probes = {}, bool fallback = true);

// A probe projection with no probes yet, for probes baked with `params` and added while it runs (live
// placement), GTAO with `ssao`'s settings under every pixel no probe covers.
std::unique_ptr<ProbeProjectionPass> makeEmptyProbePass(const CacheParams& params, const SsaoSettings& ssao,
                                                        std::span<const glm::vec3> positions,
                                                        std::span<const std::uint32_t> indices,
                                                        const ProbeProjectionSettings& probes = {});

}  // namespace cubeao
