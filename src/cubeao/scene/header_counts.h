// Counts a mesh file's header claims, checked against what the file can hold, before any reader
// allocates for them (issue 15, "counts that lie"). OpenMesh's OFF and PLY readers loop over the
// claimed vertex count and add a vertex per step even after the stream has failed: assimp's 309-byte
// test file invalid/OutOfMemory.off claims 3.5·10¹¹ vertices and grew `cubeao info` past 3 GB. Each
// element needs some bytes in the file (a text vertex at least "0 0 0\n", a binary one its
// properties' sizes), so a claim above size / bytes-per-element is a lie and the file is refused.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>

namespace cubeao {

// What a header claimed; empty when the format has no counts (OBJ, ASCII STL) or they fit.
struct ClaimedCounts {
    std::string element;           // "vertex", "face", "triangle"
    long double claimed = 0;       // what the header says
    long double mostPossible = 0;  // what the file's size allows
    // A PLY header OpenMesh's reader would crash on (found by tests/fuzz/fuzz_mesh.cpp: a "property"
    // line before any "element" line makes _PLYReader_::can_u_read read through an empty list): what
    // is wrong, with its line. Empty when the header is sound.
    std::string malformed;
};

// The first claim of `path` (extension `ext`, lower case, with the dot: .off, .ply, .stl) that its
// size cannot hold; nullopt-like empty `element` when every claim fits or the header has none. A
// header it cannot parse is left to the reader (which reports it); this only catches lies.
ClaimedCounts impossibleHeaderCount(const std::filesystem::path& path, const std::string& ext);

}  // namespace cubeao
