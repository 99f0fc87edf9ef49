// Free space and probe candidates (DESIGN.md §4 "Placement", issue 31): the scene's bounding box cut
// into cubic voxels. A voxel is *clear* when its centre keeps `clearance` from every triangle, and free
// when it is reached from known-free seeds without crossing geometry: the walk's eyes, and the space
// outside the box (a boundary voxel whose segment out of the box meets nothing). Reaching is a flood
// over the six neighbours whose centre-to-centre segment no triangle cuts (an Embree ray), so it does
// not depend on which way faces point: CAD exports and scans flip them, and a model with every face
// reversed has the same free space as the original.
// Clear voxels nobody reaches (a sealed room, the inside of a pillar or a thick wall) are decided by
// sidedness, as a tie-break: DDGI's rule (more than a quarter of the rays from the centre meet the back
// of a face: inside) and CGAL's exact test for closed outward components. The winding those read is
// the one learned from reached space where it can be: a face that reached voxels see from its back is
// reversed, and so is every unseen face of a connected component that is seen mostly from behind.
#pragma once

#include <cstdint>
#include <memory>
#include <span>
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

    // `clearance` 0 → half a voxel. `seeds`: points known to be free (the walk's eyes); each seeds the
    // clear voxel nearest it among those around it that it sees, or none (stats().seedsNotFree).
    FreeSpace(const Scene& scene, const EmbreeScene& embree, float voxel, float clearance,
              std::span<const glm::vec3> seeds = {});
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

    // What a point is, tested in this order (the first that applies): outside the box, too close to
    // geometry, free (its voxel is reached and p sees the voxel's centre), and for the rest the
    // sidedness tie-break: inside a closed solid, inside by the rays, else free.
    enum class Verdict : std::uint8_t { Free, Outside, TooClose, InsideClosed, InsideByRays };
    Verdict classify(const glm::vec3& p) const;
    // The test of the voxels at any point (the grid method's lattice, a probe set's check).
    bool isFree(const glm::vec3& p) const { return classify(p) == Verdict::Free; }
    float distanceToSurface(const glm::vec3& p) const;
    // Share of kInsideRays rays from p that hit the back of a face, with the winding learned from
    // reached space (> 0.25: inside).
    float backFaceShare(const glm::vec3& p) const;
    bool insideClosedSolid(const glm::vec3& p) const;
    // Whether the flood from the seeds reached voxel `voxelIndex`.
    bool reached(std::size_t voxelIndex) const { return reached_[voxelIndex] != 0; }

    struct Stats {
        std::size_t voxels = 0, candidates = 0, tooClose = 0, insideByRays = 0, insideClosed = 0, outside = 0;
        std::size_t closedSolids = 0, closedRooms = 0, openComponents = 0;
        std::size_t reached = 0;         // candidates the flood reached (the rest are free by the tie-break)
        std::size_t seeds = 0, seedsNotFree = 0;  // given seeds that seeded a voxel, and those that did not
        std::size_t outsideSeeds = 0;    // boundary voxels open to the outside of the box
        std::size_t reversedFaces = 0;   // triangles whose winding reached space reads as reversed
        bool roomiestSeed = false;       // no seed and nothing open to the outside: the clear voxel
                                         // farthest from geometry seeded the flood (a sealed model)
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
    std::vector<std::uint8_t> reached_;   // per voxel
    std::vector<std::uint8_t> reversed_;  // per triangle: 1 where the learned winding is the scene's reversed
    Stats stats_;

    // The flood (free_space.cpp): which neighbours' segments are open, the voxels the seeds and the
    // outside start from, the breadth-first spread over open segments, and the sidedness tie-break of
    // the clear voxels left.
    std::vector<std::uint16_t> openSides(const std::vector<std::uint8_t>& clear) const;
    std::vector<std::size_t> seedVoxels(const std::vector<std::uint8_t>& clear, const std::vector<std::uint16_t>& open,
                                        std::span<const glm::vec3> seeds);
    void spread(const std::vector<std::uint16_t>& open, const std::vector<std::size_t>& starts);
    void decideUnreached(const std::vector<std::uint8_t>& clear, std::vector<Verdict>& verdict);
    void learnWinding();
    // Whether a ray along `dir` meets the back of triangle `primitive` (geometric normal `normal`).
    bool backHit(const glm::vec3& dir, const glm::vec3& normal, unsigned primitive) const;
};

}  // namespace cubeao::placement
