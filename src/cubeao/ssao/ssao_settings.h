// Screen-space AO baselines (DESIGN.md §1 "baselines", papers 000–002): what they compute and how.
// A plain aggregate where zero means "default" (STYLE.md, sokol), resolved once by
// resolveSsaoSettings. Pure, no GL.
//
// Every method marches the camera G-buffer within the world radius R projected to the screen at the
// pixel's depth (the same R as the bake and the reference, DESIGN.md §4), counts only occluders
// within R of the pixel's surface point (V_R) and weights them by the same falloff as the reference
// (none: 1; smooth: (1 − (t/R)²)²), and returns AO in [0, 1] with 1 = open.
#pragma once

#include <cstdint>
#include <string>

#include "cubeao/core/falloff.h"

namespace cubeao {

enum class SsaoMethod {
    Alchemy,  // "alchemy": Alchemy obscurance estimator, paper 000 eq. 2.2.6 (McGuire et al. 2011)
    Hbao,     // "hbao": horizon-based AO, sin h − sin t per direction with attenuation (paper 002 §3.3.4, 001)
    Gtao,     // "gtao": cosine-weighted slice integral, paper 002 eqs. 3.21–3.23 with the projected normal
};
SsaoMethod parseSsaoMethod(const std::string& name);  // UsageError naming the choices otherwise
const char* ssaoMethodName(SsaoMethod m);

struct SsaoSettings {
    SsaoMethod method = SsaoMethod::Gtao;
    float radius = 0.0f;       // R, world units; 0 → the scene default (2 % of the bbox diagonal)
    Falloff falloff = Falloff::None;
    int directions = 0;        // N_d screen directions; 0 → 8. Even: gtao takes them as N_d/2 slices
                               // with two sides each. alchemy takes N_d × N_s spiral samples (the
                               // same fetch budget).
    int steps = 0;             // N_s march steps per direction; 0 → 8
    float maxRadiusPixels = 0.0f;  // clamp of the projected radius, pixels; 0 → no clamp (exact R,
                                   // at the cost of texture-cache misses close to the camera)
    std::uint32_t seed = 0;    // changes every pixel's jitter (key = hash(x, y, frame ^ seed))

    // Alchemy only (paper 000 eq. 2.2.6): A = max(0, 1 − (2σ/N) Σ R·max(0, v·n + z_C β)/(v·v + ε))^k.
    // Paper 000's σ carries the scene's length unit; ours is scaled by R so one value fits every
    // scene. 0 → defaults below.
    float alchemyIntensity = 0.0f;  // σ; 0 → 0.8, fitted to the Embree reference on the cloister
                                    // (8 frames: MAE 0.059 at σ = 0.5, 0.047 at 0.8, 0.050 at 1, 0.075 at 1.5)
    float alchemyContrast = 0.0f;   // k; 0 → 1 (no contrast change)
    float alchemyBias = 0.0f;       // β, per unit of view depth; 0 → 1e-4 (McGuire et al.: 10⁻⁴)
    float alchemyEpsilon = 0.0f;    // ε in units of R²; 0 → 0.01 (keeps neighbours from exploding)
};

// Fills zero fields with the defaults (radius from `sceneDefaultRadius`) and checks ranges, listing
// every problem in one UsageError.
SsaoSettings resolveSsaoSettings(SsaoSettings s, float sceneDefaultRadius);

// G-buffer texel fetches per pixel that a method plans for a pixel with geometry: the centre's depth
// and normal plus one depth fetch per sample. (Measured counts are lower: samples beyond the screen
// or a projected radius under a pixel are skipped.)
int plannedFetchesPerPixel(const SsaoSettings& s);

}  // namespace cubeao
