// Scene: one triangle mesh in flat arrays, as every later stage (Embree, GL upload, placement)
// wants it. Imported files are validated and repaired on load (import.h, repair.h).
#pragma once

#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include <glm/vec3.hpp>
#include <glm/ext/vector_double3.hpp>
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
    // Georeferenced models (IFC, surveys) sit 10^5..10^6 units from the file's origin, where a float has
    // 8..60 mm steps. Such a scene is re-centred on import (chooseOrigin): `origin` is the point of the
    // file's coordinates that local (0, 0, 0) stands for, and everything in memory (positions, bounds,
    // probes, camera eyes, the .cubeao table) is local = file - origin. Whatever leaves or enters the
    // program (camera paths, probes.json, the cache header) is in file coordinates. 0 for every scene
    // near its file's origin, whose positions and hash are then exactly what they were before.
    glm::dvec3 origin{0.0};
    std::vector<glm::vec3> positions;    // local: the file's own units, minus `origin`
    std::vector<glm::vec3> normals;      // per vertex, unit length; same size as positions
    std::vector<std::uint32_t> indices;  // three per triangle, counter-clockwise
    Bounds bounds;
    glm::vec3 up{0.0f, 1.0f, 0.0f};
    std::uint64_t hash = 0;              // geometryHash() of positions and indices
    SceneProblems problems;

    std::size_t triangleCount() const { return indices.size() / 3; }
    bool recentred() const { return origin != glm::dvec3(0.0); }
    // File coordinates <-> local, the subtraction in double (exact when `p` is near the origin).
    glm::vec3 toLocal(const glm::dvec3& file) const { return glm::vec3(file - origin); }
    glm::dvec3 toFile(const glm::vec3& local) const { return glm::dvec3(local) + origin; }
    std::size_t vertexCount() const { return positions.size(); }
    // DESIGN.md §4: the AO radius defaults to 2 % of the bounding-box diagonal.
    float defaultRadius() const { return 0.02f * bounds.diagonal(); }
};

// 64-bit xxHash (XXH3) over the position bytes, then the index bytes, then, only when it is not zero,
// the origin's three doubles (a model and its copy moved by a whole number of units have the same
// local positions, but not the same place: a cache baked for one must not pass for the other).
// Identifies the geometry a probe cache was baked for, so it must not depend on normals, file name or
// load order of anything else.
std::uint64_t geometryHash(const std::vector<glm::vec3>& positions, const std::vector<std::uint32_t>& indices,
                           const glm::dvec3& origin = glm::dvec3(0.0));

// The origin a model with file-coordinate bounds [min, max] is re-centred on: zero, unless the bounds'
// centre c is both beyond kRecentreDistance and farther than kRecentreDiagonals diagonals from the file's
// origin (only then does re-centring gain precision worth a different hash: a 100 m building 20 km out
// has 2 mm float steps, one at 100 km 8 mm). Then c rounded to whole units and to the nearest float, so
// the offset is exact in float and double and local coordinates are exact differences of nearby numbers.
inline constexpr double kRecentreDistance = 16384.0;  // 2^14: float steps of 1/512 unit (2 mm in metres)
inline constexpr double kRecentreDiagonals = 4.0;
glm::dvec3 chooseOrigin(const glm::dvec3& min, const glm::dvec3& max);

// Recomputes bounds and hash from the arrays (call after any change to positions/indices).
void finalizeScene(Scene& scene);

// Area-weighted vertex normals (the cross product's length is twice the area, so summing raw cross
// products weights by area). Returns the number of vertices left without a defined normal.
std::size_t computeVertexNormals(const std::vector<glm::vec3>& positions, const std::vector<std::uint32_t>& indices,
                                 std::vector<glm::vec3>& normals, const glm::vec3& fallback);

// "0x" followed by 16 hex digits.
std::string hashToString(std::uint64_t hash);

}  // namespace cubeao
