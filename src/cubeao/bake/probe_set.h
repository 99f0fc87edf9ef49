// probes.json, the hand-over from placement to bake:
//   {"version": 1, "probes": [{"pos": [x, y, z]}, ...]}
// (placement adds fields; readers ignore what they do not know).
#pragma once

#include <filesystem>
#include <vector>

#include <glm/vec3.hpp>

#include "cubeao/scene/camera_path.h"

namespace cubeao {

struct ProbeSpec {
    glm::vec3 position{0.0f};
};

// Throws cubeao::Error naming the file and the probe for a missing/unreadable file, bad JSON, an
// unknown version, a missing or non-finite position, or no probes at all.
std::vector<ProbeSpec> readProbeSet(const std::filesystem::path& file);
// Atomic (temporary file + rename).
void writeProbeSet(const std::filesystem::path& file, const std::vector<ProbeSpec>& probes);

// `cubeao place --method path`: min(count, frames) probes at the camera's eye, at the frame centres of
// that many equal parts of the path (the first and last half a part in).
std::vector<ProbeSpec> probesAlongPath(const CameraPath& path, std::size_t count);

}  // namespace cubeao
