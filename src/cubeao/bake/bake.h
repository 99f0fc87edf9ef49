// Baking one probe: its cube G-buffer and AO (plus confidence) for every texel (DESIGN.md §4 "Bake").
// Two paths compute the same quantities: the GPU path (gpu_bake.h: rasterised G-buffer, compute
// shaders) and the CPU path here (Embree primary rays and AO rays, all cores), which is the test twin
// and what a CPU-only cluster node runs.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <span>
#include <utility>
#include <vector>

#include "cubeao/bake/bake_settings.h"
#include "cubeao/bake/cube_gbuffer.h"
#include "cubeao/reference/embree_scene.h"

namespace cubeao {

struct BakeTimings {
    double gbufferMs = 0.0, aoMs = 0.0;
    double encodeMs = 0.0;    // BC5 of (AO, confidence) and the distance cube: what the cache stores
    double errorMs = 0.0;     // measuring what BC5 cost the AO (EncodedProbe::aoSquaredError)
    double readbackMs = 0.0;  // GPU → CPU copies
};

// A probe as the cache stores it (cache_file.h ProbeRecord, less position and index), plus what the
// compression cost.
struct EncodedProbe {
    std::vector<std::uint8_t> aoConfidence;  // BC5 cube (cache/bc4.h layout)
    std::vector<std::uint8_t> depth;         // distance cube at settings.depthRes (cache/depth_cube.h)
    float maxDistance = 0.0f;                // its r16unorm scale
    double aoSquaredError = 0.0;             // Σ (decoded BC5 AO − AO)² over the surface texels
    std::uint64_t surfaceTexels = 0;         // texels that show a surface (G-buffer distance > 0)
};

// The one conversion from what a baker made to what the cache stores (and tools read back): the
// encoded sections are moved, so `e` is left empty.
inline ProbeRecord probeRecord(std::uint32_t index, const glm::vec3& position, EncodedProbe&& e) {
    return {index, position, e.maxDistance, std::move(e.aoConfidence), std::move(e.depth)};
}

// PSNR in dB (peak 1) of an AO error: 10·log10(texels / squaredError), capped at 100 dB for an exact
// encoding (and 100 for no texels) so JSON never needs infinity.
inline double aoPsnr(double squaredError, std::uint64_t texels) {
    if (texels == 0) return 100.0;
    return std::min(100.0, 10.0 * std::log10(double(texels) / std::max(squaredError, 1e-300)));
}

struct BakedProbe {
    // Uncompressed results: always on the CPU path; on the GPU path only with BakeReadback::All
    // (gpu_bake.h), otherwise empty (gbuffer.res 0): a production bake keeps them on the GPU.
    CubeGBuffer gbuffer;            // distances and normals (the surface points the AO belongs to)
    std::vector<float> ao;          // per texel, cube::texelIndex order; empty texels: 1
    std::vector<float> confidence;  // horizon estimators' confidence; 1 for `traced` and empty texels
                                    // (hybrid keeps the hsplit confidence of the texels it traced)
    EncodedProbe encoded;           // always
    std::uint64_t tracedTexels = 0; // texels whose AO came from rays (all of them for traced)
    std::uint64_t rays = 0;         // AO rays cast
    std::uint64_t fetches = 0;      // G-buffer lookups by the horizon march
    BakeTimings timings;
};

// G-buffer by Embree primary rays through every texel centre: nearest hit, unit geometric normal
// turned to face the probe, distance along the centre ray; no hit: (0, 0, 0, 0).
CubeGBuffer renderGBufferCpu(const EmbreeScene& scene, const glm::vec3& probe, int res);

// The whole probe on the CPU with settings.estimator (settings resolved: resolveBakeSettings),
// encoded as by encodeProbeCpu.
BakedProbe bakeProbeCpu(const EmbreeScene& scene, const glm::vec3& probe, std::uint32_t probeIndex,
                        const BakeSettings& settings);

// What the cache stores of a probe, on the CPU: bc::encodeBc5Cube of (ao, confidence), the distance
// cube of g at settings.depthRes / depthFormat (depth::downsample with depth::kFilter, encode), and
// the AO error of the BC5 blocks over g's surface texels. The GPU bake produces the same BC5 bytes
// and distance texels within one r16unorm code (tests/bake/test_bake_cache.cpp).
EncodedProbe encodeProbeCpu(const CubeGBuffer& g, const std::vector<float>& ao, const std::vector<float>& confidence,
                            const BakeSettings& settings);

// The coarser levels of detail (settings.levels > 1; cache/probe_levels.h) appended to e's sections,
// from the full-resolution (AO, confidence) and g's distances, and e's level-0 distance cube. Both
// bakers call it, so their levels agree as their level 0 does.
void appendLevels(EncodedProbe& e, std::span<const glm::vec2> aoConfidence, const CubeGBuffer& g,
                  const BakeSettings& settings);

// AO of every texel of `g` by rays from its surface point: ambientOcclusion() with the texel's
// texelKey. `only`, when not empty, selects texels (nonzero = trace); others keep `ao`'s value.
// Returns the rays cast.
std::uint64_t traceTexelsCpu(const EmbreeScene& scene, const CubeGBuffer& g, std::uint32_t probeIndex,
                             const BakeSettings& settings, std::vector<float>& ao,
                             const std::vector<std::uint8_t>& only = {});

// The edge-aware filter of traced AO (shaders/common/ao_denoise.h, window radius `radius` texels, AO
// radius `aoRadius`) over every surface texel of `g`, or over the texels `only` selects (nonzero) when
// it is not empty; nothing for radius 0. Each filtered texel reads the AO as it was before the pass.
void denoiseAoCpu(const CubeGBuffer& g, int radius, float aoRadius, std::vector<float>& ao,
                  const std::vector<std::uint8_t>& only = {});

// Mean |ao − reference| over the baked probe's non-empty texels, the reference computed by Embree
// (ambientOcclusion() with `reference`'s AO settings and each texel's texelKey) at each texel's
// surface point. Two uses (DESIGN.md §5 `bake --verify`):
// - the bake's error: `reference` = verifyReferenceSettings(bake settings), an independent estimate
//   (another seed, 4× the rays, no filter), so the MAE measures the bake on every path, `traced` and
//   its filter included; `noise` (the reference's mean standard error) says how much of the MAE is the
//   reference's own;
// - the twin check (`twin_mae`): `reference` = the bake's own settings, so for `traced` it traces the
//   same rays as the bake, filters them as the bake did (settings.denoise), and any difference is a
//   GPU/Embree disagreement (grazing-ray flips only).
struct VerifyResult {
    double mae = 0.0;
    double noise = 0.0;
    std::uint64_t texels = 0;
};
// What `bake --verify` compares against: the bake's AO settings (radius, falloff) with the seed
// changed by kVerifySeedSalt (independent samples for every texel of every probe: the GPU key is
// probeIndex ^ seed, and the salt is far above any probe count) and `spp` rays per texel, or
// kVerifyRayFactor × the bake's when `spp` is 0. 4× the rays halve the reference's share of the noise.
constexpr std::uint32_t kVerifySeedSalt = 0x9E3779B9u;
constexpr int kVerifyRayFactor = 4;
BakeSettings verifyReferenceSettings(const BakeSettings& bake, int spp = 0);
VerifyResult verifyProbe(const EmbreeScene& scene, const BakedProbe& probe, std::uint32_t probeIndex,
                         const BakeSettings& settings);

}  // namespace cubeao
