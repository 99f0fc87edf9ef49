#include "cubeao/core/surface_samples.h"

#include <algorithm>
#include <array>
#include <cmath>

#include <glm/geometric.hpp>

#include "cubeao/core/sampling.h"

namespace cubeao {
namespace {

double triangleArea(std::span<const glm::vec3> positions, std::span<const std::uint32_t> indices, std::size_t t) {
    const glm::vec3 a = positions[indices[3 * t]], b = positions[indices[3 * t + 1]], c = positions[indices[3 * t + 2]];
    return 0.5 * double(glm::length(glm::cross(b - a, c - a)));
}

// The area of each triangle summed in order: cumulative[t] = area of triangles 0..t.
std::vector<double> cumulativeArea(std::span<const glm::vec3> positions, std::span<const std::uint32_t> indices) {
    std::vector<double> cumulative(indices.size() / 3);
    double total = 0.0;
    for (std::size_t t = 0; t < cumulative.size(); ++t) cumulative[t] = total += triangleArea(positions, indices, t);
    return cumulative;
}

}  // namespace

std::vector<SurfaceSample> sampleSurface(std::span<const glm::vec3> positions, std::span<const std::uint32_t> indices,
                                         std::size_t points, std::uint32_t seed) {
    const std::vector<double> cumulative = cumulativeArea(positions, indices);
    const std::size_t triangles = cumulative.size();
    const double total = triangles == 0 ? 0.0 : cumulative.back();
    std::vector<SurfaceSample> samples;
    if (points == 0 || !(total > 0.0)) return samples;
    samples.reserve(2 * points);
    const float area = float(total / double(points));
    for (std::size_t i = 0; i < points; ++i) {
        // Stratified: point i falls in the i-th of `points` equal slices of the cumulative area.
        const std::uint32_t key = sampling::hashKey(std::uint32_t(i), seed, 0x5A3F1u);
        const double u = (double(i) + double(sampling::toUnitFloat(key))) / double(points) * total;
        const std::size_t t = std::min<std::size_t>(
            std::size_t(std::upper_bound(cumulative.begin(), cumulative.end(), u) - cumulative.begin()), triangles - 1);
        // The corners in a fixed order (by position), not the winding's: a model with faces reversed is
        // sampled at the same points with the same two sides in the same order (issue 31).
        std::array<glm::vec3, 3> corner{positions[indices[3 * t]], positions[indices[3 * t + 1]],
                                        positions[indices[3 * t + 2]]};
        std::sort(corner.begin(), corner.end(), [](const glm::vec3& l, const glm::vec3& r) {
            return l.x != r.x ? l.x < r.x : l.y != r.y ? l.y < r.y : l.z < r.z;
        });
        const auto& [a, b, c] = corner;
        // Uniform in the triangle: the square-root map of two hashed numbers.
        const float r1 = std::sqrt(sampling::toUnitFloat(sampling::hash32(key ^ 0x68E31DA4u)));
        const float r2 = sampling::toUnitFloat(sampling::hash32(key ^ 0xB5297A4Du));
        const glm::vec3 p = (1.0f - r1) * a + r1 * (1.0f - r2) * b + r1 * r2 * c;
        const glm::vec3 n = glm::normalize(glm::cross(b - a, c - a));
        samples.push_back({p, n, area, std::uint32_t(t)});
        samples.push_back({p, -n, area, std::uint32_t(t)});
    }
    return samples;
}

std::size_t surfacePointsFor(std::span<const glm::vec3> positions, std::span<const std::uint32_t> indices,
                             float spacing, std::size_t maxSamples) {
    double total = 0.0;  // summed in cumulativeArea's order: the same total sampleSurface divides
    for (std::size_t t = 0; t < indices.size() / 3; ++t) total += triangleArea(positions, indices, t);
    const double perSide = std::ceil(total / (double(spacing) * double(spacing)));
    return std::size_t(std::min(perSide, double(maxSamples / 2)));
}

}  // namespace cubeao
