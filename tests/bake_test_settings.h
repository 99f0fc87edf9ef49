// Bake settings for tests: one helper instead of a private copy in each test_*.cpp. Every number a
// test bakes with is written at its call site; nothing differs from file to file.
#pragma once

#include "cubeao/bake/bake_settings.h"

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

}  // namespace cubeao::test
