// Horizon estimators on a probe's cube G-buffer, per texel (DESIGN.md §4 "Bake"), for the CPU bake
// path and the tests that check the GPU pass: the C++ face of the shared kernel
// shaders/common/horizon.h, which shaders/bake/ao_horizon.comp compiles as GLSL.
//
// Both march in world space from the texel's surface point p out to the AO radius R and look the
// cube map up *by direction from the probe*, so a march crosses face borders like any other texel
// (no seams, unlike the face-local offsets of Oswald's thesis, fig. 5.7). The occluder for a march
// point x is the surface the probe sees in the direction of x (the texel centre's surface point q).
//
// Confidence (GTAO; horizon-split refines it below): a march point is *hidden* when the probe sees
// something nearer than x in its direction that is not this texel's occluder yet could hide one: it
// lies above p's tangent plane but farther than R from p. The depth map says nothing about what lies
// behind it around x then. (A surface at or below the tangent plane hides only more of the
// half-space below it, since the probe is above the plane, and nothing there occludes p.)
// confidence = 1 − hidden fraction of all march points. "Above" means by more than float rounding
// (1e-5 of the coordinates' size), so an open plane has AO 1 and confidence 1 at every texel,
// grazing ones included.
#pragma once

#include <cstdint>

#include <glm/vec3.hpp>

#include "cubeao/bake/bake_settings.h"
#include "cubeao/bake/cube_gbuffer.h"

namespace cubeao {

struct HorizonEstimate {
    float ao = 1.0f;
    float confidence = 1.0f;
    std::uint32_t fetches = 0;  // G-buffer lookups made
};

// Horizon-split AO, Oswald ch. 4: AO = 1 − 1/N_d Σ sin²(h_i) over N_d azimuths in the tangent plane
// of (p, n); with a falloff each rise of sin² h is weighted by the falloff at the occluder's distance.
// The horizon is the top of a height field over the tangent plane: at each march point x the
// estimator asks the probe about points straight above x (along n), y = x + b·n, and calls y
// *solid* when the probe sees, in y's direction, a surface nearer than y that lies within R of p and
// above its tangent plane (y is inside or behind that surface: below the height field), *open*
// when the probe sees y itself or something beyond it, and *unknown* otherwise (hidden behind a
// surface that is not p's occluder). The top is found by bisection between the current horizon and
// the R-ball. Marching only the tangent plane itself would find a wall only where rays from the
// probe to the plane cross it, low down, and miss most of its occlusion whenever the probe looks at
// the wall obliquely.
// Confidence counts a march point as doubtful when it is unknown, or when it is open at the horizon
// but solid higher up (an overhang: an arch, a table top, which breaks the height-field model).
HorizonEstimate horizonSplitAo(const CubeGBuffer& g, const glm::vec3& p, const glm::vec3& n, const BakeSettings& s,
                               std::uint32_t key);

// GTAO (Jimenez et al. 2016, paper 002, eq. 10 with the projected-normal weight): N_d/2 slices around
// the direction to the probe (the "view" vector), two horizons per slice, normalised by the open
// hemisphere's slice integrals as the screen-space GTAO is (shaders/common/gtao.h): an open plane reads 1.
HorizonEstimate gtaoAo(const CubeGBuffer& g, const glm::vec3& p, const glm::vec3& n, const BakeSettings& s,
                       std::uint32_t key);


}  // namespace cubeao
