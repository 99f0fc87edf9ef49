#include "cubeao/scene/scene.h"

#include <xxhash.h>

#include <algorithm>
#include <cinttypes>
#include <cmath>
#include <cstdio>

#include <glm/geometric.hpp>
#include <nlohmann/json.hpp>

namespace cubeao {

void Bounds::extend(const glm::vec3& p) {
    min = glm::min(min, p);
    max = glm::max(max, p);
}

float Bounds::diagonal() const { return empty() ? 0.0f : glm::length(max - min); }

nlohmann::json SceneProblems::toJson() const {
    return {{"degenerate_triangles_removed", degenerateTriangles},
            {"duplicate_vertices_merged", duplicateVertices},
            {"unused_vertices_removed", unusedVertices},
            {"normals_computed", normalsComputed},
            {"zero_normals", zeroNormals},
            {"warnings", warnings}};
}

std::uint64_t geometryHash(const std::vector<glm::vec3>& positions, const std::vector<std::uint32_t>& indices,
                           const glm::dvec3& origin) {
    XXH3_state_t* state = XXH3_createState();
    XXH3_64bits_reset(state);
    XXH3_64bits_update(state, positions.data(), positions.size() * sizeof(glm::vec3));
    XXH3_64bits_update(state, indices.data(), indices.size() * sizeof(std::uint32_t));
    if (origin != glm::dvec3(0.0)) {
        const double o[3] = {origin.x, origin.y, origin.z};
        XXH3_64bits_update(state, o, sizeof o);
    }
    const std::uint64_t h = XXH3_64bits_digest(state);
    XXH3_freeState(state);
    return h;
}

void finalizeScene(Scene& scene) {
    scene.bounds = Bounds{};
    for (const glm::vec3& p : scene.positions) scene.bounds.extend(p);
    scene.hash = geometryHash(scene.positions, scene.indices, scene.origin);
}

glm::dvec3 chooseOrigin(const glm::dvec3& min, const glm::dvec3& max) {
    if (!(min.x <= max.x && min.y <= max.y && min.z <= max.z)) return glm::dvec3(0.0);  // empty or NaN
    const glm::dvec3 c = 0.5 * (min + max);
    const double far = std::max({std::fabs(c.x), std::fabs(c.y), std::fabs(c.z)});
    const double diagonal = glm::length(max - min);
    if (!(far > kRecentreDistance && far > kRecentreDiagonals * diagonal)) return glm::dvec3(0.0);
    glm::dvec3 o(0.0);
    for (int i = 0; i < 3; ++i) {
        // Whole units, then to 24 significant bits (the nearest float, ties away from zero) by scaling with
        // a power of two. Not double(float(std::round(x))): in this loop g++ 12.2 -O2's SLP vectoriser drops
        // that float round trip for two of the three components (wrong code, seen in the assembly; fine with
        // -fno-tree-slp-vectorize), so 5500000022 stayed 5500000022 instead of the float 5500000256.
        const double r = std::round(c[i]);
        if (r == 0.0) continue;
        const double step = std::ldexp(1.0, std::max(0, std::ilogb(r) - 23));
        o[i] = std::round(r / step) * step;
    }
    return o;
}

std::size_t computeVertexNormals(const std::vector<glm::vec3>& positions, const std::vector<std::uint32_t>& indices,
                                 std::vector<glm::vec3>& normals, const glm::vec3& fallback) {
    normals.assign(positions.size(), glm::vec3(0.0f));
    for (std::size_t t = 0; t + 2 < indices.size(); t += 3) {
        const std::uint32_t a = indices[t], b = indices[t + 1], c = indices[t + 2];
        const glm::vec3 n = glm::cross(positions[b] - positions[a], positions[c] - positions[a]);
        normals[a] += n;
        normals[b] += n;
        normals[c] += n;
    }
    std::size_t undefined = 0;
    for (glm::vec3& n : normals) {
        const float len = glm::length(n);
        if (len > 0.0f && std::isfinite(len)) {
            n /= len;
        } else {
            n = fallback;
            ++undefined;
        }
    }
    return undefined;
}

std::string hashToString(std::uint64_t hash) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "0x%016" PRIx64, hash);
    return buf;
}

}  // namespace cubeao
