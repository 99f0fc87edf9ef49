#version 450 core
// Horizon-based AO (Bavoil, Sainz & Dimitrov 2008) as given in paper 001 §3.5 (eqs. 7–10) and paper 002
// §3.3.4: per screen direction, march outwards and track the highest horizon; each rise of the
// horizon adds W(r)·(sin h − sin h_prev) (002 listing 3.20), starting from the tangent angle t, so a slice adds
// W·(sin h − sin t) in total; AO = 1 − mean over the N_d directions. Angles are elevations above the
// plane perpendicular to the view vector, measured in the slice through the view ray (exact for a
// pinhole camera, not the view-space xy approximation). Differences from 002's implementation: the
// tangent comes from the G-buffer's geometric normal instead of depth differences, and W is the
// project's falloff (none: 1 within R; smooth: (1 − (r/R)²)²) rather than Bavoil's 1 − r²/R², so
// every method and the reference share one definition of R. HBAO weights directions uniformly, not
// by the cosine of the AO integral: it is biased by design.
#include "ssao.glsl"

float estimateAo(vec3 p, vec3 n, float radiusPixels, vec2 jitter, inout uint fetches) {
    vec3 view = normalize(-p);
    vec2 centre = vec2(ssaoPixel) + 0.5;
    float occlusion = 0.0;
    for (int k = 0; k < ssao.directions; ++k) {
        float phi = kTwoPi * (float(k) + jitter.x) / float(ssao.directions);
        vec2 screenDir = vec2(cos(phi), sin(phi));  // pixels, y down
        vec3 towards = vec3(screenDir.x, -screenDir.y, 0.0);
        vec3 dir = normalize(towards - view * dot(towards, view));  // in the slice, ⟂ view
        // Tangent of the surface in the slice, pointing along dir: (u, w) = (n·view, −n·dir) in the
        // (dir, view) frame; its elevation is sin t = w / |(u, w)|.
        vec2 tangent = vec2(dot(n, view), -dot(n, dir));
        float len = length(tangent);
        if (!(len > 1e-6)) continue;
        float sinHorizon = tangent.y / len;  // sin t
        for (int s = 0; s < ssao.steps; ++s) {
            float t = radiusPixels * (float(s) + jitter.y) / float(ssao.steps);
            vec3 q;
            if (!samplePoint(centre + t * screenDir, q, fetches)) continue;
            vec3 v = q - p;
            float dist = length(v);
            if (dist > ssao.radius || !aboveTangentPlane(v, n)) continue;
            float sinElevation = dot(v, view) / dist;
            if (sinElevation > sinHorizon) {
                occlusion += occlusionWeight(ssao.falloff, dist, ssao.radius) * (sinElevation - sinHorizon);
                sinHorizon = sinElevation;
            }
        }
    }
    return 1.0 - occlusion / float(ssao.directions);
}
