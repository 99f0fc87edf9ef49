// The bake's edge-aware filter of traced AO (DESIGN.md §4 "Bake"), one kernel for the GPU pass
// (shaders/bake/ao_denoise.comp) and the CPU bake (src/cubeao/bake/cpu_bake.cpp).
//
// A traced texel's AO is a Monte Carlo estimate, and the run time shows each texel's own error to the
// viewer: as the image slides, neighbouring texels' independent noise appears as flicker. AO is smooth
// along a surface at texel scale, so the filter fits the AO of a texel's face neighbours that lie on
// the same surface: a cross-bilateral filter guided by the probe's cube G-buffer (normal, distance).
// A neighbour counts with a Gaussian of its surface point's distance from the centre's (σ = radius
// footprints, the footprint being the centre texel's world size, distance · 2 / res; at most R / 4,
// since AO changes over the AO radius R and faster near occluders: a coarse cube must not average
// across them), times a Gaussian of its distance from the centre texel's tangent plane in
// footprints, times its normal's agreement with the centre's, raised to a power. Texels of another
// surface (a crease, a silhouette, a step) get no weight, so edges stay sharp; neighbours on a
// surface seen at a grazing angle lie far apart and get little. Only texels of the same face: no
// seams to cross.
//
// The value is a weighted least-squares plane ao ≈ a + b·u + c·v in the centre's tangent coordinates,
// evaluated at the centre (a), not the weighted mean: where the window is one-sided (beside a crease,
// where AO changes fastest, at a step, a face border) a mean is pulled by the AO's slope, a plane is
// not. A small ridge on the slopes makes the fit fall back to the mean where the neighbours cannot
// tell a slope (few of them, or all in a line). The result is clamped to [0, 1].
#pragma once

#include "cube.h"
#include "glsl_cpp.h"

#ifdef __cplusplus
#define CUBEAO_DENOISE_FN template <class Reader> inline
#define CUBEAO_DENOISE_READER(r) const Reader& r,
#define CUBEAO_DENOISE_READ(r) r.
#else
#define CUBEAO_DENOISE_FN
#define CUBEAO_DENOISE_READER(r)
#define CUBEAO_DENOISE_READ(r)
#endif

CUBEAO_KERNEL_BEGIN

// Texels a side of the window by default (`bake --denoise`): 3 × 3. On both walks (512², 64 rays) the
// plane fit is as good at 1 as at 2 and worse at 3; a weighted mean was best at 1 and worse at 2 and
// 4: wider windows remove more noise and add more bias (BENCHMARKS "The bake's AO filter").
CUBEAO_CONST int kAoDenoiseDefaultRadius = 1;
// σ of the tangent-plane distance, in centre-texel footprints (distance · 2 / res).
CUBEAO_CONST float kAoDenoisePlaneSigma = 1.0f;
// Normal agreement: weight dot(nc, nk)^kAoDenoiseNormalPower (0.5 at 17°, 0.06 at 30°).
CUBEAO_CONST float kAoDenoiseNormalPower = 32.0f;

#ifndef __cplusplus
vec4 denoiseGBuffer(ivec3 texel);  // (normal, distance) of the probe's cube G-buffer; distance 0: empty
float denoiseAo(ivec3 texel);      // the AO before the filter
#endif

// Ridge of the local linear fit's slopes, as a fraction of the summed weight.
CUBEAO_CONST float kAoDenoiseRidge = 0.1f;
// The largest σ of the spatial Gaussian, as a fraction of the AO radius R.
CUBEAO_CONST float kAoDenoiseMaxSigmaOfRadius = 0.25f;

