// Points spread over a mesh's surface: the one sampler of the run-time's candidate grid
// (runtime/probe_grid.h, which chooses each cell's probes on them) and of placement's coverage and
// error estimates (placement/coverage.h). In core rather than scene/ because the run-time library,
// which engines link, takes a mesh as spans and links no importer.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

namespace cubeao {

// A surface point as a camera could see it: position and the unit normal of the side seen.
struct SurfaceSample {
    glm::vec3 position{0.0f};
    glm::vec3 normal{0.0f, 0.0f, 1.0f};  // unit, the side this sample stands for
    float area = 0.0f;                   // the surface area it stands for (one side's)
    std::uint32_t triangle = 0;
};

// `points` area-uniform points (stratified along the cumulative area of the triangles, jittered by
// `seed`), each returned twice, once per side: samples 2i and 2i + 1 share a position. Deterministic,
// and the same whichever way the faces are wound (each triangle's corners are taken in order of
// position). None for a mesh without area.
std::vector<SurfaceSample> sampleSurface(std::span<const glm::vec3> positions, std::span<const std::uint32_t> indices,
                                         std::size_t points, std::uint32_t seed);

// The `points` for about one sample per spacing² of area on each side, widened to at most
// maxSamples samples (both sides counted).
std::size_t surfacePointsFor(std::span<const glm::vec3> positions, std::span<const std::uint32_t> indices,
                             float spacing, std::size_t maxSamples);

}  // namespace cubeao
