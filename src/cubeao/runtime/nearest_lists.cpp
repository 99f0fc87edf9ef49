#include "cubeao/runtime/nearest_lists.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include "common/projection.h"
#include "common/runtime_layout.h"
#include "cubeao/core/error.h"

namespace cubeao {

NearestProbeLists::NearestProbeLists(const glm::vec3& boundsMin, const glm::vec3& boundsMax, float minCellSize, int k,
                                     std::size_t maxCells) {
    if (k <= 0) throw Error("NearestProbeLists: k must be positive, got " + std::to_string(k));
    k_ = k;
    const glm::vec3 extent = glm::max(boundsMax - boundsMin, glm::vec3(1e-6f));
    cell_ = minCellSize > 0.0f ? minCellSize : std::max({extent.x, extent.y, extent.z}) / 16.0f;
    for (;;) {  // widen until the grid fits the cap
        dims_ = glm::max(glm::ivec3(glm::ceil(extent / cell_)), glm::ivec3(1));
        if (double(dims_.x) * dims_.y * dims_.z <= double(std::max<std::size_t>(maxCells, 1))) break;
        cell_ *= 1.25f;
    }
    origin_ = boundsMin;
    const std::size_t cells = std::size_t(dims_.x) * std::size_t(dims_.y) * std::size_t(dims_.z);
    table_.assign(cells * std::size_t(k_), kernel::kNoProbe);
    buckets_.assign(cells, {});
}

std::span<const std::uint32_t> NearestProbeLists::cellList(std::size_t c) const {
    return {table_.data() + c * std::size_t(k_), std::size_t(k_)};
}

glm::vec3 NearestProbeLists::cellCentre(std::size_t c) const {
    return kernel::candidateCellCentre(kernel::candidateCellCoordinates(std::uint32_t(c), dims_), origin_, cell_);
}

std::size_t NearestProbeLists::cellOf(const glm::vec3& position) const {
    const glm::ivec3 c = kernel::candidateCellOf(position, origin_, cell_, dims_);
    return (std::size_t(c.z) * std::size_t(dims_.y) + std::size_t(c.y)) * std::size_t(dims_.x) + std::size_t(c.x);
}

std::vector<std::size_t> NearestProbeLists::assign(std::span<const std::uint32_t> ids,
                                                   std::span<const glm::vec3> positions) {
    if (ids.size() != positions.size()) throw Error("NearestProbeLists::assign: ids and positions differ in count");
    const std::size_t cells = cellCount(), k = std::size_t(k_);
    // The difference from the last set: ids that left (or moved), ids that came (or moved).
    std::uint32_t top = 0;
    for (const std::uint32_t id : ids) top = std::max(top, id + 1);
    if (top > where_.size()) where_.resize(top), member_.resize(top, 0), bucketOf_.resize(top);
    std::vector<std::uint8_t> inNew(where_.size(), 0);
    std::vector<std::uint32_t> added, removed;
    for (std::size_t i = 0; i < ids.size(); ++i) {
        const std::uint32_t id = ids[i];
        if (inNew[id]) throw Error("NearestProbeLists::assign: id " + std::to_string(id) + " listed twice");
        inNew[id] = 1;
        if (!member_[id] || where_[id] != positions[i]) {
            if (member_[id]) removed.push_back(id);
            added.push_back(id);
        }
    }
    for (std::uint32_t id = 0; id < member_.size(); ++id)
        if (member_[id] && !inNew[id]) removed.push_back(id);
    if (added.empty() && removed.empty()) return {};

    std::vector<std::uint8_t> isRemoved(where_.size(), 0);
    for (const std::uint32_t id : removed) {
        isRemoved[id] = 1;
        std::vector<std::uint32_t>& b = buckets_[bucketOf_[id]];
        b.erase(std::find(b.begin(), b.end(), id));  // order within a bucket does not matter
        member_[id] = 0;
    }
    for (std::size_t i = 0; i < ids.size(); ++i) {
        const std::uint32_t id = ids[i];
        if (member_[id]) continue;
        where_[id] = positions[i];
        member_[id] = 1;
        bucketOf_[id] = cellOf(positions[i]);
        buckets_[bucketOf_[id]].push_back(id);
    }

    // A cell's list changes only if it held a probe that left, or a probe that came would rank among
    // its k (nearest first, ties by the smaller id), or it was not full; those cells are searched again.
    // Many arrivals at once (the first frame, a cut): every cell.
    const bool everyCell = added.size() + removed.size() > std::max<std::size_t>(ids.size() / 4, 64);
    std::vector<std::size_t> changed;
    std::vector<std::pair<float, std::uint32_t>> found;  // scratch of nearestOf
    std::vector<std::uint32_t> list(k);
    for (std::size_t c = 0; c < cells; ++c) {
        std::uint32_t* out = table_.data() + c * k;
        bool search = everyCell || out[k - 1] == kernel::kNoProbe;
        for (std::size_t j = 0; j < k && !search; ++j) search = isRemoved[out[j]] != 0;
        if (!search && !added.empty()) {
            const glm::vec3 centre = cellCentre(c);
            const glm::vec3 dl = where_[out[k - 1]] - centre;
            const std::pair<float, std::uint32_t> last(glm::dot(dl, dl), out[k - 1]);
            for (const std::uint32_t id : added) {
                const glm::vec3 d = where_[id] - centre;
                if (std::pair<float, std::uint32_t>(glm::dot(d, d), id) < last) {
                    search = true;
                    break;
                }
            }
        }
        if (!search) continue;
        nearestOf(c, ids, found, list);
        if (!std::equal(list.begin(), list.end(), out)) {
            std::copy(list.begin(), list.end(), out);
            changed.push_back(c);
        }
    }
    return changed;
}

void NearestProbeLists::nearestOf(std::size_t c, std::span<const std::uint32_t> ids,
                                  std::vector<std::pair<float, std::uint32_t>>& found,
                                  std::vector<std::uint32_t>& list) const {
    const std::size_t k = std::size_t(k_);
    const glm::ivec3 at = kernel::candidateCellCoordinates(std::uint32_t(c), dims_);
    const glm::vec3 centre = kernel::candidateCellCentre(at, origin_, cell_);
    found.clear();
    std::size_t visited = 0;
    const auto take = [&](int x, int y, int z) {
        const std::size_t cell = (std::size_t(z) * std::size_t(dims_.y) + std::size_t(y)) * std::size_t(dims_.x) +
                                 std::size_t(x);
        ++visited;
        for (const std::uint32_t id : buckets_[cell]) {
            const glm::vec3 d = where_[id] - centre;
            found.emplace_back(glm::dot(d, d), id);
        }
    };
    // Rings of cells at Chebyshev distance r: every probe in ring r + 1 or beyond lies at least
    // (r + 1/2) cells from the centre (a probe clamped into a border cell lies farther still). Where
    // the probes are sparse, once the rings have cost more than trying every probe, try every probe.
    const int maxRing = std::max({dims_.x, dims_.y, dims_.z});
    bool complete = false;
    for (int r = 0; r <= maxRing && !complete; ++r) {
        const glm::ivec3 lo = at - r, hi = at + r;
        for (int z = std::max(lo.z, 0); z <= std::min(hi.z, dims_.z - 1); ++z)
            for (int y = std::max(lo.y, 0); y <= std::min(hi.y, dims_.y - 1); ++y) {
                if (r == 0 || z == lo.z || z == hi.z || y == lo.y || y == hi.y) {
                    for (int x = std::max(lo.x, 0); x <= std::min(hi.x, dims_.x - 1); ++x) take(x, y, z);
                } else {
                    if (lo.x >= 0) take(lo.x, y, z);
                    if (hi.x < dims_.x) take(hi.x, y, z);
                }
            }
        if (found.size() >= k) {
            std::nth_element(found.begin(), found.begin() + std::ptrdiff_t(k - 1), found.end());
            const float reach = (float(r) + 0.5f) * cell_;
            complete = found[k - 1].first < reach * reach;
        }
        if (!complete && visited > ids.size()) {
            found.clear();
            for (const std::uint32_t id : ids) {
                const glm::vec3 d = where_[id] - centre;
                found.emplace_back(glm::dot(d, d), id);
            }
            complete = true;
        }
    }
    const std::size_t n = std::min(found.size(), k);
    std::partial_sort(found.begin(), found.begin() + std::ptrdiff_t(n), found.end());
    for (std::size_t j = 0; j < k; ++j) list[j] = j < n ? found[j].second : kernel::kNoProbe;
}

}  // namespace cubeao
