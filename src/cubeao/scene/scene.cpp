#include "cubeao/scene/scene.h"

#include <xxhash.h>

#include <cinttypes>
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

std::uint64_t geometryHash(const std::vector<glm::vec3>& positions, const std::vector<std::uint32_t>& indices) {
    XXH3_state_t* state = XXH3_createState();
    XXH3_64bits_reset(state);
    XXH3_64bits_update(state, positions.data(), positions.size() * sizeof(glm::vec3));
    XXH3_64bits_update(state, indices.data(), indices.size() * sizeof(std::uint32_t));
    const std::uint64_t h = XXH3_64bits_digest(state);
    XXH3_freeState(state);
    return h;
}

void finalizeScene(Scene& scene) {
    scene.bounds = Bounds{};
    for (const glm::vec3& p : scene.positions) scene.bounds.extend(p);
    scene.hash = geometryHash(scene.positions, scene.indices);
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
