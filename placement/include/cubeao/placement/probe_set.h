// probes.json, the hand-over from placement to bake (placement owns it; the bake takes positions):
//   {"version": 1, "probes": [{"pos": [x, y, z]}, ...]}   (the model file's coordinates)
// Placement adds fields (method, parameters, its report, each probe's "gain": the predicted walk MAE
// it removed after the ones before it, in the order chosen); readers ignore what they do not know.
#pragma once

#include <filesystem>
#include <vector>

#include <glm/ext/vector_double3.hpp>
#include <glm/vec3.hpp>
#include <nlohmann/json_fwd.hpp>

#include "cubeao/scene/camera_path.h"

namespace cubeao {

struct ProbeSpec {
    glm::vec3 position{0.0f};
    double gain = -1.0;  // coverage this probe added, in the order chosen; < 0: unknown (not written)
};

// Positions in probes.json are file coordinates; ProbeSpec::position is relative to `origin` (the scene's,
// Scene::origin), the subtraction done in double on the JSON's numbers.
// Throws cubeao::Error naming the file and the probe for a missing/unreadable file, bad JSON, an
// unknown version, a missing or non-finite position, or no probes at all.
std::vector<ProbeSpec> readProbeSet(const std::filesystem::path& file, const glm::dvec3& origin = glm::dvec3(0.0));
// Atomic (temporary file + rename).
void writeProbeSet(const std::filesystem::path& file, const std::vector<ProbeSpec>& probes);
// The same with `meta`'s fields (an object; "version" and "probes" are ours) at the top level, positions
// written as position + origin in double (as the floats they always were when the origin is 0).
void writeProbeSet(const std::filesystem::path& file, const std::vector<ProbeSpec>& probes, const nlohmann::json& meta,
                   const glm::dvec3& origin = glm::dvec3(0.0));

// The positions alone, in order (what BakeJob::probes and BakeCacheWriter take).
std::vector<glm::vec3> positionsOf(const std::vector<ProbeSpec>& probes);

// `cubeao place --method path`: min(count, frames) probes at the camera's eye, at the frame centres of
// that many equal parts of the path (the first and last half a part in).
std::vector<ProbeSpec> probesAlongPath(const CameraPath& path, std::size_t count);

}  // namespace cubeao
