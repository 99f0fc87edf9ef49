// AO sample directions: the GLSL twin of src/cubeao/reference/sampling.h (keep the two in step;
// tests/test_sampling_gl.cpp checks that they agree). One fixed Hammersley set per sample count,
// shifted per pixel or texel by an integer hash (Cranley–Patterson rotation), mapped to a
// cosine-weighted hemisphere, so the GPU bake and the Embree twin trace the same rays.
#pragma once

// Integer hash "lowbias32" (C. Wellons, hash-prospector).
uint hash32(uint x) {
    x ^= x >> 16;
    x *= 0x7feb352du;
    x ^= x >> 15;
    x *= 0x846ca68bu;
    x ^= x >> 16;
    return x;
}

uint hashKey(uint a, uint b, uint c) { return hash32(a ^ hash32(b ^ hash32(c))); }

// 24 high bits → [0, 1): exactly representable, never rounds up to 1.
float toUnitFloat(uint bits) { return float(bits >> 8) * (1.0 / 16777216.0); }

float radicalInverse2(uint i) { return toUnitFloat(bitfieldReverse(i)); }

vec2 rotatedHammersley(uint i, uint n, uint key) {
    vec2 shift = vec2(toUnitFloat(hash32(key)), toUnitFloat(hash32(key ^ 0x9e3779b9u)));
    return fract(vec2((float(i) + 0.5) / float(n), radicalInverse2(i)) + shift);
}

// Duff et al., "Building an Orthonormal Basis, Revisited", JCGT 2017.
void orthonormalBasis(vec3 n, out vec3 t, out vec3 b) {
    float s = n.z >= 0.0 ? 1.0 : -1.0;
    float a = -1.0 / (s + n.z);
    float c = n.x * n.y * a;
    t = vec3(1.0 + s * n.x * n.x * a, s * c, -s * n.x);
    b = vec3(c, s + n.y * n.y * a, -n.y);
}

// Malley's method: pdf = cos θ / π, so AO is a plain average of visibility (DESIGN.md §4).
vec3 cosineHemisphere(vec2 u, vec3 n) {
    float r = sqrt(u.x), phi = 6.28318530718 * u.y;
    vec3 t, b;
    orthonormalBasis(n, t, b);
    float z = sqrt(max(0.0, 1.0 - u.x));
    return normalize(r * cos(phi) * t + r * sin(phi) * b + z * n);
}
