#include "cubeao/runtime/probe_grid.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numeric>
#include <random>

#include <glm/geometric.hpp>

#include "common/projection.h"
#include "common/runtime_layout.h"

namespace cubeao {
namespace {

constexpr std::uint32_t kNone = kernel::kNoProbe;

// The K of one cell, chosen greedily for the sum over its points of the best three normalised
// qualities (the blend uses the best two, weighted against the third). `nearest` are the competing
// probes, nearest first (which also breaks ties); quality[p * points + s] the quality of nearest[p]
// at point s.
void chooseCandidates(std::span<const std::uint32_t> nearest, std::vector<double>& quality, std::size_t points,
                      int k, std::uint32_t* out) {
    const std::size_t m = nearest.size();
    for (std::size_t s = 0; s < points; ++s) {  // normalise: each point's best probe scores 1
        double best = 0.0;
        for (std::size_t p = 0; p < m; ++p) best = std::max(best, quality[p * points + s]);
        if (best > 0.0)
            for (std::size_t p = 0; p < m; ++p) quality[p * points + s] /= best;
    }
    std::vector<std::array<double, 3>> top(points, {0.0, 0.0, 0.0});  // best three chosen so far, descending
    std::vector<bool> taken(m, false);
    int chosen = 0;
    for (; chosen < k; ++chosen) {
        double bestGain = 0.0;
        std::size_t bestProbe = m;
        for (std::size_t p = 0; p < m; ++p) {
            if (taken[p]) continue;
            double gain = 0.0;  // what the top-three sum grows by
            const double* q = quality.data() + p * points;
            for (std::size_t s = 0; s < points; ++s) gain += std::max(0.0, q[s] - top[s][2]);
            if (gain > bestGain) bestGain = gain, bestProbe = p;  // strict: the nearer probe wins ties
        }
        if (bestProbe == m) break;  // nobody adds anything: fill up by distance below
        taken[bestProbe] = true;
        out[chosen] = nearest[bestProbe];
        const double* q = quality.data() + bestProbe * points;
        for (std::size_t s = 0; s < points; ++s) {
            std::array<double, 3>& t = top[s];
            if (q[s] <= t[2]) continue;
            t[2] = q[s];
            if (t[2] > t[1]) std::swap(t[1], t[2]);
            if (t[1] > t[0]) std::swap(t[0], t[1]);
        }
    }
    // The rest by distance: a point the samples missed still gets tried by its nearest probes.
    for (std::size_t p = 0; p < m && chosen < k; ++p)
        if (!taken[p]) out[chosen++] = nearest[p];
}

}  // namespace

ProbeGrid::ProbeGrid(const glm::vec3& boundsMin, const glm::vec3& boundsMax, const ProbeSet& probes,
                     std::span<const SurfaceSample> points, QualityFn quality, ProbeGridSettings s)
    : quality_(std::move(quality)) {
    k_ = s.candidates > 0 ? s.candidates : 8;
    const int maxCells = s.maxCells > 0 ? s.maxCells : 1 << 20;
    considered_ = std::size_t(s.considered > 0 ? s.considered : std::max(8 * k_, 64));
    const std::size_t perCell = std::size_t(s.pointsPerCell > 0 ? s.pointsPerCell : 128);
    const glm::vec3 extent = glm::max(boundsMax - boundsMin, glm::vec3(1e-6f));
    cell_ = s.cellSize > 0.0f ? s.cellSize : std::max({extent.x, extent.y, extent.z}) / 32.0f;
    // Grow the cells until the grid fits the cap.
    for (;;) {
        dims_ = glm::max(glm::ivec3(glm::ceil(extent / cell_)), glm::ivec3(1));
        if (double(dims_.x) * dims_.y * dims_.z <= double(maxCells)) break;
        cell_ *= 1.25f;
    }
    origin_ = boundsMin;
    const std::size_t cells = std::size_t(dims_.x) * std::size_t(dims_.y) * std::size_t(dims_.z);
    table_.assign(cells * std::size_t(k_), kNone);
    reach2_.assign(cells, std::numeric_limits<float>::infinity());

    // Each cell's points, at most perCell of them: a fixed random subset, not the first triangles'.
    std::vector<std::uint32_t> order(points.size());
    std::iota(order.begin(), order.end(), 0u);
    std::shuffle(order.begin(), order.end(), std::mt19937(12345u));
    cellPoints_.resize(cells);
    for (std::uint32_t i : order) {
        std::vector<SurfaceSample>& list = cellPoints_[cellOf(points[i].position)];
        if (list.size() < perCell) list.push_back(points[i]);
    }
    for (std::size_t c = 0; c < cells; ++c) choose(probes, c);
}

glm::vec3 ProbeGrid::cellCentre(std::size_t c) const {
    return kernel::candidateCellCentre(kernel::candidateCellCoordinates(std::uint32_t(c), dims_), origin_, cell_);
}

void ProbeGrid::choose(const ProbeSet& probes, std::size_t cell) {
    std::uint32_t* out = table_.data() + cell * std::size_t(k_);
    std::fill(out, out + k_, kNone);
    const glm::vec3 centre = cellCentre(cell);
    order_.clear();
    distance2_.resize(probes.size());
    for (std::uint32_t p = 0; p < probes.size(); ++p) {
        if (!probes.isLive(ProbeId{p})) continue;
        const glm::vec3 d = probes.position(ProbeId{p}) - centre;
        distance2_[p] = glm::dot(d, d);
        order_.push_back(p);
    }
    const std::size_t considered = std::min(order_.size(), considered_);
    const auto nearer = [&](std::uint32_t a, std::uint32_t b) {
        return distance2_[a] != distance2_[b] ? distance2_[a] < distance2_[b] : a < b;
    };
    std::partial_sort(order_.begin(), order_.begin() + std::ptrdiff_t(considered), order_.end(), nearer);
    // Everyone competes while there are no more live probes than `considered`: any new one joins.
    reach2_[cell] = order_.size() <= considered_ ? std::numeric_limits<float>::infinity()
                                                : distance2_[order_[considered - 1]];
    if (considered == 0) return;
    const std::span<const std::uint32_t> nearest(order_.data(), considered);
    const std::vector<SurfaceSample>& mine = cellPoints_[cell];
    quality2_.assign(considered * mine.size(), 0.0);
    for (std::size_t p = 0; p < considered; ++p)
        for (std::size_t i = 0; i < mine.size(); ++i) quality2_[p * mine.size() + i] = quality_(nearest[p], mine[i]);
    chooseCandidates(nearest, quality2_, mine.size(), k_, out);
}

std::vector<std::size_t> ProbeGrid::rechooseAround(const ProbeSet& probes, const glm::vec3& position) {
    std::vector<std::size_t> changed;
    for (std::size_t c = 0; c < reach2_.size(); ++c) {
        const glm::vec3 d = position - cellCentre(c);
        // ≤, not <: at equal distance the id decides, and re-choosing is always safe.
        if (glm::dot(d, d) <= reach2_[c]) changed.push_back(c);
    }
    for (std::size_t c : changed) choose(probes, c);
    return changed;
}

std::vector<std::size_t> ProbeGrid::addProbe(const ProbeSet& probes, ProbeId id) {
    return rechooseAround(probes, probes.position(id));
}

std::vector<std::size_t> ProbeGrid::removeProbe(const ProbeSet& probes, ProbeId id) {
    return rechooseAround(probes, probes.position(id));
}

std::size_t ProbeGrid::cellOf(const glm::vec3& x) const {
    return cellIndex(kernel::candidateCellOf(x, origin_, cell_, dims_));  // the cell project.comp reads
}

std::span<const std::uint32_t> ProbeGrid::candidates(const glm::vec3& x) const { return cellCandidates(cellOf(x)); }

std::span<const std::uint32_t> ProbeGrid::cellCandidates(std::size_t c) const {
    const std::uint32_t* first = table_.data() + c * std::size_t(k_);
    std::size_t n = 0;
    while (n < std::size_t(k_) && first[n] != kNone) ++n;
    return {first, n};
}

}  // namespace cubeao
