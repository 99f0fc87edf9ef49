// Occlusion weight of a hit at distance t < radius: the twin of occlusionWeight() in
// src/cubeao/reference/ao_reference.cpp. falloff 0 = none (V_R), 1 = smooth (1 − (t/R)²)².
#pragma once

#define FALLOFF_NONE 0
#define FALLOFF_SMOOTH 1

float occlusionWeight(int falloff, float t, float radius) {
    if (falloff == FALLOFF_NONE) return 1.0;
    float x = t / radius, w = 1.0 - x * x;
    return w * w;
}
