// Ray queries against the scene's BVH for the traced AO estimator, written once for the GPU bake
// (shaders/bake/ao_traced.comp, through bvh.glsl, which declares the storage buffers) and the C++
// traversal (src/cubeao/bake/bvh.h, which documents the layout and the build). tests/bake/test_bvh.cpp
// checks the two compilations ray by ray, and the C++ one against Embree.
//
// Node and triangle reads go through bvhNode(b, i) and bvhTriangle(b, i): in C++ `b` holds the
// arrays; GLSL cannot pass a buffer to a function, so there `b` is a placeholder and the includer
// (bvh.glsl) defines bvhNode(i) and bvhTriangle(i) over its storage buffers.
#pragma once

#include "glsl_cpp.h"

CUBEAO_KERNEL_BEGIN

// Default shader storage bindings of the node and triangle arrays (bvh.glsl; a shader may choose
// others, gpu_bvh.h binds where it is told).
CUBEAO_CONST int kBvhNodeBuffer = 10;
CUBEAO_CONST int kBvhTriangleBuffer = 11;

// The traversal stack holds this many nodes; buildBvh keeps every leaf at most this deep (root =
// depth 0), which bounds the stack, so no overflow check is needed.
CUBEAO_CONST uint kBvhMaxDepth = 64u;
// Leaves hold at most this many triangles (fewer where the SAH says a split pays).
CUBEAO_CONST uint kBvhMaxLeafSize = 4u;

// "Missed the box": the largest finite float (GLSL does not promise infinities).
CUBEAO_CONST float kBvhMiss = 3.402823466e38f;
// Direction components smaller than this are replaced by ±kBvhTinyDir before inversion: 1/0 = ∞
// would turn (bound − org) · ∞ into NaN when the origin lies on a slab plane. 1/1e-20 = 1e20 keeps
// every slab distance finite for coordinates below 1e18 and still acts as "parallel to the slab".
CUBEAO_CONST float kBvhTinyDir = 1e-20f;
// Robust slab test (Ize, "Robust BVH Ray Traversal", JCGT 2013; pbrt-v4 §6.8.2): the exit distance,
// rounded in three float operations, is pushed out by 1 + 2γ₃ ≈ 1 + 3.6e-7 so rounding never makes
// a ray miss a box that contains its hit. The literal rounds to 1 + 3·2⁻²³ as float.
CUBEAO_CONST float kBvhSlabGrow = 1.00000036f;
// No triangle (bvhTrace's `triangle` on a miss).
CUBEAO_CONST uint kBvhNoTriangle = 0xffffffffu;

// count == 0: interior node, children at leftOrFirst and leftOrFirst + 1 (siblings adjacent, so one
// index serves both). count > 0: leaf with triangles [leftOrFirst, leftOrFirst + count). Root at 0.
// The one exception is the BVH of a scene without triangles: a single node with count == 0 and
// leftOrFirst == 0 (no interior node can point there: the root is nobody's child), which traversal
// treats as empty. std430: 32 bytes.
struct BvhNode {
    vec3 boundsMin;
    uint leftOrFirst;
    vec3 boundsMax;
    uint count;
};

// Vertex 0 and the edges v1 − v0, v2 − v0: what Möller–Trumbore needs, precomputed once. The word
// after v0 is the scene's index of the triangle (triangles are stored in BVH order). std430: 48 bytes.
struct BvhTriangle {
    vec3 v0;
    uint scenePrimitive;
    vec3 e1;
    float pad1;  // 0
    vec3 e2;
    float pad2;  // 0
};

CUBEAO_KERNEL_END

#ifdef __cplusplus
#include <cstddef>

namespace cubeao::kernel {
static_assert(sizeof(BvhNode) == 32 && offsetof(BvhNode, leftOrFirst) == 12 && offsetof(BvhNode, boundsMax) == 16 &&
              offsetof(BvhNode, count) == 28);
static_assert(sizeof(BvhTriangle) == 48 && offsetof(BvhTriangle, scenePrimitive) == 12 &&
              offsetof(BvhTriangle, e1) == 16 && offsetof(BvhTriangle, e2) == 32);

// The arrays a traversal reads (a Bvh's nodes and triangles).
struct BvhArrays {
    const BvhNode* nodes;
    const BvhTriangle* triangles;
};
inline BvhNode bvhNode(const BvhArrays& b, uint i) { return b.nodes[i]; }
inline BvhTriangle bvhTriangle(const BvhArrays& b, uint i) { return b.triangles[i]; }
}  // namespace cubeao::kernel
#else
struct BvhArrays {
    uint unused;  // a placeholder: GLSL has no empty structs, and the arrays are the includer's buffers
};
BvhNode bvhNode(uint i);
BvhTriangle bvhTriangle(uint i);
BvhNode bvhNode(BvhArrays b, uint i) { return bvhNode(i); }
BvhTriangle bvhTriangle(BvhArrays b, uint i) { return bvhTriangle(i); }
#endif

