// The GTAO slice integral and its normalisation, for every GTAO in the project: the screen-space
// baseline (shaders/ssao/gtao.comp) and the bake's estimator on a probe's cube G-buffer
// (shaders/common/horizon.h, whose C++ compilation src/cubeao/bake/horizon.cpp wraps). The marches
// that find the horizons differ (screen pixels vs cube-map lookups); what is done with them is here.
//
// GTAO (Jimenez et al. 2016, as given in paper 002 §3.3.5): N_d/2 slices around the view vector, two
// horizons per slice, the cosine-weighted slice integral in closed form (002 eq. 3.23) over the normal
// projected onto the slice (002 fig. 3.26, Timonen), weighted by its length.
// One change to the paper: the sum over slices is divided by the same sum for an unoccluded
// hemisphere (a ratio estimator). The unoccluded slice integral |n_p|·(cos γ + γ sin γ) averages to
// 1 only over many slices: with 4 slices an open floor seen at a grazing angle came out as low as
// 0.955 in screen space, and the bake's 8 slices read up to 1.3 % low on open planes. The ratio is 1
// on any open surface (to float rounding) and converges to the same value as the slice count grows;
// on the cloister (8 frames vs the Embree reference) it lowered the screen-space MAE from 0.034 to 0.027.
#pragma once

#include "constants.h"
#include "glsl_cpp.h"

CUBEAO_KERNEL_BEGIN

// One slice: the plane through the view vector and a direction dir ⟂ view.
struct GtaoSlice {
    float weight;    // |n_p|, the projected normal's length; 0: n ⟂ the slice plane, the slice carries no weight
    float gamma;     // signed angle of n_p from the view vector, positive towards dir (002 listing 3.23)
    float cosGamma;  // cos γ
};

// The slice through view and dir (both unit, dir ⟂ view) for the unit normal n.
CUBEAO_FN GtaoSlice gtaoSlice(vec3 n, vec3 view, vec3 dir) {
    vec3 axis = cross(dir, view);
    vec3 projected = n - axis * dot(n, axis);
    float projectedLength = length(projected);
    if (!(projectedLength > 1e-6f)) return GtaoSlice(0.0f, 0.0f, 1.0f);
    float cosGamma = clamp(dot(projected, view) / projectedLength, -1.0f, 1.0f);
    float gamma = (dot(projected, dir) >= 0.0f ? 1.0f : -1.0f) * acos(cosGamma);
    return GtaoSlice(projectedLength, gamma, cosGamma);
}

// cos of the horizon angle (from the view vector) on side ±1 when nothing occludes: the tangent
// plane's. A march starts its horizon here.
CUBEAO_FN float gtaoTangentCos(GtaoSlice slice, float side) { return cos(slice.gamma + side * 0.5f * kPi); }

// The horizon raised by an occluder whose direction makes cos c with the view vector, at falloff
// weight w ∈ [0, 1] (1: the occluder's own angle; 0: no rise), from the tangent's cos `low`.
CUBEAO_FN float gtaoRaisedCos(float horizonCos, float low, float c, float w) {
    return max(horizonCos, low + (c - low) * w);
}

// ∫_0^h cos(θ − γ)|sin θ| dθ for the horizon angle h (signed like γ): 002 eq. 3.23, one side.
CUBEAO_FN float gtaoSliceArc(float h, float gamma, float cosGamma) {
    return 0.25f * (cosGamma + 2.0f * h * sin(gamma) - cos(2.0f * h - gamma));
}

// The arc on side ±1 up to the horizon whose cos (from the view vector) is horizonCos, the angle
// clamped to the normal's hemisphere (paper 002 §4).
CUBEAO_FN float gtaoSideArc(GtaoSlice slice, float side, float horizonCos) {
    float h = side * acos(clamp(horizonCos, -1.0f, 1.0f));
    h = slice.gamma + clamp(h - slice.gamma, -0.5f * kPi, 0.5f * kPi);
    return gtaoSliceArc(h, slice.gamma, slice.cosGamma);
}

// Adds a slice's two arcs (arcs = the sum of gtaoSideArc over both sides) to the ratio estimator's
// sums: x = Σ |n_p| · arcs, y = the same for the open hemisphere (both sides at the tangent).
CUBEAO_FN void gtaoAddSlice(GtaoSlice slice, float arcs, CUBEAO_INOUT(vec2) sums) {
    float open = gtaoSliceArc(slice.gamma - 0.5f * kPi, slice.gamma, slice.cosGamma) +
                 gtaoSliceArc(slice.gamma + 0.5f * kPi, slice.gamma, slice.cosGamma);
    sums += slice.weight * vec2(arcs, open);
}

// Visibility from the sums: the ratio estimator (1 when no slice carried weight). Each arc is at
// most its open arc (the horizon is clamped to the hemisphere), so the ratio leaves [0, 1] only by
// rounding, which the clamp removes.
CUBEAO_FN float gtaoVisibility(vec2 sums) { return sums.y > 0.0f ? clamp(sums.x / sums.y, 0.0f, 1.0f) : 1.0f; }

CUBEAO_KERNEL_END
