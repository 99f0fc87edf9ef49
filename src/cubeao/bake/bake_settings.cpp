#include "cubeao/bake/bake_settings.h"

#include <algorithm>
#include <vector>

#include "common/ao_denoise.h"
#include "cubeao/cache/depth_cube.h"
#include "cubeao/core/error.h"
#include "cubeao/core/sampling.h"

namespace cubeao {

Estimator parseEstimator(const std::string& name) {
    if (name == "hsplit") return Estimator::HorizonSplit;
    if (name == "gtao") return Estimator::Gtao;
    if (name == "traced") return Estimator::Traced;
    if (name == "hybrid") return Estimator::Hybrid;
    throw UsageError("--estimator \"" + name + "\": expected hsplit, gtao, traced or hybrid");
}

const char* estimatorName(Estimator e) {
    switch (e) {
        case Estimator::HorizonSplit: return "hsplit";
        case Estimator::Gtao: return "gtao";
        case Estimator::Traced: return "traced";
        case Estimator::Hybrid: return "hybrid";
    }
    return "?";
}

BakeDevice parseBakeDevice(const std::string& name) {
    if (name == "gpu") return BakeDevice::Gpu;
    if (name == "cpu") return BakeDevice::Cpu;
    throw UsageError("--device \"" + name + "\": expected gpu or cpu");
}

const char* bakeDeviceName(BakeDevice d) { return d == BakeDevice::Gpu ? "gpu" : "cpu"; }

BakeSettings resolveBakeSettings(BakeSettings s, float sceneDefaultRadius) {
    if (s.res == 0) s.res = 512;
    if (s.ao.spp == 0) s.ao.spp = 64;
    if (s.ao.radius == 0.0f) s.ao.radius = sceneDefaultRadius;
    if (s.directions == 0) s.directions = 16;
    if (s.steps == 0) s.steps = 16;
    if (s.hybridThreshold == 0.0f) s.hybridThreshold = 0.95f;
    if (s.depthRes == 0) s.depthRes = depth::depthResFor(s.res);
    if (s.depthFormat == DepthFormat{}) s.depthFormat = depth::kDefaultFormat;
    if (s.denoise == -1)
        s.denoise = tracesRays(s.estimator) ? kernel::kAoDenoiseDefaultRadius : 0;
    if (!s.aoFormat) s.aoFormat = defaultAoFormat(std::uint8_t(s.estimator));
    if (s.levels == 0) s.levels = 1;
    const int mostLevels =
        s.res >= 4 && s.depthRes >= 1 ? int(maxLevels(std::uint32_t(s.res), std::uint32_t(s.depthRes))) : 1;
    if (s.levels == kAllLevels) s.levels = mostLevels;

    std::vector<std::string> problems;
    if (s.res < 4 || s.res > 4096 || s.res % 4 != 0)
        problems.push_back("--res " + std::to_string(s.res) + ": expected a multiple of 4 in 4..4096 (BC5 blocks are 4x4)");
    if (s.depthRes < 1 || s.depthRes > s.res)
        problems.push_back("--depth-res " + std::to_string(s.depthRes) + ": expected 1..res (" + std::to_string(s.res) + ")");
    if (depthBytesPerTexel(s.depthFormat) == 0)
        problems.push_back("depth format " + std::to_string(int(s.depthFormat)) + ": expected r16unorm, r16float or r32float");
    if (s.denoise < 0 || s.denoise > kMaxDenoiseRadius)
        problems.push_back("--denoise " + std::to_string(s.denoise) + ": expected 0.." + std::to_string(kMaxDenoiseRadius));
    else if (s.denoise > 0 && !tracesRays(s.estimator))
        problems.push_back("--denoise " + std::to_string(s.denoise) + ": only traced texels are filtered (estimator " +
                           estimatorName(s.estimator) + "); use 0");
    if (s.ao.spp < 1 || s.ao.spp > 65536) problems.push_back("--spp " + std::to_string(s.ao.spp) + ": expected 1..65536");
    if (!(s.ao.radius > 0.0f)) problems.push_back("--radius must be positive");
    if (s.directions < 2 || s.directions > 64 || s.directions % 2 != 0)
        problems.push_back("directions " + std::to_string(s.directions) + ": expected an even number in 2..64");
    if (s.steps < 1 || s.steps > 64) problems.push_back("steps " + std::to_string(s.steps) + ": expected 1..64");
    if (!(s.hybridThreshold > 0.0f && s.hybridThreshold <= 1.0f))
        problems.push_back("hybrid threshold must lie in (0, 1]");
    if (s.levels < 1 || s.levels > mostLevels)
        problems.push_back("--levels " + std::to_string(s.levels) + ": expected 1.." + std::to_string(mostLevels) +
                           " at res " + std::to_string(s.res) + " and depth-res " + std::to_string(s.depthRes) +
                           " (each level halves both, whole 4x4 blocks, AO faces of at least " +
                           std::to_string(kMinLevelRes) + " texels), or max");
    if (*s.aoFormat == AoFormat::Bc4 && s.estimator != Estimator::Traced)
        problems.push_back(std::string("--ao bc4: AO alone suits traced caches, whose confidence is 1 everywhere; ") +
                           estimatorName(s.estimator) + " estimates a confidence the projection ranks by: use bc5");
    if (!problems.empty()) {
        std::string message = "bad bake settings:";
        for (const auto& p : problems) message += "\n  " + p;
        throw UsageError(message);
    }
    return s;
}

// The cache numbers estimators as Estimator does (defaultAoFormat and the BC4 check read 2 as traced).
static_assert(int(Estimator::HorizonSplit) == 0 && int(Estimator::Gtao) == 1 && int(Estimator::Traced) == 2 &&
              int(Estimator::Hybrid) == 3);

CacheParams cacheParamsFor(const BakeSettings& s, std::uint64_t sceneHash) {
    const bool horizon = s.estimator != Estimator::Traced, rays = tracesRays(s.estimator);
    CacheParams p;
    p.sceneHash = sceneHash;
    p.res = std::uint32_t(s.res);
    p.depthRes = std::uint32_t(s.depthRes);
    p.depthFormat = s.depthFormat;
    p.estimator = std::uint8_t(s.estimator);
    p.falloff = std::uint8_t(s.ao.falloff);
    p.denoise = std::uint8_t(s.denoise);
    p.spp = rays ? std::uint32_t(s.ao.spp) : 0;
    p.radius = s.ao.radius;
    p.seed = s.ao.seed;
    p.directions = horizon ? std::uint32_t(s.directions) : 0;
    p.steps = horizon ? std::uint32_t(s.steps) : 0;
    p.hybridThreshold = s.estimator == Estimator::Hybrid ? s.hybridThreshold : 0.0f;
    p.aoFormat = s.aoFormat.value_or(defaultAoFormat(p.estimator));
    p.levels = std::uint8_t(std::max(s.levels, 1));
    return p;
}

CacheParams cacheParamsFor(const BakeSettings& s, const Scene& scene) {
    CacheParams p = cacheParamsFor(s, scene.hash);
    p.origin = glm::vec3(scene.origin);  // exact: chooseOrigin rounds it to a float
    return p;
}

std::uint32_t texelKey(int face, int i, int j, int res, std::uint32_t probeIndex, std::uint32_t seed) {
    return kernel::cubeTexelKey({i, j, face}, res, probeIndex ^ seed);
}

}  // namespace cubeao
