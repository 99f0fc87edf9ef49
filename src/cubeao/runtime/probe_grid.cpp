#include "cubeao/runtime/probe_grid.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

namespace cubeao {

ProbeGrid::ProbeGrid(const glm::vec3& boundsMin, const glm::vec3& boundsMax, std::span<const glm::vec3> probes,
                     const SeesFn& sees, ProbeGridSettings s) {
    k_ = s.candidates > 0 ? s.candidates : 8;
    const int maxCells = s.maxCells > 0 ? s.maxCells : 1 << 20;
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
    table_.assign(cells * std::size_t(k_), 0xffffffffu);

    struct Scored {
        float distance2;
        bool seen;
        std::uint32_t probe;
    };
    std::vector<Scored> scored(probes.size());
    for (int z = 0; z < dims_.z; ++z)
        for (int y = 0; y < dims_.y; ++y)
            for (int x = 0; x < dims_.x; ++x) {
                const glm::vec3 lo = origin_ + glm::vec3(x, y, z) * cell_;
                const glm::vec3 centre = lo + 0.5f * cell_;
                for (std::uint32_t p = 0; p < probes.size(); ++p) {
                    const glm::vec3 d = centre - probes[p];
                    bool seen = sees(p, centre);
                    for (int c = 0; c < 8 && !seen; ++c)
                        seen = sees(p, lo + cell_ * glm::vec3(c & 1, (c >> 1) & 1, (c >> 2) & 1));
                    scored[p] = {glm::dot(d, d), seen, p};
                }
                const std::size_t keep = std::min<std::size_t>(std::size_t(k_), scored.size());
                std::partial_sort(scored.begin(), scored.begin() + std::ptrdiff_t(keep), scored.end(),
                                  [](const Scored& a, const Scored& b) {
                                      return a.seen != b.seen ? a.seen : a.distance2 < b.distance2;
                                  });
                const std::size_t cell = (std::size_t(z) * std::size_t(dims_.y) + std::size_t(y)) * std::size_t(dims_.x) + std::size_t(x);
                for (std::size_t i = 0; i < keep; ++i) table_[cell * std::size_t(k_) + i] = scored[i].probe;
            }
}

std::size_t ProbeGrid::cellOf(const glm::vec3& x) const {
    const glm::ivec3 c = glm::clamp(glm::ivec3(glm::floor((x - origin_) / cell_)), glm::ivec3(0), dims_ - 1);
    return (std::size_t(c.z) * std::size_t(dims_.y) + std::size_t(c.y)) * std::size_t(dims_.x) + std::size_t(c.x);
}

std::span<const std::uint32_t> ProbeGrid::candidates(const glm::vec3& x) const {
    const std::uint32_t* first = table_.data() + cellOf(x) * std::size_t(k_);
    std::size_t n = 0;
    while (n < std::size_t(k_) && first[n] != 0xffffffffu) ++n;
    return {first, n};
}

}  // namespace cubeao
