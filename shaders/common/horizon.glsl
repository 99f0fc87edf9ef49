// Horizon estimators on a probe's cube G-buffer: the GLSL twin of src/cubeao/bake/horizon.cpp (read
// its header for the definitions; keep the two in step line for line, tests/test_bake_gl.cpp checks
// them on the same G-buffer). The including shader defines, before this header:
//   vec4 horizonFetch(ivec3 texel)   // (normal, distance) of texel (i, j, face); distance 0 = empty
#pragma once

#include "constants.glsl"
#include "cube.glsl"
#include "falloff.glsl"
#include "sampling.glsl"

struct HorizonParams {
    vec3 probe;
    int res;
    float radius;
    int directions;
    int steps;
    int falloff;
};

// Bisection steps for the height field's top above a march point (its height to R/32 at most).
const int kBisections = 4;
const int SEEN_OPEN = 0, SEEN_SOLID = 1, SEEN_UNKNOWN = 2;

// One G-buffer lookup in the direction of y: the surface q the probe sees there, as evidence about y.
struct Lookup {
    int seen;
    bool occluder;
    bool hidden;
    vec3 v;
    float distance;
};

Lookup look(HorizonParams hp, vec3 p, vec3 n, vec3 y) {
    Lookup m = Lookup(SEEN_OPEN, false, false, vec3(0.0), 0.0);
    vec3 d = y - hp.probe;
    vec2 sc;
    int face = cubeFaceOf(d, sc);
    ivec2 t = cubeTexelOf(sc, hp.res);
    vec4 texel = horizonFetch(ivec3(t, face));
    if (!(texel.w > 0.0)) return m;  // sky that way: open, and known
    vec3 q = hp.probe + normalize(cubeFaceDirection(face, cubeTexelCentre(t, hp.res))) * texel.w;
    m.v = q - p;
    m.distance = length(m.v);
    float dy = length(d);
    bool above = dot(m.v, n) > 1e-5 * (length(hp.probe) + dy);  // by more than rounding
    m.occluder = above && m.distance <= hp.radius && m.distance > 1e-4 * hp.radius;
    bool behind = texel.w < dy - dy * 4.0 / float(hp.res);
    m.hidden = behind && above && m.distance > hp.radius;
    vec3 w = q - y;
    if (behind && above)
        m.seen = m.distance <= hp.radius || dot(w, w) <= hp.radius * hp.radius ? SEEN_SOLID : SEEN_UNKNOWN;
    return m;
}

float stepDistance(int step, int steps, float jitter, float radius) {
    return radius * (float(step) + jitter) / float(steps);
}

vec2 horizonJitter(uint key) { return vec2(toUnitFloat(hash32(key)), toUnitFloat(hash32(key ^ 0x68e31da4u))); }

// A slice's running horizon: sin² h, tan h and the falloff-weighted sum of its rises.
struct Horizon {
    float sin2;
    float tanH;
    float slice;
};

Horizon raisedHorizon(Horizon h, HorizonParams hp, float e2, float dist) {
    if (!(e2 > h.sin2)) return h;
    return Horizon(e2, sqrt(e2 / max(1.0 - e2, 1e-12)), h.slice + (e2 - h.sin2) * occlusionWeight(hp.falloff, dist, hp.radius));
}

// Looks y up, lets an occluder it reveals raise the horizon, returns what is known about y.
// Only occluders inside the slice's wedge of azimuths (cos of its half-angle: cosWedge) count.
int seen(HorizonParams hp, vec3 p, vec3 n, vec3 dir, float cosWedge, vec3 y, inout Horizon h, inout uint fetches) {
    ++fetches;
    Lookup m = look(hp, p, n, y);
    vec3 level = m.v - n * dot(m.v, n);
    if (m.occluder && dot(level, dir) >= cosWedge * length(level)) {
        float e = dot(m.v, n) / m.distance;
        h = raisedHorizon(h, hp, e * e, m.distance);
    }
    return m.seen;
}

