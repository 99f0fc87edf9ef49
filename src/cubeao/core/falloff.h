// The AO distance falloff (DESIGN.md §4): the same weight in the reference, every bake estimator and
// every screen-space baseline. The weight itself is the shared kernel shaders/common/falloff.h; this
// is its C++ face (an enum with the kernel's values, and its command-line names).
#pragma once

#include <string>

#include "common/falloff.h"
#include "cubeao/core/error.h"

namespace cubeao {

enum class Falloff {
    None = kernel::FALLOFF_NONE,      // V_R = 1 for any hit closer than R
    Smooth = kernel::FALLOFF_SMOOTH,  // a hit at distance t occludes with weight (1 − (t/R)²)², fading to 0 at R
};

// "none" | "smooth"; UsageError otherwise.
inline Falloff parseFalloff(const std::string& name) {
    if (name == "none") return Falloff::None;
    if (name == "smooth") return Falloff::Smooth;
    throw UsageError("--falloff \"" + name + "\": expected none or smooth");
}

inline const char* falloffName(Falloff f) { return f == Falloff::Smooth ? "smooth" : "none"; }

// Occlusion weight of a hit at distance t < radius.
inline float occlusionWeight(Falloff falloff, float t, float radius) {
    return kernel::occlusionWeight(int(falloff), t, radius);
}

// What a shader's `falloff` uniform takes.
inline int falloffUniform(Falloff f) { return int(f); }

}  // namespace cubeao
