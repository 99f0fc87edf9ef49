// Made-up probe payloads for timing the run time without a bake: `cubeao bench render --synthetic`
// and the GPU benchmark `cubeao-gpubench` (tools/cubeao-gpubench), which must run on a machine with
// neither Embree nor a scene's worth of baking time. The payloads make the projection do all its work,
// as a bake's would: every distance texel lies beyond `maxDistance`·60000/65535 (so with maxDistance
// past the scene's diagonal every candidate passes the depth test wherever its surface faces it, and
// the best-two blend always runs), AO blocks with random endpoints and codes (varied texels),
// confidence 1 in every texel, as a traced bake writes it (the caches say "traced").
// The AO values mean nothing: these caches are for timings, never for quality figures.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

#include "cubeao/cache/cache_file.h"

namespace cubeao {

// `count` distinct payloads for caches with `params` (r16unorm distances only: Error otherwise; the AO
// in params.aoFormat),
// deterministic for a seed. A cache of thousands of probes shares them round-robin, so writing a
// 10,000-probe cache at 256² (4.4 GB) holds a few probes in memory, not all.
std::vector<ProbeRecord> syntheticPayloads(const CacheParams& params, float maxDistance, std::size_t count,
                                           std::uint32_t seed = 2);

// Probe k of `positions` with payload k mod payloads.size() and index k, as views for writeCache
// (into `payloads`: valid while it lives).
std::vector<ProbeView> syntheticProbeViews(std::span<const glm::vec3> positions,
                                           std::span<const ProbeRecord> payloads);

}  // namespace cubeao
