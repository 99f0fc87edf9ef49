#include "cubeao/scene/repair.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <sstream>

#include <glm/geometric.hpp>

#include "cubeao/core/error.h"

namespace cubeao {
namespace {

bool finite(const glm::vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

// Exact (bitwise) vertex identity: a duplicate is a vertex a file wrote twice, not one that happens to
// be close (welding nearby vertices would change the geometry and its hash). The vertices are sorted
// by their bits (position, then normal) rather than hashed: a soup of 5 million triangles has 15 million
// corners, and a hash map of them costs about 1 GB where the sort's order costs 60 MB.
using VertexBits = std::array<std::uint32_t, 6>;

VertexBits vertexBits(const Scene& s, std::uint32_t i) {
    VertexBits b;
    std::memcpy(b.data(), &s.positions[i], sizeof(glm::vec3));
    std::memcpy(b.data() + 3, &s.normals[i], sizeof(glm::vec3));
    return b;
}

// Every vertex maps to the first (lowest-numbered) vertex with the same bits.
void mergeDuplicates(Scene& s) {
    std::vector<std::uint32_t> order(s.positions.size());
    for (std::uint32_t i = 0; i < order.size(); ++i) order[i] = i;
    std::stable_sort(order.begin(), order.end(),
                     [&](std::uint32_t a, std::uint32_t b) { return vertexBits(s, a) < vertexBits(s, b); });
    std::vector<std::uint32_t> remap(s.positions.size());
    for (std::size_t k = 0; k < order.size(); ++k) {
        const bool same = k > 0 && vertexBits(s, order[k - 1]) == vertexBits(s, order[k]);
        remap[order[k]] = same ? remap[order[k - 1]] : order[k];
        if (same) ++s.problems.duplicateVertices;
    }
    for (std::uint32_t& idx : s.indices) idx = remap[idx];
}

void removeDegenerate(Scene& s) {
    std::size_t out = 0;
    for (std::size_t t = 0; t < s.indices.size(); t += 3) {
        const std::uint32_t a = s.indices[t], b = s.indices[t + 1], c = s.indices[t + 2];
        const glm::vec3 n = glm::cross(s.positions[b] - s.positions[a], s.positions[c] - s.positions[a]);
        if (a == b || b == c || a == c || glm::dot(n, n) == 0.0f) {
            ++s.problems.degenerateTriangles;
            continue;
        }
        s.indices[out++] = a;
        s.indices[out++] = b;
        s.indices[out++] = c;
    }
    s.indices.resize(out);
}

void compactVertices(Scene& s) {
    constexpr std::uint32_t kUnused = ~0u;
    std::vector<std::uint32_t> remap(s.positions.size(), kUnused);
    std::vector<glm::vec3> positions, normals;
    positions.reserve(s.positions.size());
    normals.reserve(s.normals.size());
    for (std::uint32_t& idx : s.indices) {
        if (remap[idx] == kUnused) {
            remap[idx] = std::uint32_t(positions.size());
            positions.push_back(s.positions[idx]);
            normals.push_back(s.normals[idx]);
        }
        idx = remap[idx];
    }
    s.problems.unusedVertices += s.positions.size() - positions.size();
    s.positions = std::move(positions);
    s.normals = std::move(normals);
}

// File normals that are zero, NaN or tiny get the area-weighted normal instead; where that is undefined
// too (e.g. a vertex shared by a two-sided pair of faces) the scene's up vector, counted.
void fixNormals(Scene& s, bool hasNormals) {
    std::vector<glm::vec3> computed;
    computeVertexNormals(s.positions, s.indices, computed, glm::vec3(0.0f));
    s.problems.normalsComputed = !hasNormals;
    s.problems.zeroNormals = 0;
    for (std::size_t i = 0; i < s.normals.size(); ++i) {
        const float len = hasNormals ? glm::length(s.normals[i]) : 0.0f;
        if (std::isfinite(len) && len > 1e-6f) {
            s.normals[i] /= len;
        } else if (computed[i] != glm::vec3(0.0f)) {
            s.normals[i] = computed[i];
        } else {
            s.normals[i] = s.up;
            ++s.problems.zeroNormals;
        }
    }
}

}  // namespace

void validateMesh(const Scene& s) {
    std::vector<std::string> problems;
    if (s.indices.empty()) problems.push_back("it contains no triangles");
    if (s.indices.size() % 3 != 0) problems.push_back("index count " + std::to_string(s.indices.size()) +
                                                      " is not a multiple of 3");
    std::size_t badPos = 0, firstBadPos = 0;
    for (std::size_t i = 0; i < s.positions.size(); ++i)
        if (!finite(s.positions[i]) && badPos++ == 0) firstBadPos = i;
    if (badPos) problems.push_back(std::to_string(badPos) + " vertices have NaN/Inf coordinates (first: vertex " +
                                   std::to_string(firstBadPos) + ")");
    std::size_t badIdx = 0, firstBadIdx = 0;
    for (std::size_t i = 0; i < s.indices.size(); ++i)
        if (s.indices[i] >= s.positions.size() && badIdx++ == 0) firstBadIdx = i;
    if (badIdx) problems.push_back(std::to_string(badIdx) + " indices are out of range (first: triangle " +
                                   std::to_string(firstBadIdx / 3) + " refers to vertex " +
                                   std::to_string(s.indices[firstBadIdx]) + " of " +
                                   std::to_string(s.positions.size()) + ")");
    if (!s.normals.empty() && s.normals.size() != s.positions.size())
        problems.push_back(std::to_string(s.normals.size()) + " normals for " + std::to_string(s.positions.size()) +
                           " vertices");
    if (problems.empty()) return;
    std::ostringstream msg;
    msg << s.source << ": unusable mesh: ";
    for (std::size_t i = 0; i < problems.size(); ++i) msg << (i ? "; " : "") << problems[i];
    throw Error(msg.str());
}

void repairMesh(Scene& s, bool hasNormals) {
    if (!hasNormals || s.normals.size() != s.positions.size()) {
        hasNormals = false;
        s.normals.assign(s.positions.size(), glm::vec3(0.0f));
    }
    mergeDuplicates(s);
    removeDegenerate(s);
    compactVertices(s);
    fixNormals(s, hasNormals);
    finalizeScene(s);
}

WindingCheck checkWinding(const Scene& s) {
    // Position ids: vertices at the same position (split only by their normals) are one corner.
    std::vector<std::uint32_t> order(s.positions.size());
    for (std::uint32_t i = 0; i < order.size(); ++i) order[i] = i;
    auto less = [&](std::uint32_t a, std::uint32_t b) {
        const glm::vec3 &p = s.positions[a], &q = s.positions[b];
        return p.x != q.x ? p.x < q.x : p.y != q.y ? p.y < q.y : p.z < q.z;
    };
    std::sort(order.begin(), order.end(), less);
    std::vector<std::uint32_t> id(s.positions.size());
    std::uint32_t next = 0;
    for (std::size_t k = 0; k < order.size(); ++k) {
        if (k > 0 && less(order[k - 1], order[k])) ++next;
        id[order[k]] = next;
    }
    // Each directed edge as (low id, high id, direction bit) in one 64-bit word; equal words after the
    // sort are one undirected edge, and the direction bits of a pair say whether it is run both ways.
    std::vector<std::uint64_t> edges;
    edges.reserve(s.indices.size());
    for (std::size_t t = 0; t + 2 < s.indices.size(); t += 3)
        for (int k = 0; k < 3; ++k) {
            const std::uint64_t a = id[s.indices[t + k]], b = id[s.indices[t + (k + 1) % 3]];
            if (a == b) continue;
            edges.push_back((std::min(a, b) << 33) | (std::max(a, b) << 1) | (a < b ? 0u : 1u));
        }
    std::sort(edges.begin(), edges.end());
    WindingCheck w;
    for (std::size_t i = 0; i < edges.size();) {
        std::size_t j = i;
        while (j < edges.size() && (edges[j] >> 1) == (edges[i] >> 1)) ++j;
        if (j - i == 2) {
            ++w.sharedEdges;
            if ((edges[i] & 1u) == (edges[i + 1] & 1u)) ++w.flippedEdges;
        }
        i = j;
    }
    return w;
}

void prepareScene(Scene& s, bool hasNormals) {
    validateMesh(s);
    repairMesh(s, hasNormals);
    if (s.indices.empty())
        throw Error(s.source + ": unusable mesh: all " + std::to_string(s.problems.degenerateTriangles) +
                    " triangles have zero area");
}

}  // namespace cubeao
