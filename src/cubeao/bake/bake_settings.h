// What a probe bake computes and how (DESIGN.md §4 "Bake"): a plain aggregate where zero means
// "default" (STYLE.md, sokol), resolved once by resolveBakeSettings so every stage sees final values.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "cubeao/cache/cache_file.h"
#include "cubeao/reference/ao_reference.h"
#include "cubeao/scene/scene.h"

namespace cubeao {

enum class Estimator {
    HorizonSplit,  // "hsplit": W = 1/N_d Σ sin²(h_i) from the probe's own depth (Oswald ch. 4)
    Gtao,          // "gtao": cosine-weighted GTAO slice integral (Jimenez et al. 2016, paper 002)
    Traced,        // "traced": rays from the texel's surface point through the whole scene
    Hybrid,        // "hybrid": hsplit where its confidence ≥ hybridThreshold, traced elsewhere
};
Estimator parseEstimator(const std::string& name);  // UsageError naming the choices otherwise
const char* estimatorName(Estimator e);

enum class BakeDevice { Gpu, Cpu };
BakeDevice parseBakeDevice(const std::string& name);
const char* bakeDeviceName(BakeDevice d);

// Whether the estimator traces rays (traced: every texel; hybrid: its low-confidence ones): what spp
// and the AO filter (`--denoise`) apply to.
inline bool tracesRays(Estimator e) { return e == Estimator::Traced || e == Estimator::Hybrid; }

// The widest `--denoise` window: 17 × 17 texels (what a cache header can name: kMaxCacheDenoise).
constexpr int kMaxDenoiseRadius = int(kMaxCacheDenoise);

struct BakeSettings {
    int res = 0;                      // face resolution, texels per side; 0 → 512 (thesis: 256² too coarse);
                                      // a multiple of 4 (BC5 blocks)
    Estimator estimator = Estimator::Traced;
    AoSettings ao;                    // radius (0 → scene default), spp for traced texels (0 → 64), falloff, seed
    int directions = 0;               // horizon directions N_d; 0 → 16 (thesis ~15); even (gtao pairs them)
    int steps = 0;                    // march steps N_s per direction; 0 → 16
    float hybridThreshold = 0.0f;     // confidence below which hybrid traces; 0 → 0.95
    BakeDevice device = BakeDevice::Gpu;
    int depthRes = 0;                 // distance cube texels per side, 1..res; 0 → res/4 (depth_cube.h)
    DepthFormat depthFormat{};        // 0 → r16unorm (depth_cube.h: the measured choice)
    int denoise = -1;                 // edge-aware filter of traced AO, texels a side (common/ao_denoise.h);
                                      // -1 → kAoDenoiseDefaultRadius (1) for traced and hybrid, 0 = off
    std::optional<AoFormat> aoFormat; // the cache's AO blocks; none → defaultAoFormat: BC4 for traced (its
                                      // confidence is 1 everywhere), BC5 (AO + confidence) for the others
    int levels = 0;                   // levels of detail per probe (format 5, probe_levels.h); 0 → 1 (the
                                      // run time reads level 0 alone so far), kAllLevels → maxLevels(res, depthRes)
};
constexpr int kAllLevels = -1;  // `--levels max`

// Fills the zero fields with defaults (radius from `sceneDefaultRadius`) and checks ranges, listing
// every problem in one UsageError.
BakeSettings resolveBakeSettings(BakeSettings s, float sceneDefaultRadius);

// The cache header's bake parameters for resolved settings `s` and the scene's hash. Fields the
// estimator does not use are 0 (spp for hsplit and gtao; directions, steps for traced; the hybrid
// threshold except for hybrid), so a cache is not refused for a setting that made no difference.
CacheParams cacheParamsFor(const BakeSettings& s, std::uint64_t sceneHash);
// The same with the scene's hash and origin (Scene::origin, which the header carries from format 2 on).
CacheParams cacheParamsFor(const BakeSettings& s, const Scene& scene);

// Key of the per-texel rotation of sample sets: the same rays on every device (the shared kernel
// cubeTexelKey, shaders/common/sampling.h, with probeKey = probeIndex ^ seed).
std::uint32_t texelKey(int face, int i, int j, int res, std::uint32_t probeIndex, std::uint32_t seed);

}  // namespace cubeao
