// probes.json, the hand-over from placement to bake:
//   {"version": 1, "probes": [{"pos": [x, y, z]}, ...]}
// (placement adds fields; readers ignore what they do not know).
#pragma once

#include <filesystem>
#include <vector>

#include <glm/vec3.hpp>

namespace cubeao {

struct ProbeSpec {
    glm::vec3 position{0.0f};
};

// Throws cubeao::Error naming the file and the probe for a missing/unreadable file, bad JSON, an
// unknown version, a missing or non-finite position, or no probes at all.
std::vector<ProbeSpec> readProbeSet(const std::filesystem::path& file);
// Atomic (temporary file + rename).
void writeProbeSet(const std::filesystem::path& file, const std::vector<ProbeSpec>& probes);

}  // namespace cubeao
