// The error placement minimises (DESIGN.md §4 "Placement", issue 31): the AO error the projection is
// expected to show at a surface sample served by a given probe, so that the greedy optimises the
// picture rather than a 0/1 threshold.
//
// The projection ranks the probes that pass its depth test at a point (placement's "serve",
// coverage.h servedSamples) by the area one of their texels spans there
// (shaders/common/texel_area.h probeTexelArea: distance, off-centre and incidence in one number) and
// blends the best two; the AO it reads is the texel's, taken at the texel's own surface point and
// filtered over its neighbours. Where nothing lies within R the AO is 1 whatever the texel (a probe and
// GTAO both get it right); near an occluder AO changes over about the occluder's distance. So, with
// o = 1 − AO at the sample and L the mean distance of what occludes it (placement traces both with
// Embree), s = sqrt(texel area):
//     expected(s, o, L) = min(fallback(o), o · (occluded + slope · s / L)),
//     fallback(o)       = screen · o      (a sample no probe sees: the screen-space fallback's error).
// occluded carries what no texel size removes (the bake's and the reference's ray noise, the blend of
// two probes, the depth test at silhouettes), slope the error per texel side over the AO's own scale.
//
// Calibration (tools/calibrate_error.sh, tools/fit_error_model.py; table in docs/BENCHMARKS.md
// "Placement by predicted error", 2026-12-04): 24 probe sets (the walk's eyes and voting, 6, 12 and 24
// probes) baked traced at 128² and 512² with 64 rays, both shared walks rendered at 320×180 and
// compared with a 512-ray reference; occluded and slope minimise the relative squared miss of the
// predicted walk MAE (the prediction is linear in them): rms 22 %, worst 34 %, and the misses are by
// walk: Sibenik's MAE is under-predicted (×0.66–0.93), FZK-Haus's over (×1.08–1.22), so something
// per building is still missing (the reference's own noise is 0.0039 against 0.0026 RMS). screen =
// GTAO's walk MAE over the walks' mean occlusion.
// Tried and not kept: a constant floor (it and the occlusion term cannot be told apart with two walks;
// the fit makes it negative), and the texel side over R instead of over L (worst 46 %: the texel term
// is 1.8× steeper on Sibenik than on FZK-Haus measured against R, and the same against L).
// Ranking probe sets of equal count (2026-12-07, placement/calibration/: 103 + 102 measured 6-probe
// sets, each term refitted per walk, correlation with the measured MAE over FZK-Haus's 70 sets that
// serve nearly everything): the model's two terms 0.73 (0.60 with the constants below); the depth
// test in "serve" 0.78 (0.75 with the constants below; kept: it is what the projection does, and it
// gains on both walks); tried and not kept, each beside o · s / L:
// parallax (1 − cos of the angle between the probe's ray to the sample and the walk's mean ray to it)
// 0.76 with a *negative* weight, the probe's distance over the walk's 0.80 (weight negative again,
// doubling the texel term's), the best two probes blended as the projection blends them 0.63, the
// texel term as (s / L)^p for p = 0.25–1.5 0.36–0.61 (p = 1 best).
#pragma once

#include <algorithm>
#include <cmath>

namespace cubeao::placement {

struct ErrorModel {
    float occluded = 0.0357f;
    float slope = 0.2156f;
    float screen = 0.384f;

    float fallback(float occlusion) const { return screen * occlusion; }
    // Expected AO error at a sample with occlusion `occlusion` (1 − AO, in [0, 1]) and occluders at mean
    // distance `occluderDistance` (> 0), whose best probe gives texel area `area` (world units², +inf
    // when none sees it).
    float expected(float area, float occluderDistance, float occlusion) const {
        const float worst = fallback(occlusion);
        if (!(area < INFINITY)) return worst;
        return std::min(worst, occlusion * (occluded + slope * std::sqrt(area) / occluderDistance));
    }
};

}  // namespace cubeao::placement
