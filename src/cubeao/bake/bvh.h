// A bounding-volume hierarchy over a Scene, built on the CPU and traversed by the GPU bake
// (shaders/common/bvh.glsl) for the "traced" AO estimator. The layout is flat and std430-shaped so
// the arrays upload as they are (gpu_bvh.h); bvhIntersect/bvhOccluded below are the C++ twin of the
// GLSL traversal (same algorithm, same order of float operations where practical), so the GPU's
// answers can be checked ray by ray here and the twin against Embree (tests/test_bvh.cpp).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "cubeao/scene/scene.h"

namespace cubeao {

// count == 0: interior node, children at leftOrFirst and leftOrFirst + 1 (siblings adjacent, so one
// index serves both). count > 0: leaf with triangles [leftOrFirst, leftOrFirst + count). Root at 0.
// The one exception is the BVH of a scene without triangles: a single node with count == 0 and
// leftOrFirst == 0 (no interior node can point there: the root is nobody's child), which traversal
// treats as empty.
struct BvhNode {
    glm::vec3 boundsMin;
    std::uint32_t leftOrFirst;
    glm::vec3 boundsMax;
    std::uint32_t count;
};
static_assert(sizeof(BvhNode) == 32, "BvhNode mirrors the std430 struct in bvh.glsl");
static_assert(offsetof(BvhNode, leftOrFirst) == 12 && offsetof(BvhNode, boundsMax) == 16 &&
              offsetof(BvhNode, count) == 28);

// Vertex 0 and the edges v1 − v0, v2 − v0: what Möller–Trumbore needs, precomputed once. v0.w holds
// the bits of the scene's triangle index (std::bit_cast; bvh.glsl declares that word a uint, so the
// GPU never reads it as a float); e1.w and e2.w are 0.
struct BvhTriangle {
    glm::vec4 v0, e1, e2;
};
static_assert(sizeof(BvhTriangle) == 48, "BvhTriangle mirrors the std430 struct in bvh.glsl");

// The traversal stack of both twins holds this many nodes; buildBvh keeps every leaf at most this
// deep (root = depth 0), which bounds the stack. Keep in step with BVH_STACK_SIZE in bvh.glsl.
inline constexpr std::uint32_t kBvhMaxDepth = 64;
// Leaves hold at most this many triangles (fewer where the SAH says a split pays).
inline constexpr std::uint32_t kBvhMaxLeafSize = 4;

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
// 1e20 may be missed (axis-parallel rays use 1/1e-20 as the inverse of a zero component, bvh.cpp).
BvhHit bvhIntersect(const Bvh& bvh, glm::vec3 org, glm::vec3 dir, float tnear, float tfar);
// Whether any triangle lies in (tnear, tfar) along the ray; stops at the first one found.
bool bvhOccluded(const Bvh& bvh, glm::vec3 org, glm::vec3 dir, float tnear, float tfar);

// Number of levels below the root of the deepest leaf (0 for a root leaf); at most kBvhMaxDepth.
std::uint32_t bvhDepth(const Bvh& bvh);

}  // namespace cubeao
