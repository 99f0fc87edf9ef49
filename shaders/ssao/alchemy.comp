#version 450 core
// Alchemy ambient obscurance (McGuire et al. 2011), paper 000 eq. 2.2.6:
//   A = max(0, 1 − (2σ/N) Σ_i max(0, v_i·n + z_C β) / (v_i·v_i + ε))^k
// v_i from the shaded point to the surface seen at sample i, z_C the shaded point's view-space z
// (negative: the bias lowers occlusion with depth), N samples on a spiral over the disk of radius R
// projected to screen, rotated per pixel (paper 000 §2.2.3.1, McGuire et al. 2012). Project changes,
// so one setting fits every scene and the result is comparable with the reference:
//  - each term is multiplied by R and ε is given in units of R² (paper 000's σ carries a length unit);
//  - samples farther than R from the shaded point do not count (V_R) and count with the project's
//    falloff weight; the spiral is area-uniform (radius ∝ √α) so the sum estimates an area integral.
#include "ssao.glsl"

// ssao.intensity = σ, ssao.contrast = k, ssao.bias = β, ssao.epsilon = ε / R² (SsaoBlock).

const float kGoldenAngle = 2.39996322972865332;  // π(3 − √5): a Vogel spiral covers the disk evenly

float estimateAo(vec3 p, vec3 n, float radiusPixels, vec2 jitter, inout uint fetches) {
    vec2 centre = vec2(ssaoPixel) + 0.5;
    int samples = ssao.directions * ssao.steps;
    float eps = ssao.epsilon * ssao.radius * ssao.radius;
    float sum = 0.0;
    for (int i = 0; i < samples; ++i) {
        float alpha = (float(i) + jitter.y) / float(samples);
        float angle = float(i) * kGoldenAngle + kTwoPi * jitter.x;
        vec3 q;
        if (!samplePoint(centre + radiusPixels * sqrt(alpha) * vec2(cos(angle), sin(angle)), q, fetches)) continue;
        vec3 v = q - p;
        float vv = dot(v, v);
        if (vv > ssao.radius * ssao.radius) continue;
        sum += occlusionWeight(ssao.falloff, sqrt(vv), ssao.radius) * ssao.radius *
               max(0.0, dot(v, n) + p.z * ssao.bias) / (vv + eps);
    }
    return pow(max(0.0, 1.0 - 2.0 * ssao.intensity / float(samples) * sum), ssao.contrast);
}
