// The projection's second list (DESIGN.md §4 "Run time that grows"): a coarse grid whose every cell
// lists the K probes of a set nearest its centre. The set is the resident probes: a pixel none of
// whose cell's candidates (probe_grid.h) is resident and sees it tries these before the screen-space
// fallback. The candidate grid chooses per cell from every probe, so under a small budget, or with
// thousands of probes crowding the cells, whole regions can have no resident candidate while resident
// probes a few metres away see them; the issue asks for "the next resident candidate that sees it".
//
// Nearest rather than chosen by quality: the set changes whenever the residency loads or evicts,
// and a rebuild costs a ring search per cell (milliseconds), not the candidate grid's sampled
// qualities; the projection's depth test then keeps only those that see the point.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <utility>
#include <vector>

#include <glm/vec3.hpp>

namespace cubeao {

class NearestProbeLists {
public:
    // A grid over [boundsMin, boundsMax] of cubic cells at least `minCellSize` wide, widened until
    // there are at most maxCells; k entries per cell.
    NearestProbeLists(const glm::vec3& boundsMin, const glm::vec3& boundsMax, float minCellSize, int k,
                      std::size_t maxCells = std::size_t(1) << 14);

    // Lists, per cell, the k of `ids` nearest its centre (positions[i] is ids[i]'s position), nearest
    // first, ties by the smaller id; returns the cells whose list changed (ascending). Incremental: it
    // searches again only the cells a probe that left or came can change (the lists equal a rebuild;
    // tested), so a frame that loads a few probes costs microseconds, not a search per cell. Error for
    // an id listed twice.
    std::vector<std::size_t> assign(std::span<const std::uint32_t> ids, std::span<const glm::vec3> positions);

    // GPU layout: cells in x-fastest order, k entries each, unused entries = kernel::kNoProbe.
    const std::vector<std::uint32_t>& table() const { return table_; }
    std::span<const std::uint32_t> cellList(std::size_t c) const;
    glm::vec3 cellCentre(std::size_t c) const;
    std::size_t cellCount() const { return table_.size() / std::size_t(k_); }
    glm::ivec3 dims() const { return dims_; }
    glm::vec3 origin() const { return origin_; }
    float cellSize() const { return cell_; }
    int k() const { return k_; }

private:
    std::size_t cellOf(const glm::vec3& position) const;  // x-fastest index, clamped into the grid
    // Cell c's k nearest of the set (ring search over the buckets; `ids` is the whole set) into list.
    void nearestOf(std::size_t c, std::span<const std::uint32_t> ids, std::vector<std::pair<float, std::uint32_t>>& found,
                   std::vector<std::uint32_t>& list) const;

    glm::vec3 origin_{0.0f};
    glm::ivec3 dims_{1};
    float cell_ = 1.0f;
    int k_ = 8;
    std::vector<std::uint32_t> table_;
    // The set of the last assign, by id: position, membership, bucket (cell); and each cell's members.
    std::vector<glm::vec3> where_;
    std::vector<std::uint8_t> member_;
    std::vector<std::size_t> bucketOf_;
    std::vector<std::vector<std::uint32_t>> buckets_;
};

}  // namespace cubeao
