// Weights of the edge-aware AO blur (src/cubeao/runtime/blur.h has the formula's derivation and
// measurements): shaders/runtime/blur.comp and its CPU twin blurAoCpu use these, so they cannot drift.
#pragma once

#include "glsl_cpp.h"

CUBEAO_KERNEL_BEGIN

// Normal term ((n_c·n_s + 1)/2)^k_n (paper 000 eq. 3.2.2) times the relative depth term
// max(0, 1 − |n_c·(p_s − p_c)| / (τ · z_c)) (paper 002 listing 3.16, measured from the centre's
// tangent plane) of tap s for centre c; both must have geometry.
CUBEAO_FN float bilateralWeight(vec3 centreNormal, vec3 centrePoint, float centreDepth, vec3 tapNormal, vec3 tapPoint,
                                float normalPower, float depthTolerance) {
    float normalTerm = pow(max(0.0f, 0.5f * (dot(centreNormal, tapNormal) + 1.0f)), normalPower);
    float planeDistance = abs(dot(centreNormal, tapPoint - centrePoint));
    float depthTerm = max(0.0f, 1.0f - planeDistance / (depthTolerance * centreDepth));
    return normalTerm * depthTerm;
}

// Spatial term of tap i (−radius..radius): a Gaussian with σ = radius/2; 1 for radius 0.
CUBEAO_FN float bilateralSpatialWeight(int tap, int radius) {
    if (radius == 0) return 1.0f;
    float sigma = 0.5f * float(radius);
    return exp(-float(tap * tap) / (2.0f * sigma * sigma));
}

CUBEAO_KERNEL_END
