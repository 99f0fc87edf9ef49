// A bounding-volume hierarchy over a Scene, built on the CPU and traversed by the GPU bake for the
// "traced" AO estimator. The node and triangle structs, the constants and the traversal are the
// shared kernel shaders/common/bvh.h (compiled as GLSL by shaders/bake/ao_traced.comp through
// shaders/common/bvh.glsl); the layout is flat and std430-shaped so the arrays upload as they are
// (gpu_bvh.h). bvhIntersect/bvhOccluded below run the same kernel on the CPU, so the GPU's answers
// can be checked ray by ray here and the traversal against Embree (tests/bake/test_bvh.cpp).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "common/bvh.h"
#include "cubeao/scene/scene.h"

namespace cubeao {

// count == 0: interior node, children at leftOrFirst and leftOrFirst + 1; count > 0: leaf with
// triangles [leftOrFirst, leftOrFirst + count); root at 0; a root with count == 0 and leftOrFirst ==
// 0 is an empty scene (common/bvh.h).
using BvhNode = kernel::BvhNode;
// Vertex 0, the edges v1 − v0 and v2 − v0, and the scene's triangle index (common/bvh.h).
using BvhTriangle = kernel::BvhTriangle;

// buildBvh keeps every leaf at most this deep (root = depth 0), which bounds the traversal's stack.
inline constexpr std::uint32_t kBvhMaxDepth = kernel::kBvhMaxDepth;
// Leaves hold at most this many triangles (fewer where the SAH says a split pays).
inline constexpr std::uint32_t kBvhMaxLeafSize = kernel::kBvhMaxLeafSize;

struct Bvh {
    std::vector<BvhNode> nodes;          // root first; at most 2 · triangles − 1 (1 when empty)
    std::vector<BvhTriangle> triangles;  // BVH order: each leaf's triangles are contiguous
    std::vector<std::uint32_t> primitive;  // BVH order → the scene's triangle index
};

// Binned SAH build (Wald 2007, "On fast Construction of SAH-based Bounding Volume Hierarchies"):
// 16 bins on the centroid bounds of each node, all three axes. Every triangle of the scene appears
// once. O(n log n); Sibenik's 77k triangles take tens of milliseconds.
Bvh buildBvh(const Scene& scene);

struct BvhHit {
    float t = 0.0f;                // distance along `dir` (in units of its length); valid when hit
    std::uint32_t triangle = ~0u;  // the scene's triangle index
    bool hit = false;
};

// Closest triangle with tnear < t < tfar, both sides of a triangle count (no backface culling).
// `dir` need not be unit length; t is in units of its length, as in Embree. Hits farther than about
// 1e20 may be missed (axis-parallel rays use 1/1e-20 as the inverse of a zero component, common/bvh.h).
BvhHit bvhIntersect(const Bvh& bvh, glm::vec3 org, glm::vec3 dir, float tnear, float tfar);
// Whether any triangle lies in (tnear, tfar) along the ray; stops at the first one found.
bool bvhOccluded(const Bvh& bvh, glm::vec3 org, glm::vec3 dir, float tnear, float tfar);

// Number of levels below the root of the deepest leaf (0 for a root leaf); at most kBvhMaxDepth.
std::uint32_t bvhDepth(const Bvh& bvh);

}  // namespace cubeao
