// Horizon estimators on a probe's cube G-buffer, per texel (DESIGN.md §4 "Bake"), written once for
// the GPU pass (shaders/bake/ao_horizon.comp) and the CPU bake (src/cubeao/bake/horizon.h, which
// documents the estimators; tests/bake/test_bake_gl.cpp runs both compilations on the same G-buffer).
//
// The G-buffer lookup: horizonFetch(hp, texel) returns (normal, distance) of texel (i, j, face),
// distance 0 = empty. In GLSL the including shader defines `vec4 horizonFetch(ivec3 texel)` (reading
// its sampler2DArray; before or after the #include); in C++ it reads HorizonParams::texels.
#pragma once

#include "constants.h"
#include "cube.h"
#include "falloff.h"
#include "glsl_cpp.h"
#include "gtao.h"
#include "sampling.h"

#ifdef __cplusplus
#include <cstddef>
#endif

CUBEAO_KERNEL_BEGIN

// What a horizon estimator needs besides the texel: the probe's G-buffer and the bake settings.
// Built from uniforms in the shader; never GPU-visible as a struct.
struct HorizonParams {
    vec3 probe;
    int res;
    float radius;
    int directions;
    int steps;
    int falloff;  // FALLOFF_NONE | FALLOFF_SMOOTH (falloff.h)
#ifdef __cplusplus
    const vec4* texels;  // the G-buffer in cubeTexelIndex order (C++ only: the shader reads a sampler)
#endif
};

#ifdef __cplusplus
inline vec4 horizonFetch(const HorizonParams& hp, ivec3 texel) {
    // cubeTexelIndex's order, widened: a six-face array at 16K² passes 2³².
    return hp.texels[(std::size_t(texel.z) * std::size_t(hp.res) + std::size_t(texel.y)) * std::size_t(hp.res) +
                     std::size_t(texel.x)];
}
#else
vec4 horizonFetch(ivec3 texel);  // the including shader's
vec4 horizonFetch(HorizonParams hp, ivec3 texel) { return horizonFetch(texel); }
#endif

// Bisection steps for the height field's top above a march point: its height to R/32 at most.
CUBEAO_CONST int kHorizonBisections = 4;

// What the probe knows about a point y (src/cubeao/bake/horizon.h), judged from the texel at (p, n).
CUBEAO_CONST int HORIZON_OPEN = 0;
CUBEAO_CONST int HORIZON_SOLID = 1;
CUBEAO_CONST int HORIZON_UNKNOWN = 2;

// One G-buffer lookup in the direction of y: the surface q the probe sees there, as evidence about y.
struct HorizonLookup {
    int seen;        // HORIZON_OPEN | HORIZON_SOLID | HORIZON_UNKNOWN
    bool occluder;   // q lies within R of p and above its tangent plane
    bool hidden;     // GTAO's confidence rule (src/cubeao/bake/horizon.h)
    vec3 v;          // q − p
    float distance;  // |q − p|
};

CUBEAO_FN HorizonLookup horizonLook(HorizonParams hp, vec3 p, vec3 n, vec3 y) {
    HorizonLookup m = HorizonLookup(HORIZON_OPEN, false, false, vec3(0.0f), 0.0f);
    vec3 d = y - hp.probe;
    vec2 sc;
    int face = cubeFaceOf(d, sc);
    ivec2 t = cubeTexelOf(sc, hp.res);
    vec4 texel = horizonFetch(hp, ivec3(t.x, t.y, face));
    if (!(texel.w > 0.0f)) return m;  // the probe sees sky that way: open, and known
    vec3 q = hp.probe + normalize(cubeFaceDirection(face, cubeTexelCentre(t, hp.res))) * texel.w;
    m.v = q - p;
    m.distance = length(m.v);
    float dy = length(d);
    // q above p's tangent plane by more than float rounding can fake: q and p are world positions
    // computed from the probe, so their error grows with the coordinates. (On a plane q comes out
    // ±1 ulp off it; with a strict > 0, GTAO took such q for occluders, and as a texel centre lies off
    // the slice its angle to the view is not the plane's: AO 0.81 on an open plane.)
    bool above = dot(m.v, n) > 1e-5f * (length(hp.probe) + dy);
    // 1e-4 R: q is p's own texel; its offset from p is sub-texel noise, not an occluder.
    m.occluder = above && m.distance <= hp.radius && m.distance > 1e-4f * hp.radius;
    // Two texel footprints of slack: the texel centre seen in y's direction is not y itself.
    bool behind = texel.w < dy - dy * 4.0f / float(hp.res);
    // A surface at or below the tangent plane hides only more of the half-space below it (the probe
    // is above the plane), where nothing occludes p: y is as good as open.
    m.hidden = behind && above && m.distance > hp.radius;
    // y is inside or behind q; q belongs to p's surroundings when it lies within R of p or of y.
    vec3 w = q - y;
    if (behind && above)
        m.seen = m.distance <= hp.radius || dot(w, w) <= hp.radius * hp.radius ? HORIZON_SOLID : HORIZON_UNKNOWN;
    return m;
}

CUBEAO_FN float horizonStepDistance(int step, int steps, float jitter, float radius) {
    return radius * (float(step) + jitter) / float(steps);
}


// A slice's running horizon: sin² h, tan h and the falloff-weighted sum of its rises.
struct HorizonState {
    float sin2;
    float tanH;
    float slice;
};

CUBEAO_FN HorizonState raisedHorizon(HorizonState h, HorizonParams hp, float e2, float dist) {
    if (!(e2 > h.sin2)) return h;
    return HorizonState(e2, sqrt(e2 / max(1.0f - e2, 1e-12f)),
                        h.slice + (e2 - h.sin2) * occlusionWeight(hp.falloff, dist, hp.radius));
}

