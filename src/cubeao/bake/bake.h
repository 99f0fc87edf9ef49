// Baking one probe: its cube G-buffer and AO (plus confidence) for every texel (DESIGN.md §4 "Bake").
// Two paths compute the same quantities: the GPU path (gpu_bake.h: rasterised G-buffer, compute
// shaders) and the CPU path here (Embree primary rays and AO rays, all cores), which is the test twin
// and what a CPU-only cluster node runs.
#pragma once

#include <cstdint>
#include <vector>

#include "cubeao/bake/bake_settings.h"
#include "cubeao/bake/cube_gbuffer.h"
#include "cubeao/reference/embree_scene.h"

namespace cubeao {

struct BakeTimings {
    double gbufferMs = 0.0, aoMs = 0.0, readbackMs = 0.0;
};

struct BakedProbe {
    CubeGBuffer gbuffer;            // distances and normals (the surface points the AO belongs to)
    std::vector<float> ao;          // per texel, cube::texelIndex order; empty texels: 1
    std::vector<float> confidence;  // horizon estimators' confidence; 1 for `traced` and empty texels
                                    // (hybrid keeps the hsplit confidence of the texels it traced)
    std::uint64_t tracedTexels = 0; // texels whose AO came from rays (all of them for traced)
    std::uint64_t rays = 0;         // AO rays cast
    std::uint64_t fetches = 0;      // G-buffer lookups by the horizon march
    BakeTimings timings;
};

// G-buffer by Embree primary rays through every texel centre: nearest hit, unit geometric normal
// turned to face the probe, distance along the centre ray; no hit: (0, 0, 0, 0).
CubeGBuffer renderGBufferCpu(const EmbreeScene& scene, const glm::vec3& probe, int res);

// The whole probe on the CPU with settings.estimator (settings resolved: resolveBakeSettings).
BakedProbe bakeProbeCpu(const EmbreeScene& scene, const glm::vec3& probe, std::uint32_t probeIndex,
                        const BakeSettings& settings);

// AO of every texel of `g` by rays from its surface point: ambientOcclusion() with the texel's
// texelKey. `only`, when not empty, selects texels (nonzero = trace); others keep `ao`'s value.
// Returns the rays cast.
std::uint64_t traceTexelsCpu(const EmbreeScene& scene, const CubeGBuffer& g, std::uint32_t probeIndex,
                             const BakeSettings& settings, std::vector<float>& ao,
                             const std::vector<std::uint8_t>& only = {});

// Embree twin at the baked texel points: mean |ao − reference| over the non-empty texels, with the
// reference computed by ambientOcclusion() with settings.ao and each texel's key, so with the bake's
// own settings it traces the same rays as `traced`. Pass more spp for a quality figure instead; then
// `noise` (the reference's mean standard error) says how much of the MAE is the reference's own.
struct VerifyResult {
    double mae = 0.0;
    double noise = 0.0;
    std::uint64_t texels = 0;
};
VerifyResult verifyProbe(const EmbreeScene& scene, const BakedProbe& probe, std::uint32_t probeIndex,
                         const BakeSettings& settings);

}  // namespace cubeao