CUBEAO_KERNEL_BEGIN

CUBEAO_FN float bvhSafeInverse1(float d) {
    float tiny = d >= 0.0f ? kBvhTinyDir : -kBvhTinyDir;
    return 1.0f / (abs(d) > kBvhTinyDir ? d : tiny);
}

CUBEAO_FN vec3 bvhSafeInverse(vec3 d) { return vec3(bvhSafeInverse1(d.x), bvhSafeInverse1(d.y), bvhSafeInverse1(d.z)); }

// Entry distance of the ray into the node's box within [tnear, tfar], or kBvhMiss. min and max pick
// the same operand in both languages (the first unless the second is smaller/larger).
CUBEAO_FN float bvhSlabEntry(BvhNode node, vec3 org, vec3 invDir, float tnear, float tfar) {
    vec3 t0 = (node.boundsMin - org) * invDir;
    vec3 t1 = (node.boundsMax - org) * invDir;
    vec3 tlo = min(t0, t1);
    vec3 thi = max(t0, t1);
    float tEnter = max(max(tlo.x, tlo.y), max(tlo.z, tnear));
    float tExit = min(min(min(thi.x, thi.y), thi.z) * kBvhSlabGrow, tfar);
    return tEnter <= tExit ? tEnter : kBvhMiss;
}

// Möller & Trumbore, "Fast, Minimum Storage Ray/Triangle Intersection", JGT 1997, without the
// backface cull: AO is occluded by either side of a surface. det == 0: the ray lies in the plane.
CUBEAO_FN bool bvhTriangleHit(BvhTriangle tri, vec3 org, vec3 dir, float tnear, float tfar, CUBEAO_OUT(float) t) {
    t = tfar;
    vec3 p = cross(dir, tri.e2);
    float det = dot(tri.e1, p);
    if (det == 0.0f) return false;
    float invDet = 1.0f / det;
    vec3 s = org - tri.v0;
    float u = dot(s, p) * invDet;
    if (u < 0.0f || u > 1.0f) return false;
    vec3 q = cross(s, tri.e1);
    float v = dot(dir, q) * invDet;
    if (v < 0.0f || u + v > 1.0f) return false;
    t = dot(tri.e2, q) * invDet;
    return t > tnear && t < tfar;
}

// Stack traversal, nearer child first, the farther one pushed when the ray enters it before the
// closest hit so far (J. Bikker, "How to build a BVH", part 2, 2022). anyHit: stop at the first hit
// (occlusion); the callers pass a constant, so the compiler specialises the loop. Closest hit with
// tnear < t < tfar, t in units of |dir| (as in Embree); `triangle` is the BVH-order index, or
// kBvhNoTriangle. Both sides of a triangle count.
CUBEAO_FN bool bvhTrace(BvhArrays b, vec3 org, vec3 dir, float tnear, float tfar, bool anyHit, CUBEAO_OUT(float) t,
                        CUBEAO_OUT(uint) triangle) {
    t = tfar;
    triangle = kBvhNoTriangle;
    BvhNode root = bvhNode(b, 0u);
    if (root.count == 0u && root.leftOrFirst == 0u) return false;
    vec3 invDir = bvhSafeInverse(dir);
    if (bvhSlabEntry(root, org, invDir, tnear, t) == kBvhMiss) return false;
    uint stack[kBvhMaxDepth];
    uint sp = 0u;
    uint index = 0u;
    for (;;) {
        BvhNode node = bvhNode(b, index);
        uint first = node.leftOrFirst;
        if (node.count > 0u) {
            for (uint i = first; i < first + node.count; ++i) {
                float ti;
                if (bvhTriangleHit(bvhTriangle(b, i), org, dir, tnear, t, ti)) {
                    t = ti;
                    triangle = i;
                    if (anyHit) return true;
                }
            }
            if (sp == 0u) break;
            index = stack[--sp];
            continue;
        }
        uint nearChild = first;
        uint farChild = first + 1u;
        float dNear = bvhSlabEntry(bvhNode(b, nearChild), org, invDir, tnear, t);
        float dFar = bvhSlabEntry(bvhNode(b, farChild), org, invDir, tnear, t);
        if (dFar < dNear) {
            nearChild = first + 1u;
            farChild = first;
            float d = dNear;
            dNear = dFar;
            dFar = d;
        }
        if (dNear == kBvhMiss) {
            if (sp == 0u) break;
            index = stack[--sp];
            continue;
        }
        index = nearChild;
        if (dFar != kBvhMiss) stack[sp++] = farChild;
    }
    return triangle != kBvhNoTriangle;
}

CUBEAO_KERNEL_END