// Looks y up, lets an occluder it reveals raise the horizon, returns what is known about y. Every
// surface point the probe shows within R, above the plane and inside this slice's wedge of azimuths
// (cos of its half-angle: cosWedge) is an occluder of the slice in its own right (at small R, where
// texels are coarse, it is most of the evidence). Outside the wedge it belongs to another slice.
CUBEAO_FN int horizonSeen(HorizonParams hp, vec3 p, vec3 n, vec3 dir, float cosWedge, vec3 y,
                          CUBEAO_INOUT(HorizonState) h, CUBEAO_INOUT(uint) fetches) {
    ++fetches;
    HorizonLookup m = horizonLook(hp, p, n, y);
    vec3 level = m.v - n * dot(m.v, n);
    if (m.occluder && dot(level, dir) >= cosWedge * length(level)) {
        float e = dot(m.v, n) / m.distance;
        h = raisedHorizon(h, hp, e * e, m.distance);
    }
    return m.seen;
}

// Horizon-split AO, Oswald ch. 4 eq. 4.3, over the height field found above each march point
// (src/cubeao/bake/horizon.h): returns (ao, confidence); fetches counts the G-buffer lookups.
CUBEAO_FN vec2 horizonSplitAo(HorizonParams hp, vec3 p, vec3 n, uint key, CUBEAO_INOUT(uint) fetches) {
    vec2 jitter = marchJitter(key);
    vec3 t1;
    vec3 t2;
    orthonormalBasis(n, t1, t2);
    float obscurance = 0.0f;
    int doubtful = 0;
    float cosWedge = cos(kPi / float(hp.directions));
    for (int k = 0; k < hp.directions; ++k) {
        float phi = 2.0f * kPi * (float(k) + jitter.x) / float(hp.directions);
        vec3 dir = cos(phi) * t1 + sin(phi) * t2;
        HorizonState h = HorizonState(0.0f, 0.0f, 0.0f);
        for (int s = 0; s < hp.steps; ++s) {
            float r = horizonStepDistance(s, hp.steps, jitter.y, hp.radius);
            vec3 x = p + dir * r;
            float top = sqrt(max(0.0f, hp.radius * hp.radius - r * r));  // the R-ball above x
            float lo = r * h.tanH;  // height of the current horizon above x: only more can raise it
            if (lo >= top) continue;
            int atLo = horizonSeen(hp, p, n, dir, cosWedge, x + n * lo, h, fetches);
            if (atLo != HORIZON_SOLID) {
                // Free at the horizon but solid above it: an overhang, which no height field describes.
                doubtful += atLo == HORIZON_UNKNOWN || horizonSeen(hp, p, n, dir, cosWedge, x + n * top, h, fetches) == HORIZON_SOLID ? 1 : 0;
                continue;
            }
            float hi = top;
            if (horizonSeen(hp, p, n, dir, cosWedge, x + n * top, h, fetches) != HORIZON_SOLID) {
                for (int i = 0; i < kHorizonBisections; ++i) {
                    float mid = 0.5f * (lo + hi);
                    if (horizonSeen(hp, p, n, dir, cosWedge, x + n * mid, h, fetches) == HORIZON_SOLID)
                        lo = mid;
                    else
                        hi = mid;
                }
                hi = 0.5f * (lo + hi);
            }
            h = raisedHorizon(h, hp, hi * hi / (r * r + hi * hi), sqrt(r * r + hi * hi));  // the height field's top
        }
        obscurance += h.slice;  // = max sin² h without a falloff (Oswald eq. 4.3)
    }
    return vec2(1.0f - obscurance / float(hp.directions), 1.0f - float(doubtful) / float(hp.directions * hp.steps));
}

// GTAO (gtao.h) with the direction to the probe as the view vector: N_d/2 slices, two horizons per
// slice. Returns (ao, confidence); fetches counts the G-buffer lookups.
CUBEAO_FN vec2 gtaoAo(HorizonParams hp, vec3 p, vec3 n, uint key, CUBEAO_INOUT(uint) fetches) {
    fetches += uint(hp.directions * hp.steps);
    vec2 jitter = marchJitter(key);
    vec3 view = normalize(hp.probe - p);
    vec3 a1;
    vec3 a2;
    orthonormalBasis(view, a1, a2);
    int slices = hp.directions / 2;
    vec2 sums = vec2(0.0f);
    int hidden = 0;
    for (int k = 0; k < slices; ++k) {
        float phi = kPi * (float(k) + jitter.x) / float(slices);
        vec3 dir = cos(phi) * a1 + sin(phi) * a2;  // ⟂ view: the slice's "screen" direction
        GtaoSlice slice = gtaoSlice(n, view, dir);
        if (!(slice.weight > 0.0f)) continue;  // normal ⟂ slice plane: the slice carries no weight
        float arcs = 0.0f;
        for (int side = -1; side <= 1; side += 2) {
            float low = gtaoTangentCos(slice, float(side));
            float horizonCos = low;
            for (int s = 0; s < hp.steps; ++s) {
                vec3 x = p + float(side) * dir * horizonStepDistance(s, hp.steps, jitter.y, hp.radius);
                HorizonLookup m = horizonLook(hp, p, n, x);
                hidden += m.hidden ? 1 : 0;
                if (!m.occluder) continue;
                float c = dot(m.v, view) / m.distance;
                horizonCos = gtaoRaisedCos(horizonCos, low, c, occlusionWeight(hp.falloff, m.distance, hp.radius));
            }
            arcs += gtaoSideArc(slice, float(side), horizonCos);
        }
        gtaoAddSlice(slice, arcs, sums);
    }
    return vec2(gtaoVisibility(sums), 1.0f - float(hidden) / float(hp.directions * hp.steps));
}

CUBEAO_KERNEL_END
