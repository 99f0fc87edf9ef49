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

// The test's second half (issue 34 item 4, thin walls). The slope-scaled bias widens the test along
// the ray to the probe, through whatever stands there: on a floor seen at a grazing angle it reaches
// tens of centimetres, so a 2 cm wall hid strips of the room behind it (of its floor, ceiling and side
// walls where they meet the wall). So the point is also lifted off its surface along its own normal n
// (turned to the side seen) by `offset` coarse texel widths at its distance (normal offset, Holbert
// 2011), w = 2 / depthRes as above, and the lifted point must not lie behind the surface the probe
// stored in its direction by more than the relative tolerance. A surface that runs into a wall (the
// room behind it) stays behind that wall however far it is lifted, at any level of detail; a surface
// the probe sees comes off it towards the probe. Lifting alone would clear low occluders (a step, a
// moulding) the slope test still sees, so both must pass; a point within the relative tolerance of
// the stored surface needs no lift (measurements in depth_cube.h).
CUBEAO_FN vec3 depthLiftedPoint(vec3 x, vec3 n, float distance, float offset, int depthRes) {
    return x + n * (offset * (2.0f / float(depthRes)) * distance);
}

// The lifted point at `distance` is clear of the surface stored that way (`stored`; an empty texel: of
// nothing).
CUBEAO_FN bool depthLiftedClear(float stored, float distance, float tolerance) {
    return !(stored > 0.0f) || distance <= stored * (1.0f + tolerance);
}

// The whole test for a point at `distance` whose direction holds `stored` (> 0): within the relative
// tolerance it is the stored surface; beyond, up to the slope-scaled bias, only if the point lifted
// off its surface (at `liftedDistance`, its direction holding `lifted`) is clear too (no second half
// when offset is 0). Facing and empty texels are the caller's.
CUBEAO_FN bool depthVisible(float stored, float distance, float cosine, float lifted, float liftedDistance,
                            float tolerance, float slope, float offset, int depthRes) {
    if (distance <= stored * (1.0f + tolerance)) return true;
    return depthWithinBias(stored, distance, cosine, tolerance, slope, depthRes) &&
           (!(offset > 0.0f) || depthLiftedClear(lifted, liftedDistance, tolerance));
}

CUBEAO_KERNEL_END
