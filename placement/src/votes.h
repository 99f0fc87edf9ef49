// Normal voting's rays (placement.h): shared by the relevance of samples without a camera path (a
// sample is relevant when one of its rays reaches a free voxel) and by the votes themselves.
#pragma once

#include <cmath>
#include <cstdint>
#include <limits>
#include <span>
#include <vector>

#include <glm/common.hpp>

#include "cubeao/placement/placement.h"

namespace cubeao::placement {

// Walks the voxels the ray origin + t·dir crosses for t in [0, tEnd) (Amanatides & Woo), calling
// visit(cell, tEntry) until it returns false.
template <class Visit>
void walkVoxels(const VoxelGrid& grid, const glm::vec3& origin, const glm::vec3& dir, float tEnd, Visit&& visit) {
    const glm::vec3 o = (origin - grid.origin) / grid.voxel;
    glm::ivec3 c = glm::clamp(glm::ivec3(glm::floor(o)), glm::ivec3(0), grid.dims - 1);
    glm::ivec3 step;
    glm::vec3 tMax, tDelta;
    for (int a = 0; a < 3; ++a) {
        step[a] = dir[a] > 0.0f ? 1 : -1;
        if (dir[a] == 0.0f) {
            tMax[a] = tDelta[a] = std::numeric_limits<float>::infinity();
            continue;
        }
        const float boundary = float(c[a] + (step[a] > 0 ? 1 : 0));
        tMax[a] = (boundary - o[a]) / dir[a] * grid.voxel;
        tDelta[a] = grid.voxel / std::abs(dir[a]);
    }
    float t = 0.0f;
    while (grid.contains(c) && t < tEnd) {
        if (!visit(c, t)) return;
        const int a = tMax.x < tMax.y ? (tMax.x < tMax.z ? 0 : 2) : (tMax.y < tMax.z ? 1 : 2);
        t = tMax[a];
        tMax[a] += tDelta[a];
        c[a] += step[a];
    }
}

// Casts `rays` cosine-distributed rays around the normal of every sample with cast[i] != 0 and walks
// the voxels each crosses before it hits geometry. A candidate within the criterion's distance whose
// centre would give a small enough texel and whose centre the sample sees (one more ray) gets the
// sample's vote: a vote means "this candidate covers me". reached[i] is set when some candidate the
// rays led to, at any distance, sees sample i: sample i is visible from free space.
PlacementScene::Votes castVotes(const EmbreeScene& embree, const FreeSpace& space,
                                std::span<const SurfaceSample> samples, std::span<const std::uint8_t> cast,
                                const CoverageCriterion& criterion, int rays, std::uint32_t seed,
                                std::vector<std::uint8_t>* reached);

}  // namespace cubeao::placement
