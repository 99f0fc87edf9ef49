// A probe's levels of detail (docs/FORMAT.md "Levels of detail", format 5): the coarser cubes stored
// after the full-resolution one in each section, what a run time holds of a probe it sees from far
// away. Each level is made from the full-resolution data, not from a compressed level:
// - AO and confidence: the mean over the 2^k × 2^k full-resolution texels a level-k texel covers,
//   of those that show a surface (all of them where none does: empty texels hold AO 1), then BC5
//   (the writer keeps the red half for a BC4 cache). Sky does not brighten a silhouette's coarse AO.
// - Distance: the nearest non-empty stored texel of the 2 × 2 it covers in the level above, i.e. the
//   minimum over every full-resolution texel the cube's Min filter saw (depth_cube.h), on the stored
//   codes themselves: every format's codes order as their distances do, so no level re-quantises.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include <glm/vec2.hpp>

#include "cubeao/cache/cache_file.h"

namespace cubeao::levels {

// Levels 1 … levels − 1 of the AO (BC5 blocks, cache/bc4.h layout, level after level): from the
// full-resolution (AO, confidence) and distances (0 = the texel shows no surface), 6·res² each in
// cube::texelIndex order. Empty for levels ≤ 1. Error when res does not halve `levels − 1` times into
// whole blocks or a size is wrong.
std::vector<std::uint8_t> coarserAo(std::span<const glm::vec2> aoConfidence, std::span<const float> distances, int res,
                                    int levels);

// Levels 1 … levels − 1 of the distance cube, from level 0's stored bytes (6·depthRes² texels of
// `format`). Empty for levels ≤ 1. Error when depthRes does not halve `levels − 1` times or the size
// is wrong.
std::vector<std::uint8_t> coarserDistances(std::span<const std::uint8_t> level0, int depthRes, DepthFormat format,
                                           int levels);

}  // namespace cubeao::levels
