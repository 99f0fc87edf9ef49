// Scene: one triangle mesh in flat arrays, as every later stage (Embree, GL upload, placement)
// wants it. Imported files are validated and repaired on load (import.h, repair.h).
#pragma once

#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include <glm/vec3.hpp>
#include <nlohmann/json_fwd.hpp>

namespace cubeao {

struct Bounds {
    glm::vec3 min{std::numeric_limits<float>::max()};
    glm::vec3 max{std::numeric_limits<float>::lowest()};

    void extend(const glm::vec3& p);
    bool empty() const { return min.x > max.x; }
    float diagonal() const;
    glm::vec3 center() const { return 0.5f * (min + max); }
};

// What load/repair found and fixed; reported by `cubeao info` as "problems".
struct SceneProblems {
    std::size_t degenerateTriangles = 0;  // zero-area triangles removed
    std::size_t duplicateVertices = 0;    // vertices merged into an identical one (position and normal)
    std::size_t unusedVertices = 0;       // vertices no triangle references, dropped
    bool normalsComputed = false;         // the file had no normals: area-weighted vertex normals computed
    std::size_t zeroNormals = 0;          // vertices whose normal stays undefined (replaced by up)
    std::vector<std::string> warnings;    // importer messages worth showing (e.g. assimp's IFC warnings)

    nlohmann::json toJson() const;
};

struct Scene {
    std::string source;                  // file path or "builtin:NAME"
    std::vector<glm::vec3> positions;    // world space, the file's own units
    std::vector<glm::vec3> normals;      // per vertex, unit length; same size as positions
    std::vector<std::uint32_t> indices;  // three per triangle, counter-clockwise
    Bounds bounds;
    glm::vec3 up{0.0f, 1.0f, 0.0f};
    std::uint64_t hash = 0;              // geometryHash() of positions and indices
    SceneProblems problems;

    std::size_t triangleCount() const { return indices.size() / 3; }
    std::size_t vertexCount() const { return positions.size(); }
    // DESIGN.md §4: the AO radius defaults to 2 % of the bounding-box diagonal.
    float defaultRadius() const { return 0.02f * bounds.diagonal(); }
};

// 64-bit xxHash (XXH3) over the position bytes, then the index bytes. Identifies the geometry a
// probe cache was baked for, so it must not depend on normals, file name or load order of anything else.
std::uint64_t geometryHash(const std::vector<glm::vec3>& positions, const std::vector<std::uint32_t>& indices);

// Recomputes bounds and hash from the arrays (call after any change to positions/indices).
void finalizeScene(Scene& scene);

// Area-weighted vertex normals (the cross product's length is twice the area, so summing raw cross
// products weights by area). Returns the number of vertices left without a defined normal.
std::size_t computeVertexNormals(const std::vector<glm::vec3>& positions, const std::vector<std::uint32_t>& indices,
                                 std::vector<glm::vec3>& normals, const glm::vec3& fallback);

// "0x" followed by 16 hex digits.
std::string hashToString(std::uint64_t hash);

}  // namespace cubeao
