// The BVH's storage buffers for a shader that traces rays (shaders/bake/ao_traced.comp): the kernel
// is bvh.h, shared with the C++ traversal (src/cubeao/bake/bvh.h); this file only declares the two
// std430 arrays cubeao::GpuBvh uploads and the reads bvh.h asks its includer for.
//
// Include-only. Before including, a shader may #define BVH_NODE_BINDING and BVH_TRIANGLE_BINDING
// (shader storage binding points; defaults kBvhNodeBuffer and kBvhTriangleBuffer of bvh.h) and bind
// GpuBvh there.
#pragma once

#include "bvh.h"

#ifndef BVH_NODE_BINDING
#define BVH_NODE_BINDING kBvhNodeBuffer
#endif
#ifndef BVH_TRIANGLE_BINDING
#define BVH_TRIANGLE_BINDING kBvhTriangleBuffer
#endif

layout(std430, binding = BVH_NODE_BINDING) restrict readonly buffer BvhNodes { BvhNode bvhNodes[]; };
layout(std430, binding = BVH_TRIANGLE_BINDING) restrict readonly buffer BvhTriangles { BvhTriangle bvhTriangles[]; };

BvhNode bvhNode(uint i) { return bvhNodes[i]; }
BvhTriangle bvhTriangle(uint i) { return bvhTriangles[i]; }

// Closest hit with tnear < t < tfar; `triangle` is the index in BVH order (bvhTriangles), not the
// scene's: bvhScenePrimitive maps it. t is in units of |dir|, as in Embree. Both sides count.
bool bvhIntersect(vec3 org, vec3 dir, float tnear, float tfar, out float t, out uint triangle) {
    return bvhTrace(BvhArrays(0u), org, dir, tnear, tfar, false, t, triangle);
}

// Whether anything lies in (tnear, tfar) along the ray; stops at the first hit found.
bool bvhOccluded(vec3 org, vec3 dir, float tnear, float tfar) {
    float t;
    uint triangle;
    return bvhTrace(BvhArrays(0u), org, dir, tnear, tfar, true, t, triangle);
}

// The scene's index of the triangle at BVH position `triangle` (what bvhIntersect returns).
uint bvhScenePrimitive(uint triangle) { return bvhTriangles[triangle].scenePrimitive; }
