#include "cubeao/runtime/probe_grid.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>
#include <random>

#include <glm/geometric.hpp>

#include "common/projection.h"
#include "common/runtime_layout.h"
#include "cubeao/core/sampling.h"

namespace cubeao {
namespace {

constexpr std::uint32_t kNone = kernel::kNoProbe;

// Uniform in [0, 1) from a triangle index and a counter (sampling.h's hash: deterministic).
float unit(std::uint32_t triangle, std::uint32_t counter) {
    return sampling::toUnitFloat(sampling::hashKey(triangle, counter, 0x9a1du));
}

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

std::vector<SurfacePoint> sampleSurface(std::span<const glm::vec3> positions, std::span<const std::uint32_t> indices,
                                        float spacing, std::size_t maxPoints) {
    double area = 0.0;
    for (std::size_t t = 0; t + 2 < indices.size(); t += 3) {
        const glm::vec3 a = positions[indices[t]], b = positions[indices[t + 1]], c = positions[indices[t + 2]];
        area += 0.5 * double(glm::length(glm::cross(b - a, c - a)));
    }
    const double perArea = std::min(1.0 / (double(spacing) * spacing), double(maxPoints) / std::max(2.0 * area, 1e-30));
    std::vector<SurfacePoint> points;
    points.reserve(std::min(maxPoints, std::size_t(2.0 * area * perArea) + indices.size()));
    for (std::size_t t = 0; t + 2 < indices.size(); t += 3) {
        const glm::vec3 a = positions[indices[t]], b = positions[indices[t + 1]], c = positions[indices[t + 2]];
        const glm::vec3 cross = glm::cross(b - a, c - a);
        const float twiceArea = glm::length(cross);
        if (!(twiceArea > 0.0f)) continue;
        const glm::vec3 n = cross / twiceArea;
        const auto tri = std::uint32_t(t / 3);
        const double expected = 0.5 * double(twiceArea) * perArea;
        auto count = std::uint32_t(expected);
        if (unit(tri, 0) < expected - double(count)) ++count;  // stochastic rounding keeps the density
        for (std::uint32_t i = 0; i < count; ++i) {
            const float r = std::sqrt(unit(tri, 2 * i + 1)), v = unit(tri, 2 * i + 2);  // uniform on the triangle
            const glm::vec3 x = (1.0f - r) * a + r * (1.0f - v) * b + r * v * c;
            points.push_back({x, n});
            points.push_back({x, -n});
        }
    }
    return points;
}

ProbeGrid::ProbeGrid(const glm::vec3& boundsMin, const glm::vec3& boundsMax, std::span<const glm::vec3> probes,
                     std::span<const SurfacePoint> points, const QualityFn& quality, ProbeGridSettings s) {
    k_ = s.candidates > 0 ? s.candidates : 8;
    const int maxCells = s.maxCells > 0 ? s.maxCells : 1 << 20;
    const std::size_t considered =
        std::min(probes.size(), std::size_t(s.considered > 0 ? s.considered : std::max(8 * k_, 64)));
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

    // Each cell's points, at most perCell of them: a fixed random subset, not the first triangles'.
    std::vector<std::uint32_t> order(points.size());
    std::iota(order.begin(), order.end(), 0u);
    std::shuffle(order.begin(), order.end(), std::mt19937(12345u));
    std::vector<std::vector<std::uint32_t>> cellPoints(cells);
    for (std::uint32_t i : order) {
        std::vector<std::uint32_t>& list = cellPoints[cellOf(points[i].position)];
        if (list.size() < perCell) list.push_back(i);
    }

    std::vector<std::uint32_t> byDistance(probes.size());
    std::vector<float> distance2(probes.size());
    std::vector<double> q;
    for (int z = 0; z < dims_.z; ++z)
        for (int y = 0; y < dims_.y; ++y)
            for (int x = 0; x < dims_.x; ++x) {
                const std::size_t cell = (std::size_t(z) * std::size_t(dims_.y) + std::size_t(y)) * std::size_t(dims_.x) + std::size_t(x);
                const glm::vec3 centre = origin_ + (glm::vec3(x, y, z) + 0.5f) * cell_;
                for (std::uint32_t p = 0; p < probes.size(); ++p) {
                    const glm::vec3 d = probes[p] - centre;
                    distance2[p] = glm::dot(d, d);
                }
                std::iota(byDistance.begin(), byDistance.end(), 0u);
                const auto nearer = [&](std::uint32_t a, std::uint32_t b) {
                    return distance2[a] != distance2[b] ? distance2[a] < distance2[b] : a < b;
                };
                std::partial_sort(byDistance.begin(), byDistance.begin() + std::ptrdiff_t(considered), byDistance.end(),
                                  nearer);
                const std::span<const std::uint32_t> nearest(byDistance.data(), considered);
                const std::vector<std::uint32_t>& mine = cellPoints[cell];
                q.assign(considered * mine.size(), 0.0);
                for (std::size_t p = 0; p < considered; ++p)
                    for (std::size_t i = 0; i < mine.size(); ++i) q[p * mine.size() + i] = quality(nearest[p], points[mine[i]]);
                chooseCandidates(nearest, q, mine.size(), k_, table_.data() + cell * std::size_t(k_));
            }
}

std::size_t ProbeGrid::cellOf(const glm::vec3& x) const {
    const glm::ivec3 c = kernel::candidateCellOf(x, origin_, cell_, dims_);  // the cell project.comp reads
    return (std::size_t(c.z) * std::size_t(dims_.y) + std::size_t(c.y)) * std::size_t(dims_.x) + std::size_t(c.x);
}

std::span<const std::uint32_t> ProbeGrid::candidates(const glm::vec3& x) const {
    const std::uint32_t* first = table_.data() + cellOf(x) * std::size_t(k_);
    std::size_t n = 0;
    while (n < std::size_t(k_) && first[n] != kNone) ++n;
    return {first, n};
}

}  // namespace cubeao
