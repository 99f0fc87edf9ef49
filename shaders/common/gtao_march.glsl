// The screen-space GTAO estimator (Jimenez et al. 2016 as given in paper 002 §3.3.5), estimateAo for
// ssao_pixel.glsl: the march along N_d/2 screen directions is here; the slice integral and its
// normalisation (a ratio estimator: an open surface reads 1) are gtao.h, shared with the bake's GTAO.
// The slice through a screen direction contains the view ray exactly (square pixels), so the
// samples along it lie in the slice up to texel rounding. Two shaders include it: the baseline
// (shaders/ssao/gtao.comp, every pixel) and the fallback for pixels no probe sees
// (shaders/ssao/gtao_fill.comp).
#pragma once

#include "gtao.h"
#include "ssao_pixel.glsl"

float estimateAo(vec3 p, vec3 n, float radiusPixels, vec2 jitter, inout uint fetches) {
    vec3 view = normalize(-p);
    vec2 centre = vec2(ssaoPixel) + 0.5;
    int slices = ssao.directions / 2;
    vec2 sums = vec2(0.0);  // gtaoAddSlice's (visible, open)
    for (int k = 0; k < slices; ++k) {
        float phi = kPi * (float(k) + jitter.x) / float(slices);
        vec2 screenDir = vec2(cos(phi), sin(phi));  // pixels, y down
        vec3 towards = vec3(screenDir.x, -screenDir.y, 0.0);
        vec3 dir = normalize(towards - view * dot(towards, view));  // in the slice, ⟂ view
        GtaoSlice slice = gtaoSlice(n, view, dir);
        if (!(slice.weight > 0.0)) continue;
        float arcs = 0.0;
        for (int side = -1; side <= 1; side += 2) {
            float low = gtaoTangentCos(slice, float(side));  // the tangent: no occlusion
            float horizonCos = low;
            for (int s = 0; s < ssao.steps; ++s) {
                float t = radiusPixels * (float(s) + jitter.y) / float(ssao.steps);
                vec3 q;
                if (!samplePoint(centre + float(side) * t * screenDir, q, fetches)) continue;
                vec3 v = q - p;
                float dist = length(v);
                if (dist > ssao.radius || !aboveTangentPlane(v, n)) continue;
                float c = dot(v, view) / dist;  // 002 listing 3.22
                horizonCos = gtaoRaisedCos(horizonCos, low, c, occlusionWeight(ssao.falloff, dist, ssao.radius));
            }
            arcs += gtaoSideArc(slice, float(side), horizonCos);
        }
        gtaoAddSlice(slice, arcs, sums);
    }
    return gtaoVisibility(sums);
}
