// The world area one probe texel covers on a surface: the quality by which the projection ranks
// probes (projection.h) and placement's "small enough" (coverage.h). A header of its own so that
// coverage.h need not bring the projection's candidate loop (and the reads it asks its includer for).
#pragma once

#include "glsl_cpp.h"

CUBEAO_KERNEL_BEGIN

// World area of the probe texel at face point sc on a surface at `distance` seen at cos θ = facing > 0:
// solid angle (2/res)² / (1 + u² + v²)^{3/2} times distance² / max(cos θ, minFacing).
CUBEAO_FN float probeTexelArea(vec2 sc, float distance, float facing, int res, float minFacing) {
    float r2 = 1.0f + dot(sc, sc), texel = 2.0f / float(res);
    return texel * texel / (r2 * sqrt(r2)) * distance * distance / max(facing, minFacing);
}

CUBEAO_KERNEL_END
