// A cache's probe decoded for the CPU twin of the projection (src/cubeao/runtime/projection.h
// DecodedProbe), at one level of detail: the texels, and `view` pointing into them, so a DecodedLevel
// is neither copied nor moved (keep several in a std::deque). One decoder for the run-time tests that
// compare the pass or the depth test with the twin (test_projection_gl.cpp, test_thin_wall.cpp).
#pragma once

#include <cstdint>
#include <deque>
#include <vector>

#include <glm/vec2.hpp>
#include <gtest/gtest.h>

#include "cubeao/cache/bc4.h"
#include "cubeao/cache/cache_file.h"
#include "cubeao/cache/depth_cube.h"
#include "cubeao/runtime/projection.h"

namespace cubeao::test {

struct DecodedLevel {
    std::vector<float> ao, confidence, distance;
    DecodedProbe view;
    bool ok = false;  // both decoders succeeded (each failure is also reported)

    DecodedLevel(const ProbeView& probe, const CacheParams& params, std::uint32_t level = 0) {
        const CacheParams p = levelParams(params, level);
        const ProbeView v = levelView(probe, params, level);
        std::vector<glm::vec2> rg;
        const bool aoOk = bc::decodeAoCube(v.aoConfidence, int(p.res), v.aoFormat, rg);
        EXPECT_TRUE(aoOk) << "AO of level " << level;
        for (const glm::vec2& t : rg) ao.push_back(t.x), confidence.push_back(t.y);
        const bool depthOk = depth::decode(v.depth, int(p.depthRes), p.depthFormat, v.maxDistance, distance);
        EXPECT_TRUE(depthOk) << "distances of level " << level;
        ok = aoOk && depthOk;
        view = {v.position, int(p.res), ao, confidence, int(p.depthRes), distance};
    }
    DecodedLevel(const DecodedLevel&) = delete;
    DecodedLevel& operator=(const DecodedLevel&) = delete;
};

// Every probe of `cache` at its finest level, and their views in probe order.
struct DecodedCache {
    std::deque<DecodedLevel> probes;
    std::vector<DecodedProbe> views;
    bool ok = true;

    explicit DecodedCache(const CacheReader& cache) {
        for (std::size_t i = 0; i < cache.probeCount(); ++i) {
            const DecodedLevel& d = probes.emplace_back(cache.probe(i), cache.params());
            views.push_back(d.view);
            ok = ok && d.ok;
        }
    }
};

}  // namespace cubeao::test
