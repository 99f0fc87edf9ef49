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

struct MarchSample {
    bool occluder;
    bool hidden;
    vec3 v;
    float distance;
};

MarchSample marchSample(HorizonParams hp, vec3 p, vec3 n, vec3 x) {
    MarchSample m = MarchSample(false, false, vec3(0.0), 0.0);
    vec3 d = x - hp.probe;
    vec2 sc;
    int face = cubeFaceOf(d, sc);
    ivec2 t = cubeTexelOf(sc, hp.res);
    vec4 texel = horizonFetch(ivec3(t, face));
    if (!(texel.w > 0.0)) return m;  // sky that way: open, and known
    vec3 q = hp.probe + normalize(cubeFaceDirection(face, cubeTexelCentre(t, hp.res))) * texel.w;
    m.v = q - p;
    m.distance = length(m.v);
    float dx = length(d);
    // Above the tangent plane by more than rounding of positions computed from the probe.
    bool above = dot(m.v, n) > 1e-5 * (length(hp.probe) + dx);
    m.occluder = above && m.distance <= hp.radius && m.distance > 1e-4 * hp.radius;
    float slack = dx * 4.0 / float(hp.res);
    m.hidden = texel.w < dx - slack && above && m.distance > hp.radius;
    return m;
}

float stepDistance(int step, int steps, float jitter, float radius) {
    return radius * (float(step) + jitter) / float(steps);
}

vec2 horizonJitter(uint key) { return vec2(toUnitFloat(hash32(key)), toUnitFloat(hash32(key ^ 0x68e31da4u))); }

// Horizon-split AO, Oswald ch. 4 eq. 4.3: returns (ao, confidence).
vec2 horizonSplitAo(HorizonParams hp, vec3 p, vec3 n, uint key) {
    vec2 jitter = horizonJitter(key);
    vec3 t1, t2;
    orthonormalBasis(n, t1, t2);
    float obscurance = 0.0;
    int hidden = 0;
    for (int k = 0; k < hp.directions; ++k) {
        float phi = 2.0 * kPi * (float(k) + jitter.x) / float(hp.directions);
        vec3 dir = cos(phi) * t1 + sin(phi) * t2;
        float sin2 = 0.0, slice = 0.0;
        for (int s = 0; s < hp.steps; ++s) {
            MarchSample m = marchSample(hp, p, n, p + dir * stepDistance(s, hp.steps, jitter.y, hp.radius));
            hidden += m.hidden ? 1 : 0;
            if (!m.occluder) continue;
            float e = dot(m.v, n) / m.distance, e2 = e * e;
            if (e2 > sin2) {
                slice += (e2 - sin2) * occlusionWeight(hp.falloff, m.distance, hp.radius);
                sin2 = e2;
            }
        }
        obscurance += slice;
    }
    return vec2(1.0 - obscurance / float(hp.directions), 1.0 - float(hidden) / float(hp.directions * hp.steps));
}

// GTAO, Jimenez et al. 2016 (paper 002) eq. 10 with the projected-normal weight; the view vector is
// the direction to the probe. Returns (ao, confidence).
vec2 gtaoAo(HorizonParams hp, vec3 p, vec3 n, uint key) {
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
                MarchSample m = marchSample(hp, p, n, x);
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
