// Candidate probes for the run-time projection (DESIGN.md §4 "Projection"): a uniform grid over the
// scene whose every cell lists up to K probes worth trying for surface points inside it. The pass
// then costs K probe evaluations per pixel however many probes the cache holds (the clustered-shading
// idea, in world space: the cell a pixel's surface point falls in is its cluster).
//
// A probe is worth trying for a cell when it can see the cell: the probe's distance cube reaches at
// least as far as the cell centre in its direction (or a corner, for cells that straddle a wall).
// Among those the nearest K win (quality falls with distance squared); when fewer than K see the
// cell, the nearest others fill up the list, so that a point the grid misjudges still gets tried.
#pragma once

#include <cstdint>
#include <functional>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

namespace cubeao {

struct ProbeGridSettings {
    int candidates = 0;    // K; 0 → 8 (issue 6 default)
    float cellSize = 0.0f;  // world units; 0 → the AO radius chosen by the caller (see resolve)
    int maxCells = 0;       // cap on the cell count (memory); 0 → 1 << 20
};

class ProbeGrid {
public:
    // `sees(probe, point)`: whether probe `probe` sees world point `point` (its depth test).
    using SeesFn = std::function<bool(std::uint32_t probe, const glm::vec3& point)>;

    ProbeGrid(const glm::vec3& boundsMin, const glm::vec3& boundsMax, std::span<const glm::vec3> probes,
              const SeesFn& sees, ProbeGridSettings settings);

    // Candidates of the cell containing x (clamped to the grid): up to K probe indices, best first.
    std::span<const std::uint32_t> candidates(const glm::vec3& x) const;

    // GPU layout: cells in x-fastest order, K entries each, unused entries = 0xffffffff.
    const std::vector<std::uint32_t>& table() const { return table_; }
    glm::ivec3 dims() const { return dims_; }
    glm::vec3 origin() const { return origin_; }
    float cellSize() const { return cell_; }
    int k() const { return k_; }

private:
    std::size_t cellOf(const glm::vec3& x) const;

    glm::vec3 origin_{0.0f};
    glm::ivec3 dims_{1};
    float cell_ = 1.0f;
    int k_ = 8;
    std::vector<std::uint32_t> table_;
};

}  // namespace cubeao
