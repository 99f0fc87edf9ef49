// Ray queries against the scene's BVH for the traced AO estimator: the GLSL twin of the traversal in
// src/cubeao/bake/bvh.cpp (keep the two in step; tests/test_bvh.cpp checks them ray by ray, and the
// C++ twin against Embree). The BVH is built on the CPU (binned SAH) and uploaded as two std430
// arrays by cubeao::GpuBvh; the layout is documented in bvh.h.
//
// Include-only. Before including, a shader may #define BVH_NODE_BINDING and BVH_TRIANGLE_BINDING
// (shader storage binding points; defaults 10 and 11) and bind GpuBvh there.
#pragma once

#ifndef BVH_NODE_BINDING
#define BVH_NODE_BINDING 10
#endif
#ifndef BVH_TRIANGLE_BINDING
#define BVH_TRIANGLE_BINDING 11
#endif
// Traversal stack entries; buildBvh keeps every leaf at most kBvhMaxDepth (64) levels deep, which
// bounds the stack (bvh.h), so no overflow check is needed.
#define BVH_STACK_SIZE 64

// count == 0: interior, children at leftOrFirst and leftOrFirst + 1; count > 0: leaf with triangles
// [leftOrFirst, leftOrFirst + count). A root with count == 0 and leftOrFirst == 0 is an empty scene.
struct BvhNode {
    vec3 boundsMin;
    uint leftOrFirst;
    vec3 boundsMax;
    uint count;
};

// Vertex 0 and the two edges from it (48 bytes, the C++ struct's three vec4s). The fourth word of
// v0 is the scene's triangle index, declared uint so that no GPU ever treats its bits as a float
// (small integers are float denormals).
struct BvhTriangle {
    vec3 v0;
    uint scenePrimitive;
    vec3 e1;
    float pad1;
    vec3 e2;
    float pad2;
};

layout(std430, binding = BVH_NODE_BINDING) restrict readonly buffer BvhNodes { BvhNode bvhNodes[]; };
layout(std430, binding = BVH_TRIANGLE_BINDING) restrict readonly buffer BvhTriangles { BvhTriangle bvhTriangles[]; };

// "Missed the box": the largest finite float (GLSL does not promise infinities).
const float kBvhMiss = 3.402823466e38;
// Direction components smaller than this become ±kBvhTinyDir before inversion, so that a ray
// parallel to a slab whose origin lies on its plane gets a finite (bound − org) · 1e20, not 0 · ∞ = NaN.
const float kBvhTinyDir = 1e-20;
// Robust slab test (Ize, "Robust BVH Ray Traversal", JCGT 2013; pbrt-v4 §6.8.2): the exit distance is
// pushed out by 1 + 2γ₃ so that rounding never makes a ray miss a box that contains its hit.
const float kBvhSlabGrow = 1.00000036;

vec3 bvhSafeInverse(vec3 d) {
    vec3 tiny = mix(vec3(-kBvhTinyDir), vec3(kBvhTinyDir), greaterThanEqual(d, vec3(0.0)));
    return 1.0 / mix(tiny, d, greaterThan(abs(d), vec3(kBvhTinyDir)));
}

// Entry distance of the ray into the node's box within [tnear, tfar], or kBvhMiss.
float bvhSlabEntry(uint node, vec3 org, vec3 invDir, float tnear, float tfar) {
    vec3 t0 = (bvhNodes[node].boundsMin - org) * invDir;
    vec3 t1 = (bvhNodes[node].boundsMax - org) * invDir;
    vec3 tlo = min(t0, t1), thi = max(t0, t1);
    float tEnter = max(max(tlo.x, tlo.y), max(tlo.z, tnear));
    float tExit = min(min(min(thi.x, thi.y), thi.z) * kBvhSlabGrow, tfar);
    return tEnter <= tExit ? tEnter : kBvhMiss;
}

// Möller & Trumbore, "Fast, Minimum Storage Ray/Triangle Intersection", JGT 1997, without the
// backface cull: AO is occluded by either side of a surface. det == 0: the ray lies in the plane.
bool bvhTriangleHit(uint i, vec3 org, vec3 dir, float tnear, float tfar, out float t) {
    t = tfar;
    vec3 e1 = bvhTriangles[i].e1, e2 = bvhTriangles[i].e2;
    vec3 p = cross(dir, e2);
    float det = dot(e1, p);
    if (det == 0.0) return false;
    float invDet = 1.0 / det;
    vec3 s = org - bvhTriangles[i].v0;
    float u = dot(s, p) * invDet;
    if (u < 0.0 || u > 1.0) return false;
    vec3 q = cross(s, e1);
    float v = dot(dir, q) * invDet;
    if (v < 0.0 || u + v > 1.0) return false;
    t = dot(e2, q) * invDet;
    return t > tnear && t < tfar;
}

// Stack traversal, nearer child first, the farther one pushed when the ray enters it before the
// closest hit so far (J. Bikker, "How to build a BVH", part 2, 2022). anyHit: stop at the first hit
// (occlusion); the callers pass a constant, so the compiler specialises the loop.
bool bvhTrace(vec3 org, vec3 dir, float tnear, float tfar, bool anyHit, out float t, out uint triangle) {
    t = tfar;
    triangle = 0xffffffffu;
    if (bvhNodes[0].count == 0u && bvhNodes[0].leftOrFirst == 0u) return false;
    vec3 invDir = bvhSafeInverse(dir);
    if (bvhSlabEntry(0u, org, invDir, tnear, t) == kBvhMiss) return false;
    uint stack[BVH_STACK_SIZE];
    uint sp = 0u, index = 0u;
    for (;;) {
        uint count = bvhNodes[index].count, first = bvhNodes[index].leftOrFirst;
        if (count > 0u) {
            for (uint i = first; i < first + count; ++i) {
                float ti;
                if (bvhTriangleHit(i, org, dir, tnear, t, ti)) {
                    t = ti;
                    triangle = i;
                    if (anyHit) return true;
                }
            }
            if (sp == 0u) break;
            index = stack[--sp];
            continue;
        }
        uint nearChild = first, farChild = first + 1u;
        float dNear = bvhSlabEntry(nearChild, org, invDir, tnear, t);
        float dFar = bvhSlabEntry(farChild, org, invDir, tnear, t);
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
    return triangle != 0xffffffffu;
}

// Closest hit with tnear < t < tfar; `triangle` is the index in BVH order (bvhTriangles), not the
// scene's: bvhScenePrimitive maps it. t is in units of |dir|, as in Embree. Both sides count.
bool bvhIntersect(vec3 org, vec3 dir, float tnear, float tfar, out float t, out uint triangle) {
    return bvhTrace(org, dir, tnear, tfar, false, t, triangle);
}

// Whether anything lies in (tnear, tfar) along the ray; stops at the first hit found.
bool bvhOccluded(vec3 org, vec3 dir, float tnear, float tfar) {
    float t;
    uint triangle;
    return bvhTrace(org, dir, tnear, tfar, true, t, triangle);
}

// The scene's index of the triangle at BVH position `triangle` (what bvhIntersect returns).
uint bvhScenePrimitive(uint triangle) { return bvhTriangles[triangle].scenePrimitive; }
