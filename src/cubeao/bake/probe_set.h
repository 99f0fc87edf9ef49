// probes.json, the hand-over from placement to bake:
//   {"version": 1, "probes": [{"pos": [x, y, z]}, ...]}
// Placement adds fields (method, parameters, coverage report, each probe's "gain": the coverage it
// added after the ones before it, in the order chosen); readers ignore what they do not know.
#pragma once

#include <filesystem>
#include <vector>

#include <glm/vec3.hpp>
#include <nlohmann/json_fwd.hpp>

#include "cubeao/scene/camera_path.h"

namespace cubeao {

struct ProbeSpec {
    glm::vec3 position{0.0f};
    double gain = -1.0;  // coverage this probe added, in the order chosen; < 0: unknown (not written)
};

// Throws cubeao::Error naming the file and the probe for a missing/unreadable file, bad JSON, an
// unknown version, a missing or non-finite position, or no probes at all.
std::vector<ProbeSpec> readProbeSet(const std::filesystem::path& file);
// Atomic (temporary file + rename).
void writeProbeSet(const std::filesystem::path& file, const std::vector<ProbeSpec>& probes);
// The same with `meta`'s fields (an object; "version" and "probes" are ours) at the top level.
void writeProbeSet(const std::filesystem::path& file, const std::vector<ProbeSpec>& probes, const nlohmann::json& meta);

// `cubeao place --method path`: min(count, frames) probes at the camera's eye, at the frame centres of
// that many equal parts of the path (the first and last half a part in).
std::vector<ProbeSpec> probesAlongPath(const CameraPath& path, std::size_t count);

}  // namespace cubeao
