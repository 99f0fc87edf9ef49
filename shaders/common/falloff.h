// Occlusion weight of a hit at distance t < radius, shared by the reference (Embree), every bake
// estimator and every screen-space baseline, so one falloff means the same everywhere (DESIGN.md §4).
#pragma once

#include "glsl_cpp.h"

CUBEAO_KERNEL_BEGIN

CUBEAO_CONST int FALLOFF_NONE = 0;    // V_R: weight 1 for any hit closer than R
CUBEAO_CONST int FALLOFF_SMOOTH = 1;  // (1 − (t/R)²)², fading to 0 at R

CUBEAO_FN float occlusionWeight(int falloff, float t, float radius) {
    if (falloff == FALLOFF_NONE) return 1.0f;
    float x = t / radius;
    float w = 1.0f - x * x;
    return w * w;
}

CUBEAO_KERNEL_END
