// Binary STL read directly: an 80-byte header, a uint32 triangle count, then 50 bytes a triangle
// (normal, three corners, attribute word). OpenMesh's reader merges corners through a std::map as it
// reads: on a 5-million-triangle soup that map took 77 % of 91 s and most of 1.6 GB (docs/RELIABILITY.md).
// Here every corner is kept as written and repairMesh merges exact duplicates afterwards, which gives
// the same vertices in the same order (first occurrence), the same triangles, and the same hash.
#pragma once

#include <cstdint>
#include <filesystem>
#include <vector>

#include <glm/vec3.hpp>

namespace cubeao {

// Whether `path` is binary STL: its size is exactly 84 + 50 · count (how OpenMesh tells it from ASCII
// STL too, since some binary exporters start the header with "solid").
bool isBinaryStl(const std::filesystem::path& path);

// Appends the file's corners (three per triangle, in file order) and indices 0, 1, 2, ... Facet normals
// are not kept: they are per face, and repair computes vertex normals. Throws cubeao::Error on a read
// error. Call only when isBinaryStl(path).
void readBinaryStl(const std::filesystem::path& path, std::vector<glm::vec3>& positions,
                   std::vector<std::uint32_t>& indices);

}  // namespace cubeao
