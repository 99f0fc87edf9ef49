// Free space and probe candidates (DESIGN.md §4 "Placement"): the scene's bounding box cut into
// cubic voxels; a voxel is a candidate when its centre keeps `clearance` from every triangle and is
// not inside a solid. Meshes from CAD and surveys are rarely closed, so "inside" is decided as DDGI
// does: more than a quarter of the rays from the centre hit the back of a face. Where a part of the
// mesh is a closed solid (a box, a pillar), CGAL's exact inside test decides as well.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include <glm/vec3.hpp>

#include "cubeao/scene/scene.h"

namespace cubeao {
class EmbreeScene;
}

namespace cubeao::placement {

class SolidGeometry;

struct VoxelGrid {
    glm::vec3 origin{0.0f};  // corner of voxel (0, 0, 0)
    float voxel = 1.0f;      // edge length
    glm::ivec3 dims{0};

    // `voxel` 0 → edge chosen so the box holds about `targetVoxels` voxels.
    static VoxelGrid around(const Bounds& bounds, float voxel, std::size_t targetVoxels = 150000);
    std::size_t size() const { return std::size_t(dims.x) * std::size_t(dims.y) * std::size_t(dims.z); }
    std::size_t index(const glm::ivec3& c) const {
        return (std::size_t(c.z) * std::size_t(dims.y) + std::size_t(c.y)) * std::size_t(dims.x) + std::size_t(c.x);
    }
    glm::ivec3 cell(std::size_t index) const;
    glm::vec3 center(const glm::ivec3& c) const { return origin + (glm::vec3(c) + 0.5f) * voxel; }
    glm::vec3 center(std::size_t index) const { return center(cell(index)); }
    bool contains(const glm::ivec3& c) const;
};

class FreeSpace {
public:
    static constexpr int kInsideRays = 32;  // rays per point for the back-face rule

    // `clearance` 0 → half a voxel.
    FreeSpace(const Scene& scene, const EmbreeScene& embree, float voxel, float clearance);
    ~FreeSpace();
    FreeSpace(const FreeSpace&) = delete;
    FreeSpace& operator=(const FreeSpace&) = delete;

    const VoxelGrid& grid() const { return grid_; }
    float clearance() const { return clearance_; }
    // Candidate voxels: the grid index of each, ascending, and the candidate number of a grid index
    // (−1 when the voxel is not free).
    const std::vector<std::uint32_t>& candidates() const { return candidates_; }
    std::int32_t candidateOf(std::size_t voxelIndex) const { return candidateOf_[voxelIndex]; }
    glm::vec3 candidatePosition(std::size_t candidate) const { return grid_.center(candidates_[candidate]); }

    // What a point is, tested in this order (the first that applies).
    enum class Verdict : std::uint8_t { Free, Outside, TooClose, InsideClosed, InsideByRays };
    Verdict classify(const glm::vec3& p) const;
    // The test of the voxels at any point (the grid method's lattice): inside the box, clear of
    // geometry by `clearance`, not inside a solid.
    bool isFree(const glm::vec3& p) const { return classify(p) == Verdict::Free; }
    float distanceToSurface(const glm::vec3& p) const;
    // Share of kInsideRays rays from p that hit the back of a face (> 0.25: inside).
    float backFaceShare(const glm::vec3& p) const;
    bool insideClosedSolid(const glm::vec3& p) const;

    struct Stats {
        std::size_t voxels = 0, candidates = 0, tooClose = 0, insideByRays = 0, insideClosed = 0, outside = 0;
        std::size_t closedSolids = 0, closedRooms = 0, openComponents = 0;
    };
    const Stats& stats() const { return stats_; }

private:
    const Scene& scene_;
    const EmbreeScene& embree_;
    std::unique_ptr<SolidGeometry> solid_;
    VoxelGrid grid_;
    float clearance_ = 0.0f;
    std::vector<std::uint32_t> candidates_;
    std::vector<std::int32_t> candidateOf_;
    Stats stats_;
};

}  // namespace cubeao::placement
