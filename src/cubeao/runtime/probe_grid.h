// Candidate probes for the run-time projection (DESIGN.md §4 "Projection"): a uniform grid over the
// scene whose every cell lists up to K probes worth trying for surface points inside it. The pass
// then costs K probe evaluations per pixel however many probes the cache holds (the clustered-shading
// idea, in world space: the cell a pixel's surface point falls in is its cluster).
//
// Which K? The ones that shade the cell's surfaces best together. The grid is built from points
// sampled on both sides of every triangle (what a camera could see), and a quality per probe and
// point: 0 when the probe cannot shade the point (depth test, facing), else what the projection
// ranks by (confidence / texel footprint). Per cell, among the `considered` probes nearest its centre,
// K are chosen greedily to maximise the sum over the cell's points of the best three qualities
// (each point's qualities normalised by its best probe's, so every point counts alike): the
// projection blends the best two, weighted against the third, so a point needs all three to be
// shaded as if every probe were tried, and a probe that adds the only view of a column's far side
// beats a ninth view of the floor. Cells without points get the nearest K.
//
// Measured on the Sibenik walk's first 12 frames at 320×180 (24 probes at 256², K = 8): the previous
// rule, "nearest probes that see the cell's centre or a corner", left 1.6 % of pixels uncovered and
// an MAE of 0.0195; this one 0.6 % and 0.0165; trying every probe, 0.4 % and 0.0159.
#pragma once

#include <cstdint>
#include <functional>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

#include "cubeao/core/surface_samples.h"
#include "cubeao/runtime/probe_id.h"
#include "cubeao/runtime/probe_set.h"

namespace cubeao {

struct ProbeGridSettings {
    int candidates = 0;      // K; 0 → 8 (issue 6 default)
    float cellSize = 0.0f;   // world units; 0 → the AO radius chosen by the caller (see resolve)
    int maxCells = 0;        // cap on the cell count (memory); 0 → 1 << 20
    int considered = 0;      // probes nearest a cell's centre that compete for it; 0 → max(8 K, 64)
    int pointsPerCell = 0;   // surface points per cell used for the choice (a fixed subset); 0 → 128
};

// The probe set is live (DESIGN.md §4 "Run time that grows"): probes can be added and removed after
// construction, and only the cells whose competition a probe joins or leaves are chosen again, with
// the same rule, so the table always equals the one a grid built from scratch over the same probes
// (same ids, same order) would hold. The grid keeps no probes of its own: each call that chooses
// reads the ProbeSet it is given (probe_set.h), the one record of ids, positions and liveness. A
// cell's competition is its `considered` nearest live probes; a probe changes it only if it lies
// within the farthest of them (all cells when there are no more live probes than `considered`).
class ProbeGrid {
public:
    // quality(probe, point) ≥ 0: how well `probe` shades `point`; 0 = not at all. Kept and called
    // again when probes are added or removed.
    using QualityFn = std::function<double(std::uint32_t probe, const SurfaceSample& point)>;

    // Over the live probes of `probes`.
    ProbeGrid(const glm::vec3& boundsMin, const glm::vec3& boundsMax, const ProbeSet& probes,
              std::span<const SurfaceSample> points, QualityFn quality, ProbeGridSettings settings);

    // After `probes` added (or removed) probe `id`: the cells whose competition it joins (or leaves),
    // chosen again from `probes`, ascending.
    std::vector<std::size_t> addProbe(const ProbeSet& probes, ProbeId id);
    std::vector<std::size_t> removeProbe(const ProbeSet& probes, ProbeId id);

    // Candidates of the cell containing x (clamped to the grid): up to K probe indices, best first.
    std::span<const std::uint32_t> candidates(const glm::vec3& x) const;
    // The same for cell c (x-fastest index), and the cell's centre.
    std::span<const std::uint32_t> cellCandidates(std::size_t c) const;
    glm::vec3 cellCentre(std::size_t c) const;
    std::size_t cellCount() const { return reach2_.size(); }
    std::size_t cellIndex(const glm::ivec3& c) const {
        return (std::size_t(c.z) * std::size_t(dims_.y) + std::size_t(c.y)) * std::size_t(dims_.x) + std::size_t(c.x);
    }

    // GPU layout: cells in x-fastest order, K entries each, unused entries = kernel::kNoProbe
    // (shaders/common/runtime_layout.h).
    const std::vector<std::uint32_t>& table() const { return table_; }
    glm::ivec3 dims() const { return dims_; }
    glm::vec3 origin() const { return origin_; }
    float cellSize() const { return cell_; }
    int k() const { return k_; }

private:
    std::size_t cellOf(const glm::vec3& x) const;
    void choose(const ProbeSet& probes, std::size_t cell);  // the cell's K from its `considered` nearest live probes
    // Cells whose competition includes a probe at `position`, chosen again.
    std::vector<std::size_t> rechooseAround(const ProbeSet& probes, const glm::vec3& position);

    glm::vec3 origin_{0.0f};
    glm::ivec3 dims_{1};
    float cell_ = 1.0f;
    int k_ = 8;
    std::size_t considered_ = 0;  // competitors per cell (the setting; fewer while fewer probes live)
    std::vector<std::uint32_t> table_;
    QualityFn quality_;
    std::vector<std::vector<SurfaceSample>> cellPoints_;  // each cell's points, at most pointsPerCell
    std::vector<float> reach2_;  // per cell: squared distance of its farthest competitor (inf: all compete)
    // Scratch of choose().
    std::vector<std::uint32_t> order_;
    std::vector<float> distance2_;
    std::vector<double> quality2_;
};

}  // namespace cubeao
