#include "cubeao/placement/probe_set.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "cubeao/core/durable_file.h"
#include "cubeao/core/error.h"

namespace cubeao {

std::vector<ProbeSpec> readProbeSet(const std::filesystem::path& file, const glm::dvec3& origin) {
    std::ifstream in(file);
    if (!in) throw Error(file.string() + ": cannot open probe set");
    nlohmann::json j;
    try {
        j = nlohmann::json::parse(in);
    } catch (const nlohmann::json::exception& e) {
        throw Error(file.string() + ": not valid JSON (" + e.what() + ")");
    }
    const std::string where = file.string() + ": ";
    if (!j.is_object() || !j.contains("version") || !j["version"].is_number_integer())
        throw Error(where + "expected an object with an integer \"version\"");
    if (j["version"] != 1)  // compared as numbers: get<int>() would wrap 4294967297 to 1
        throw Error(where + "probe-set version " + j["version"].dump() + " is not supported (this build reads version 1)");
    if (!j.contains("probes") || !j["probes"].is_array()) throw Error(where + "expected a \"probes\" array");
    std::vector<ProbeSpec> probes;
    for (std::size_t i = 0; i < j["probes"].size(); ++i) {
        const auto& p = j["probes"][i];
        const std::string item = where + "probe " + std::to_string(i) + ": ";
        if (!p.is_object() || !p.contains("pos") || !p["pos"].is_array() || p["pos"].size() != 3)
            throw Error(item + "expected {\"pos\": [x, y, z]}");
        ProbeSpec spec;
        for (int k = 0; k < 3; ++k) {
            if (!p["pos"][k].is_number()) throw Error(item + "position components must be numbers");
            const double v = p["pos"][k].get<double>();
            if (!std::isfinite(v) || std::fabs(v) > 1e30) throw Error(item + "position is not finite");
            spec.position[k] = float(v - origin[k]);
        }
        probes.push_back(spec);
    }
    if (probes.empty()) throw Error(where + "no probes");
    return probes;
}

void writeProbeSet(const std::filesystem::path& file, const std::vector<ProbeSpec>& probes) {
    writeProbeSet(file, probes, nlohmann::json::object());
}

void writeProbeSet(const std::filesystem::path& file, const std::vector<ProbeSpec>& probes, const nlohmann::json& meta,
                   const glm::dvec3& origin) {
    nlohmann::json j = meta.is_object() ? meta : nlohmann::json::object();
    j["version"] = 1;
    j["probes"] = nlohmann::json::array();
    for (const auto& p : probes) {
        const glm::vec3& q = p.position;
        const glm::dvec3 f = glm::dvec3(q) + origin;
        nlohmann::json probe{{"pos", origin == glm::dvec3(0.0) ? nlohmann::json{q.x, q.y, q.z}
                                                               : nlohmann::json{f.x, f.y, f.z}}};
        if (p.gain >= 0.0) probe["gain"] = p.gain;
        j["probes"].push_back(std::move(probe));
    }
    writeFileDurably(file, j.dump(1) + "\n", "probe set");
}

std::vector<glm::vec3> positionsOf(const std::vector<ProbeSpec>& probes) {
    std::vector<glm::vec3> positions;
    positions.reserve(probes.size());
    for (const ProbeSpec& p : probes) positions.push_back(p.position);
    return positions;
}

std::vector<ProbeSpec> probesAlongPath(const CameraPath& path, std::size_t count) {
    std::vector<ProbeSpec> probes;
    const std::size_t n = std::min(count, path.frames.size());
    for (std::size_t i = 0; i < n; ++i) probes.push_back({path.frames[(2 * i + 1) * path.frames.size() / (2 * n)].eye});
    return probes;
}

}  // namespace cubeao
