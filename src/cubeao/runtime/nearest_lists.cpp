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
    table_.assign(std::size_t(dims_.x) * std::size_t(dims_.y) * std::size_t(dims_.z) * std::size_t(k_),
                  kernel::kNoProbe);
}

std::span<const std::uint32_t> NearestProbeLists::cellList(std::size_t c) const {
    return {table_.data() + c * std::size_t(k_), std::size_t(k_)};
}

glm::vec3 NearestProbeLists::cellCentre(std::size_t c) const {
    return kernel::candidateCellCentre(kernel::candidateCellCoordinates(std::uint32_t(c), dims_), origin_, cell_);
}

std::vector<std::size_t> NearestProbeLists::assign(std::span<const std::uint32_t> ids,
                                                   std::span<const glm::vec3> positions) {
    if (ids.size() != positions.size()) throw Error("NearestProbeLists::assign: ids and positions differ in count");
    const std::size_t cells = cellCount(), k = std::size_t(k_);
    const auto index = [&](const glm::ivec3& c) {
        return (std::size_t(c.z) * std::size_t(dims_.y) + std::size_t(c.y)) * std::size_t(dims_.x) + std::size_t(c.x);
    };
    // Probes bucketed by cell (clamped into the grid): bucket c is order[start[c] .. start[c + 1]).
    std::vector<std::size_t> start(cells + 1, 0), order(ids.size());
    std::vector<std::size_t> cellOfProbe(ids.size());
    for (std::size_t i = 0; i < ids.size(); ++i) {
        cellOfProbe[i] = index(kernel::candidateCellOf(positions[i], origin_, cell_, dims_));
        ++start[cellOfProbe[i] + 1];
    }
    for (std::size_t c = 0; c < cells; ++c) start[c + 1] += start[c];
    {
        std::vector<std::size_t> fill(start.begin(), start.end() - 1);
        for (std::size_t i = 0; i < ids.size(); ++i) order[fill[cellOfProbe[i]]++] = i;
    }

    std::vector<std::size_t> changed;
    std::vector<std::pair<float, std::uint32_t>> found;  // (squared distance, id)
    std::vector<std::uint32_t> list(k);
    const int maxRing = std::max({dims_.x, dims_.y, dims_.z});
    for (std::size_t c = 0; c < cells; ++c) {
        const glm::ivec3 at = kernel::candidateCellCoordinates(std::uint32_t(c), dims_);
        const glm::vec3 centre = kernel::candidateCellCentre(at, origin_, cell_);
        found.clear();
        std::size_t visited = 0;
        const auto take = [&](int x, int y, int z) {
            const std::size_t cell = index({x, y, z});
            ++visited;
            for (std::size_t j = start[cell]; j < start[cell + 1]; ++j) {
                const std::size_t i = order[j];
                const glm::vec3 d = positions[i] - centre;
                found.emplace_back(glm::dot(d, d), ids[i]);
            }
        };
        // Rings of cells at Chebyshev distance r: every probe in ring r + 1 or beyond lies at least
        // (r + 1/2) cells from the centre (a probe clamped into a border cell lies farther still). Where
        // the probes are sparse, once the rings have cost more than trying every probe, try every probe.
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
                for (std::size_t i = 0; i < ids.size(); ++i) {
                    const glm::vec3 d = positions[i] - centre;
                    found.emplace_back(glm::dot(d, d), ids[i]);
                }
                complete = true;
            }
        }
        const std::size_t n = std::min(found.size(), k);
        std::partial_sort(found.begin(), found.begin() + std::ptrdiff_t(n), found.end());
        for (std::size_t j = 0; j < k; ++j) list[j] = j < n ? found[j].second : kernel::kNoProbe;
        std::uint32_t* out = table_.data() + c * k;
        if (!std::equal(list.begin(), list.end(), out)) {
            std::copy(list.begin(), list.end(), out);
            changed.push_back(c);
        }
    }
    return changed;
}

}  // namespace cubeao
