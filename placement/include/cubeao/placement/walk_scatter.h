// Probe positions scattered around a walk, as the benchmarks place them (`bench render`: Embree's free
// distance as the reach; cubeao-gpubench: a fixed spread). Header-only and free of the placement
// library's dependencies, so cubeao-gpubench, which travels to GPU machines without Embree or CGAL,
// includes it without linking placement.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <random>
#include <vector>

#include <glm/common.hpp>
#include <glm/vec3.hpp>

#include "cubeao/core/camera.h"

namespace cubeao {

// `count` points: a uniform point of the eye polyline, a uniform direction, a uniform distance up to
// reach(eye, direction). Deterministic (fixed seed). The path needs at least one frame.
template <class Reach>
std::vector<glm::vec3> scatterAroundWalk(const CameraPath& path, std::size_t count, Reach reach) {
    std::mt19937 rng(1);
    const auto uniform = [&] { return float(rng() >> 8) * (1.0f / 16777216.0f); };
    std::vector<glm::vec3> out;
    while (out.size() < count) {
        const float u = uniform() * float(path.frames.size() - 1);
        const std::size_t i = std::size_t(u), j = std::min(i + 1, path.frames.size() - 1);
        const glm::vec3 eye = glm::mix(path.frames[i].eye, path.frames[j].eye, u - float(i));
        const float z = 1.0f - 2.0f * uniform(), phi = 6.2831853f * uniform(), r = std::sqrt(std::max(0.0f, 1.0f - z * z));
        const glm::vec3 dir(r * std::cos(phi), z, r * std::sin(phi));
        const float far = reach(eye, dir);
        out.push_back(eye + dir * (uniform() * far));
    }
    return out;
}

}  // namespace cubeao