// Horizon-split AO, Oswald ch. 4 eq. 4.3, over the height field found above each march point
// (src/cubeao/bake/horizon.h): returns (ao, confidence).
vec2 horizonSplitAo(HorizonParams hp, vec3 p, vec3 n, uint key, inout uint fetches) {
    vec2 jitter = horizonJitter(key);
    vec3 t1, t2;
    orthonormalBasis(n, t1, t2);
    float obscurance = 0.0;
    int doubtful = 0;
    float cosWedge = cos(kPi / float(hp.directions));
    for (int k = 0; k < hp.directions; ++k) {
        float phi = 2.0 * kPi * (float(k) + jitter.x) / float(hp.directions);
        vec3 dir = cos(phi) * t1 + sin(phi) * t2;
        Horizon h = Horizon(0.0, 0.0, 0.0);
        for (int s = 0; s < hp.steps; ++s) {
            float r = stepDistance(s, hp.steps, jitter.y, hp.radius);
            vec3 x = p + dir * r;
            float top = sqrt(max(0.0, hp.radius * hp.radius - r * r));
            float lo = r * h.tanH;
            if (lo >= top) continue;
            int atLo = seen(hp, p, n, dir, cosWedge, x + n * lo, h, fetches);
            if (atLo != SEEN_SOLID) {
                doubtful += atLo == SEEN_UNKNOWN || seen(hp, p, n, dir, cosWedge, x + n * top, h, fetches) == SEEN_SOLID ? 1 : 0;
                continue;
            }
            float hi = top;
            if (seen(hp, p, n, dir, cosWedge, x + n * top, h, fetches) != SEEN_SOLID) {
                for (int i = 0; i < kBisections; ++i) {
                    float mid = 0.5 * (lo + hi);
                    if (seen(hp, p, n, dir, cosWedge, x + n * mid, h, fetches) == SEEN_SOLID)
                        lo = mid;
                    else
                        hi = mid;
                }
                hi = 0.5 * (lo + hi);
            }
            h = raisedHorizon(h, hp, hi * hi / (r * r + hi * hi), sqrt(r * r + hi * hi));
        }
        obscurance += h.slice;
    }
    return vec2(1.0 - obscurance / float(hp.directions), 1.0 - float(doubtful) / float(hp.directions * hp.steps));
}

// GTAO, Jimenez et al. 2016 (paper 002) eq. 10 with the projected-normal weight; the view vector is
// the direction to the probe. Returns (ao, confidence).
vec2 gtaoAo(HorizonParams hp, vec3 p, vec3 n, uint key, inout uint fetches) {
    fetches += uint(hp.directions * hp.steps);
    vec2 jitter = horizonJitter(key);
    vec3 view = normalize(hp.probe - p);
    vec3 a1, a2;
    orthonormalBasis(view, a1, a2);
    int slices = hp.directions / 2;
    float visibility = 0.0;
    int hidden = 0;
    for (int k = 0; k < slices; ++k) {
        float phi = kPi * (float(k) + jitter.x) / float(slices);
        vec3 dir = cos(phi) * a1 + sin(phi) * a2;
        vec3 axis = cross(dir, view);
        vec3 projected = n - axis * dot(n, axis);
        float projectedLength = length(projected);
        if (!(projectedLength > 1e-6)) continue;
        float cosN = clamp(dot(projected, view) / projectedLength, -1.0, 1.0);
        float angleN = (dot(projected, dir) >= 0.0 ? 1.0 : -1.0) * acos(cosN);
        float arcs = 0.0;
        for (int side = -1; side <= 1; side += 2) {
            float low = cos(angleN + float(side) * 0.5 * kPi);
            float horizonCos = low;
            for (int s = 0; s < hp.steps; ++s) {
                vec3 x = p + float(side) * dir * stepDistance(s, hp.steps, jitter.y, hp.radius);
                Lookup m = look(hp, p, n, x);
                hidden += m.hidden ? 1 : 0;
                if (!m.occluder) continue;
                float c = dot(m.v, view) / m.distance;
                float w = occlusionWeight(hp.falloff, m.distance, hp.radius);
                horizonCos = max(horizonCos, low + (c - low) * w);
            }
            float h = float(side) * acos(clamp(horizonCos, -1.0, 1.0));
            h = angleN + clamp(h - angleN, -0.5 * kPi, 0.5 * kPi);
            arcs += (cosN + 2.0 * h * sin(angleN) - cos(2.0 * h - angleN)) * 0.25;
        }
        visibility += projectedLength * arcs;
    }
    float ao = clamp(visibility / float(slices), 0.0, 1.0);
    return vec2(ao, 1.0 - float(hidden) / float(hp.directions * hp.steps));
}
