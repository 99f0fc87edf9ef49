// AO sample directions and per-texel hashing, for the GPU bake, the Embree reference and the
// screen-space baselines alike. Plain arithmetic on 32-bit integers and floats, so the GPU and the
// CPU trace the same rays: one fixed 2-D Hammersley set per sample count, shifted per pixel or texel
// by an integer hash (Cranley–Patterson rotation), mapped to a cosine-weighted hemisphere around the
// normal. tests/core/test_sampling_gl.cpp runs this header on the GPU against its C++ compilation.
#pragma once

#include "constants.h"
#include "glsl_cpp.h"

CUBEAO_KERNEL_BEGIN

// Integer hash "lowbias32" (C. Wellons, hash-prospector): full avalanche, cheap on GPUs.
CUBEAO_FN uint hash32(uint x) {
    x ^= x >> 16;
    x *= 0x7feb352du;
    x ^= x >> 15;
    x *= 0x846ca68bu;
    x ^= x >> 16;
    return x;
}

CUBEAO_FN uint hashKey(uint a, uint b, uint c) { return hash32(a ^ hash32(b ^ hash32(c))); }

// The bake's key of texel (i, j, face) of a res² cube, for probeKey = probe index ^ seed: it rotates
// the texel's sample set and its horizon march (texelKey in src/cubeao/bake/bake_settings.h).
CUBEAO_FN uint cubeTexelKey(ivec3 texel, int res, uint probeKey) {
    return hashKey(uint(texel.x), uint(texel.z * res + texel.y), probeKey);
}

// 24 high bits → [0, 1): exactly representable in a float, never rounds up to 1.
CUBEAO_FN float toUnitFloat(uint bits) { return float(bits >> 8) * (1.0f / 16777216.0f); }

CUBEAO_FN float radicalInverse2(uint i) { return toUnitFloat(bitfieldReverse(i)); }

// Two independent values in [0, 1) for a pixel or texel key: the rotation of a march's azimuths (x)
// and the offset of its steps (y), for the bake's horizon estimators and the screen-space baselines.
CUBEAO_FN vec2 marchJitter(uint key) {
    return vec2(toUnitFloat(hash32(key)), toUnitFloat(hash32(key ^ 0x68e31da4u)));
}

// Point i of the n-point Hammersley set, shifted on the unit torus by the key's hash.
CUBEAO_FN vec2 rotatedHammersley(uint i, uint n, uint key) {
    vec2 shift = vec2(toUnitFloat(hash32(key)), toUnitFloat(hash32(key ^ 0x9e3779b9u)));
    return fract(vec2((float(i) + 0.5f) / float(n), radicalInverse2(i)) + shift);
}

// Orthonormal basis around unit n (Duff et al., "Building an Orthonormal Basis, Revisited", JCGT
// 2017). The sign is a comparison, not copysign, which would differ at −0.
CUBEAO_FN void orthonormalBasis(vec3 n, CUBEAO_OUT(vec3) t, CUBEAO_OUT(vec3) b) {
    float s = n.z >= 0.0f ? 1.0f : -1.0f;
    float a = -1.0f / (s + n.z);
    float c = n.x * n.y * a;
    t = vec3(1.0f + s * n.x * n.x * a, s * c, -s * n.x);
    b = vec3(c, s + n.y * n.y * a, -n.y);
}

// Cosine-weighted direction in the hemisphere around unit n (Malley's method): pdf = cos θ / π, so
// the AO integral of DESIGN.md §4 becomes a plain average of visibility.
CUBEAO_FN vec3 cosineHemisphere(vec2 u, vec3 n) {
    float r = sqrt(u.x);
    float phi = kTwoPi * u.y;
    vec3 t;
    vec3 b;
    orthonormalBasis(n, t, b);
    float z = sqrt(max(0.0f, 1.0f - u.x));
    return normalize(r * cos(phi) * t + r * sin(phi) * b + z * n);
}

CUBEAO_KERNEL_END
