// Sample directions for AO rays in C++: the shared kernel (shaders/common/sampling.h) in the
// sampling:: names the reference, the CPU bake and the tests use. One fixed Hammersley set per sample
// count, rotated per pixel or texel by an integer hash, mapped to a cosine-weighted hemisphere, so
// the GPU bake and the Embree twin trace the same rays (tests/core/test_sampling_gl.cpp).
#pragma once

#include <cstdint>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "common/sampling.h"

namespace cubeao::sampling {

using kernel::hash32;
using kernel::hashKey;
using kernel::radicalInverse2;
using kernel::rotatedHammersley;
using kernel::toUnitFloat;

inline void basis(const glm::vec3& n, glm::vec3& t, glm::vec3& b) { kernel::orthonormalBasis(n, t, b); }

inline glm::vec3 cosineHemisphere(const glm::vec2& u, const glm::vec3& n) { return kernel::cosineHemisphere(u, n); }

}  // namespace cubeao::sampling
