// Placement's coverage test (placement/include/cubeao/placement/coverage.h, DESIGN.md §4 "Placement"),
// once for the CPU count (placement/src/coverage.cpp) and the GPU count
// (shaders/placement/coverage_count.comp): whether a probe may cover a surface point, i.e. the point
// is in range, its seen side faces the probe, and the probe texel that sees it spans at most maxArea
// on the surface: the projection's own texel area (texel_area.h probeTexelArea). The visibility ray
// is the caller's (Embree on the CPU, the BVH kernel on the GPU).
#pragma once

#include "cube.h"
#include "glsl_cpp.h"
#include "texel_area.h"

CUBEAO_KERNEL_BEGIN

struct CoverageParams {
    float maxArea;      // largest texel area on the surface (world units²)
    float maxDistance;  // beyond it no texel is small enough (CoverageCriterion::maxDistance)
    float minFacing;    // as the projection's
    int res;            // probe face size
};

// x: surface point, n: unit normal of the side seen (turned to the viewer).
CUBEAO_FN bool probeMayCoverPoint(vec3 probe, vec3 x, vec3 n, CoverageParams p) {
    vec3 d = x - probe;
    float distance = length(d);
    if (!(distance > 0.0f) || distance > p.maxDistance) return false;
    float facing = -dot(n, d) / distance;
    if (!(facing > 0.0f)) return false;
    vec2 sc;
    cubeFaceOf(d, sc);
    return probeTexelArea(sc, distance, facing, p.res, p.minFacing) <= p.maxArea;
}

CUBEAO_KERNEL_END
