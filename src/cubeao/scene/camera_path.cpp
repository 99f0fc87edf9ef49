#include "cubeao/scene/camera_path.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <sstream>
#include <type_traits>

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>
#include <nlohmann/json.hpp>

#include "cubeao/core/durable_file.h"
#include "cubeao/core/error.h"

namespace cubeao {
namespace {

using nlohmann::json;

// Read in double and made relative to `origin` there, so a point 10^5 units out keeps its digits.
glm::vec3 readVec3(const json& j, const std::string& where, const glm::dvec3& origin = glm::dvec3(0.0)) {
    if (!j.is_array() || j.size() != 3) throw Error(where + " must be an array of 3 numbers");
    glm::vec3 v;
    for (int i = 0; i < 3; ++i) {
        if (!j[i].is_number()) throw Error(where + " must be an array of 3 numbers");
        v[i] = float(j[i].get<double>() - origin[i]);
        if (!std::isfinite(v[i])) throw Error(where + " is not finite");
    }
    return v;
}

// A point relative to `origin` back in file coordinates, as JSON: plain floats when the origin is zero
// (the file reads as it always did), doubles otherwise.
json fileVec3(const glm::vec3& v, const glm::dvec3& origin) {
    if (origin == glm::dvec3(0.0)) return {v.x, v.y, v.z};
    return {double(v.x) + origin.x, double(v.y) + origin.y, double(v.z) + origin.z};
}

// Read as a double and range-checked before the conversion: nlohmann's get<int>() of 3.6e71 is a
// float-to-int overflow, undefined behaviour (found by fuzz_camera_path).
template <class T>
T readOptional(const json& j, const char* key, T fallback, const std::string& src) {
    if (!j.contains(key)) return fallback;
    if (!j[key].is_number()) throw Error(src + ": \"" + key + "\" must be a number");
    const double v = j[key].get<double>();
    if constexpr (std::is_integral_v<T>) {
        if (!(v >= double(std::numeric_limits<T>::min()) && v <= double(std::numeric_limits<T>::max())) ||
            v != std::floor(v))
            throw Error(src + ": \"" + key + "\" must be a whole number in the range of a " +
                        std::to_string(sizeof(T) * 8) + "-bit integer (got " + j[key].dump() + ")");
    } else {
        if (!std::isfinite(v) || std::fabs(v) > double(std::numeric_limits<T>::max()))
            throw Error(src + ": \"" + key + "\" must be a finite number (got " + j[key].dump() + ")");
    }
    return T(v);
}

}  // namespace

CameraPath parseCameraPath(const std::string& text, const std::string& src, const glm::dvec3& origin) {
    json j;
    try {
        j = json::parse(text);
    } catch (const json::exception& e) {  // parse errors, and numbers too big for a double
        throw Error(src + ": not valid JSON: " + e.what());
    }
    if (!j.is_object()) throw Error(src + ": a camera path must be a JSON object");
    CameraPath p;
    p.origin = origin;
    if (j.contains("scene") && j["scene"].is_string()) p.scene = j["scene"].get<std::string>();
    if (j.contains("up")) p.up = readVec3(j["up"], src + ": \"up\"");
    if (glm::length(p.up) == 0.0f) throw Error(src + ": \"up\" is the zero vector");
    p.up = glm::normalize(p.up);
    p.fovYDeg = readOptional(j, "fov_y_deg", p.fovYDeg, src);
    p.width = readOptional(j, "width", p.width, src);
    p.height = readOptional(j, "height", p.height, src);
    p.nearPlane = readOptional(j, "near", p.nearPlane, src);
    p.farPlane = readOptional(j, "far", p.farPlane, src);
    if (!(p.fovYDeg > 0.0f && p.fovYDeg < 180.0f)) throw Error(src + ": \"fov_y_deg\" must be in (0, 180)");
    if (p.width <= 0 || p.height <= 0) throw Error(src + ": \"width\" and \"height\" must be positive");
    if (!(p.nearPlane > 0.0f && p.farPlane > p.nearPlane)) throw Error(src + ": need 0 < near < far");
    if (!j.contains("frames") || !j["frames"].is_array() || j["frames"].empty())
        throw Error(src + ": \"frames\" must be a non-empty array");
    for (std::size_t i = 0; i < j["frames"].size(); ++i) {
        const json& f = j["frames"][i];
        const std::string where = src + ": frames[" + std::to_string(i) + "]";
        if (!f.is_object() || !f.contains("eye") || !f.contains("target"))
            throw Error(where + " needs \"eye\" and \"target\"");
        CameraFrame frame{readVec3(f["eye"], where + ".eye", origin), readVec3(f["target"], where + ".target", origin)};
        const glm::vec3 fwd = frame.target - frame.eye;
        if (glm::length(fwd) == 0.0f) throw Error(where + ": eye and target coincide");
        if (glm::length(glm::cross(glm::normalize(fwd), p.up)) < 1e-6f)
            throw Error(where + ": looks straight along \"up\" (the view basis is undefined)");
        p.frames.push_back(frame);
    }
    return p;
}

CameraPath readCameraPath(const std::filesystem::path& file, const glm::dvec3& origin) {
    std::ifstream in(file);
    if (!in) throw Error(file.string() + ": cannot open camera path");
    std::stringstream ss;
    ss << in.rdbuf();
    return parseCameraPath(ss.str(), file.string(), origin);
}

void rebaseCameraPath(CameraPath& path, const glm::dvec3& origin) {
    if (path.origin == origin) return;
    const glm::dvec3 shift = path.origin - origin;
    for (CameraFrame& f : path.frames) {
        f.eye = glm::vec3(glm::dvec3(f.eye) + shift);
        f.target = glm::vec3(glm::dvec3(f.target) + shift);
    }
    path.origin = origin;
}

void writeCameraPath(const std::filesystem::path& file, const CameraPath& p) {
    json frames = json::array();
    for (const auto& f : p.frames)
        frames.push_back({{"eye", fileVec3(f.eye, p.origin)}, {"target", fileVec3(f.target, p.origin)}});
    const json j = {{"scene", p.scene},   {"up", {p.up.x, p.up.y, p.up.z}}, {"fov_y_deg", p.fovYDeg},
                    {"width", p.width},   {"height", p.height},          {"near", p.nearPlane},
                    {"far", p.farPlane},  {"frames", frames}};
    writeFileDurably(file, j.dump(1) + "\n", "camera path");
}

FrameRange parseFrameRange(const std::string& text, std::size_t count) {
    const auto n = static_cast<long long>(count);
    auto parseBound = [&](const std::string& s, long long fallback) -> long long {
        if (s.empty()) return fallback;
        std::size_t used = 0;
        long long v = 0;
        try {
            v = std::stoll(s, &used);
        } catch (const std::exception&) {
            used = 0;
        }
        if (used != s.size()) throw UsageError("--frames \"" + text + "\": expected A:B with integers");
        if (v < 0) v += n;
        return std::clamp(v, 0LL, n);
    };
    if (count == 0) throw UsageError("--frames \"" + text + "\": the path has no frames");
    if (text.empty()) return {0, count};
    const auto colon = text.find(':');
    if (colon == std::string::npos) throw UsageError("--frames \"" + text + "\": expected A:B (half-open, like 0:12)");
    const long long a = parseBound(text.substr(0, colon), 0);
    const long long b = parseBound(text.substr(colon + 1), n);
    if (a >= b)
        throw UsageError("--frames \"" + text + "\" selects no frames (the path has " + std::to_string(count) + ")");
    return {std::size_t(a), std::size_t(b)};
}

}  // namespace cubeao
