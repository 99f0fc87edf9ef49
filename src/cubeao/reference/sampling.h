// Sample directions for AO rays. Written as plain arithmetic on 32-bit integers and floats so a GLSL
// twin can reproduce the same rays bit for bit where it matters (the traced bake of DESIGN.md §4):
// one fixed 2-D low-discrepancy set (Hammersley) per sample count, rotated per pixel or texel by a
// toroidal shift from an integer hash (Cranley–Patterson rotation), mapped to a cosine-weighted
// hemisphere around the normal. Twin: shaders/common/sampling.glsl (tests/test_sampling_gl.cpp).
#pragma once

#include <cmath>
#include <cstdint>

#include <glm/geometric.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

namespace cubeao::sampling {

// Integer hash "lowbias32" (C. Wellons, hash-prospector): full avalanche, cheap on GPUs.
inline std::uint32_t hash32(std::uint32_t x) {
    x ^= x >> 16;
    x *= 0x7feb352du;
    x ^= x >> 15;
    x *= 0x846ca68bu;
    x ^= x >> 16;
    return x;
}

inline std::uint32_t hashKey(std::uint32_t a, std::uint32_t b, std::uint32_t c) {
    return hash32(a ^ hash32(b ^ hash32(c)));
}

// 24 high bits → [0, 1): exactly representable in a float, never rounds up to 1.
inline float toUnitFloat(std::uint32_t bits) { return float(bits >> 8) * (1.0f / 16777216.0f); }

inline float radicalInverse2(std::uint32_t i) {
    i = (i << 16) | (i >> 16);
    i = ((i & 0x55555555u) << 1) | ((i & 0xAAAAAAAAu) >> 1);
    i = ((i & 0x33333333u) << 2) | ((i & 0xCCCCCCCCu) >> 2);
    i = ((i & 0x0F0F0F0Fu) << 4) | ((i & 0xF0F0F0F0u) >> 4);
    i = ((i & 0x00FF00FFu) << 8) | ((i & 0xFF00FF00u) >> 8);
    return toUnitFloat(i);
}

// Point i of the n-point Hammersley set, shifted on the unit torus by the key's hash.
inline glm::vec2 rotatedHammersley(std::uint32_t i, std::uint32_t n, std::uint32_t key) {
    const float sx = toUnitFloat(hash32(key)), sy = toUnitFloat(hash32(key ^ 0x9e3779b9u));
    float u = (float(i) + 0.5f) / float(n) + sx, v = radicalInverse2(i) + sy;
    u -= std::floor(u);
    v -= std::floor(v);
    return {u, v};
}

// Orthonormal basis around unit n (Duff et al., "Building an Orthonormal Basis, Revisited", JCGT 2017).
inline void basis(const glm::vec3& n, glm::vec3& t, glm::vec3& b) {
    const float s = n.z >= 0.0f ? 1.0f : -1.0f;  // as the GLSL twin (copysign would differ at -0)
    const float a = -1.0f / (s + n.z);
    const float c = n.x * n.y * a;
    t = glm::vec3(1.0f + s * n.x * n.x * a, s * c, -s * n.x);
    b = glm::vec3(c, s + n.y * n.y * a, -n.y);
}

// Cosine-weighted direction in the hemisphere around unit n (Malley's method): pdf = cos θ / π,
// so the AO integral of DESIGN.md §4 becomes a plain average of visibility.
inline glm::vec3 cosineHemisphere(const glm::vec2& u, const glm::vec3& n) {
    const float r = std::sqrt(u.x), phi = 6.28318530718f * u.y;
    glm::vec3 t, b;
    basis(n, t, b);
    const float z = std::sqrt(std::fmax(0.0f, 1.0f - u.x));
    return glm::normalize(r * std::cos(phi) * t + r * std::sin(phi) * b + z * n);
}

}  // namespace cubeao::sampling
