// The error placement minimises (DESIGN.md §4 "Placement", issue 31): the AO error the projection is
// expected to show at a surface sample served by a given probe, so that the greedy optimises the
// picture rather than a 0/1 threshold.
//
// The projection ranks the probes that see a point by the area one of their texels spans there
// (shaders/common/texel_area.h probeTexelArea: distance, off-centre and incidence in one number) and
// blends the best two; the AO it reads is the texel's, taken at the texel's own surface point and
// filtered over its neighbours, and the depth test that decides "sees" reads a distance cube a quarter
// of that resolution. Both errors grow with the texel's side on the surface against the AO radius:
//     expected(s, p) = min(fallback, floor + slope · sqrt(area(s, p)) / R),
// and a sample no probe sees takes the screen-space fallback's error.
//
// Calibration: tools/calibrate_error.sh bakes probe sets of 6–24 probes (along the walk and voting)
// traced at 128² and 512² with 64 rays, renders the shared walks and compares them with a 512-ray
// reference; tools/fit_error_model.py fits the constants by least squares (the prediction is linear
// in them). What they mean:
// - floor: the error of a probe texel small against every AO feature (the rays' noise after the
//   bake's filter, the reference's own noise, the depth test at silhouettes);
// - slope: the error per texel side in units of R (AO varies over about R near creases);
// - fallback: GTAO's walk MAE on the shared walks (0.068–0.10), what an unserved pixel shows.
#pragma once

#include <algorithm>
#include <cmath>

namespace cubeao::placement {

struct ErrorModel {
    float floor = 0.0095f;
    float slope = 0.30f;
    float fallback = 0.08f;

    // Expected AO error at a sample whose best probe gives texel area `area` (world units², +inf when
    // none sees it) for AO radius `radius`.
    float expected(float area, float radius) const {
        if (!(area < INFINITY)) return fallback;
        return std::min(fallback, floor + slope * std::sqrt(area) / radius);
    }
    // The texel side beyond which a probe is no better than the fallback: candidates farther than that
    // cannot help, which bounds the search.
    float usefulTexel(float radius) const { return radius * std::max(fallback - floor, 0.0f) / slope; }
};

}  // namespace cubeao::placement
