// Bake settings for tests: one helper instead of a private copy in each test_*.cpp. Every number a
// test bakes with is written at its call site; nothing differs from file to file.
#pragma once

#include <span>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "cubeao/bake/bake.h"
#include "cubeao/bake/bake_cache.h"
#include "cubeao/bake/bake_driver.h"
#include "cubeao/bake/bake_settings.h"
#include "cubeao/scene/scene.h"

namespace cubeao::test {

// Resolved settings for a test bake: estimator, face resolution `res`, AO radius (also the scene
// default that resolveBakeSettings falls back to), `spp` rays per traced texel (stored but unused by
// hsplit and gtao), and the horizon march's `directions` and `steps`, where 0 is the library default
// (bake_settings.h: 16 each), as in BakeSettings itself. `device` keeps its default: only `cubeao
// bake` reads it, to pick a baker; a test calls bakeProbeCpu or GpuBaker itself.
inline BakeSettings bakeSettings(Estimator estimator, int res, float radius, int spp, int directions = 0, int steps = 0) {
    BakeSettings s;
    s.res = res;
    s.estimator = estimator;
    s.ao.radius = radius;
    s.ao.spp = spp;
    s.directions = directions;
    s.steps = steps;
    return resolveBakeSettings(s, radius);
}

// Bakes `probes` (probe i gets index i) on the CPU into the cache `path`, as `cubeao bake` does.
inline void bakeCache(const Scene& scene, std::span<const glm::vec3> probes, const BakeSettings& s,
                      const std::string& path) {
    BakeCacheWriter cache(path, cacheParamsFor(s, scene.hash), probes);
    BakeSettings cpu = s;
    cpu.device = BakeDevice::Cpu;
    ProbeBaker baker(scene, cpu);
    BakeJob job;
    job.probes = probes;
    job.progressLabel.clear();
    bakeProbes(baker, job, cache);
    cache.finish();
}

}  // namespace cubeao::test
