#version 450 core
// The GPU coverage count (placement/include/cubeao/placement/gpu_coverage.h, DESIGN.md §4
// "Placement"): per camera pixel with geometry, whether some probe covers its surface point, with the
// CPU count's definition (CoverageFeedback::frameCoverage, placement/src/coverage.cpp probeCovers):
// the shared kernel probeMayCoverPoint (common/coverage.h) and then nothing between the point, moved
// off the surface by surfaceEpsilon along its normal, and the probe (the BVH kernel instead of Embree).
// The point and normal come from the camera G-buffer as in runtime/project.comp.
#include "bvh.glsl"
#include "camera.h"
#include "coverage.h"
#include "placement_layout.h"
#include "runtime_layout.h"

layout(local_size_x = kPixelGroupSize, local_size_y = kPixelGroupSize) in;

layout(binding = kGBufferDepthUnit) uniform sampler2D depthTex;
layout(binding = kGBufferNormalUnit) uniform sampler2D normalTex;

layout(std430, binding = kCoverageProbeBuffer) restrict readonly buffer Probes { vec4 probes[]; };
layout(std430, binding = kCoverageCounterBuffer) restrict buffer Counters { CoverageCounters counters; };

layout(std140, binding = kCoverageBlock) uniform CoverageUniforms { CoverageBlock frame; };

shared uint groupPixels, groupUncovered;

bool covered(vec3 x, vec3 n) {
    vec3 origin = x + n * frame.surfaceEpsilon;
    for (uint i = 0u; i < frame.probeCount; ++i) {
        vec3 probe = probes[i].xyz;
        if (!probeMayCoverPoint(probe, x, n, frame.params)) continue;
        // As probeCovers: a unit direction from the moved origin, the whole way to the probe.
        vec3 toProbe = probe - origin;
        float distance = length(toProbe);
        if (!bvhOccluded(origin, toProbe / distance, 0.0, distance)) return true;
    }
    return false;
}

void main() {
    if (gl_LocalInvocationIndex == 0u) {
        groupPixels = 0u;
        groupUncovered = 0u;
    }
    barrier();
    ivec2 px = ivec2(gl_GlobalInvocationID.xy);
    if (onScreen(px)) {
        float depth = texelFetch(depthTex, px, 0).r;
        if (depth > 0.0) {
            vec3 x = (camera.worldFromView * vec4(viewPosition(px, depth), 1.0)).xyz;
            vec3 n = normalize(mat3(camera.worldFromView) * texelFetch(normalTex, px, 0).xyz);
            atomicAdd(groupPixels, 1u);
            if (!covered(x, n)) atomicAdd(groupUncovered, 1u);
        }
    }
    barrier();
    if (gl_LocalInvocationIndex == 0u) {
        atomicAdd(counters.pixels, groupPixels);
        atomicAdd(counters.uncovered, groupUncovered);
    }
}
