// The run-time depth test's bias, shared by the projection (projection.h, its pass and CPU twin) and
// the distance cube's C++ test depth::visible (src/cubeao/cache/depth_cube.h, which carries the
// measurements behind the defaults). The probe's distance cube is an omnidirectional shadow map.
#pragma once

#include "glsl_cpp.h"

CUBEAO_KERNEL_BEGIN

// θ ≈ 83°: a steeper incidence would let the slope-scaled bias accept everything behind the surface.
CUBEAO_CONST float kMaxTan = 8.0f;

// The depth test's bias (src/cubeao/cache/depth_cube.h DepthTest, which has the measurements): a
// surface point at `distance` from the probe, whose normal makes cos θ = `cosine` with the way to the
// probe, counts as the surface the probe stored at `stored` when
//   distance ≤ stored · (1 + tolerance + slope · w · min(tan θ, kMaxTan)),  w = 2 / depthRes,
// a relative bias for quantisation and a slope-scaled one (Williams 1978) because one coarse texel
// spans distances D·w·tan θ apart on a surface seen at incidence θ. Facing and empty texels are the
// caller's.
CUBEAO_FN bool depthWithinBias(float stored, float distance, float cosine, float tolerance, float slope, int depthRes) {
    float c = min(abs(cosine), 1.0f), s = sqrt(1.0f - c * c);
    float tanTheta = c * kMaxTan > s ? s / c : kMaxTan;
    return distance <= stored * (1.0f + tolerance + slope * (2.0f / float(depthRes)) * tanTheta);
}

CUBEAO_KERNEL_END