// Weight of neighbour k (surface point pk, normal nk) for the centre texel (surface point pc, normal
// nc, footprint = its world size), with spatial σ `sigma` (world units).
CUBEAO_FN float aoDenoiseWeight(vec3 pc, vec3 nc, float footprint, vec3 pk, vec3 nk, float sigma) {
    float agreement = dot(nc, nk);
    if (!(agreement > 0.0f)) return 0.0f;
    vec3 d = pk - pc;
    float plane = dot(nc, d) / (kAoDenoisePlaneSigma * footprint);
    return exp(-0.5f * (dot(d, d) / (sigma * sigma) + plane * plane)) * pow(agreement, kAoDenoiseNormalPower);
}

// The filtered AO of `texel` (i, j, face) of a res² cube around `probe`: the weighted plane fit over
// its (2 radius + 1)² window, at the centre; an empty texel keeps its AO. aoRadius: the AO radius R.
CUBEAO_DENOISE_FN float aoDenoiseTexel(CUBEAO_DENOISE_READER(reader) ivec3 texel, int res, vec3 probe, int radius,
                                       float aoRadius) {
    vec4 c = CUBEAO_DENOISE_READ(reader) denoiseGBuffer(texel);
    float centreAo = CUBEAO_DENOISE_READ(reader) denoiseAo(texel);
    if (!(c.w > 0.0f) || radius <= 0) return centreAo;
    vec3 nc = vec3(c.x, c.y, c.z);
    vec3 pc = probe + cubeTexelDirection(texel.z, ivec2(texel.x, texel.y), res) * c.w;
    float footprint = c.w * 2.0f / float(res);
    float sigma = min(float(radius) * footprint, kAoDenoiseMaxSigmaOfRadius * aoRadius);
    // Tangent frame of the centre (any orthonormal pair), coordinates in footprints.
    vec3 t0 = normalize(abs(nc.x) < 0.9f ? cross(nc, vec3(1.0f, 0.0f, 0.0f)) : cross(nc, vec3(0.0f, 1.0f, 0.0f)));
    vec3 t1 = cross(nc, t0);
    // Weighted sums of the local linear fit ao ≈ a + b·u + c·v (the centre at u = v = 0, weight 1).
    float sw = 1.0f, su = 0.0f, sv = 0.0f, suu = 0.0f, suv = 0.0f, svv = 0.0f;
    float sa = centreAo, sua = 0.0f, sva = 0.0f;
    for (int dj = -radius; dj <= radius; ++dj) {
        int j = texel.y + dj;
        if (j < 0 || j >= res) continue;
        for (int di = -radius; di <= radius; ++di) {
            int i = texel.x + di;
            if (i < 0 || i >= res || (di == 0 && dj == 0)) continue;
            ivec3 k = ivec3(i, j, texel.z);
            vec4 g = CUBEAO_DENOISE_READ(reader) denoiseGBuffer(k);
            if (!(g.w > 0.0f)) continue;
            vec3 pk = probe + cubeTexelDirection(texel.z, ivec2(i, j), res) * g.w;
            float w = aoDenoiseWeight(pc, nc, footprint, pk, vec3(g.x, g.y, g.z), sigma);
            if (!(w > 0.0f)) continue;
            float a = CUBEAO_DENOISE_READ(reader) denoiseAo(k);
            float u = dot(pk - pc, t0) / footprint, v = dot(pk - pc, t1) / footprint;
            sw += w;
            su += w * u;
            sv += w * v;
            suu += w * u * u;
            suv += w * u * v;
            svv += w * v * v;
            sa += w * a;
            sua += w * u * a;
            sva += w * v * a;
        }
    }
    // Ridge on the slopes: with few or collinear neighbours the fit falls back towards the mean.
    float ridge = kAoDenoiseRidge * sw;
    suu += ridge;
    svv += ridge;
    float det = sw * (suu * svv - suv * suv) - su * (su * svv - suv * sv) + sv * (su * suv - suu * sv);
    float detA = sa * (suu * svv - suv * suv) - su * (sua * svv - suv * sva) + sv * (sua * suv - suu * sva);
    return clamp(detA / det, 0.0f, 1.0f);
}

CUBEAO_KERNEL_END
