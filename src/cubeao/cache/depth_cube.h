// A probe's distance cube (DESIGN.md §4 "Storage"): the bake's per-texel distances downsampled to
// depthRes and quantised to a DepthFormat (docs/FORMAT.md "Distance cube"), and the run-time depth
// test that reads it ("is this surface point visible from the probe?"). CPU reference here; the GPU
// bake's twin is shaders/bake/depth_encode.comp (driver: src/cubeao/bake/gpu_depth.h), which
// produces the same bytes (tests/cache/test_depth_cube.cpp, tests/bake/test_bake_cache.cpp): both compile the
// Min filter, floatToHalf and encodeTexel of shaders/common/depth_encode.h.
//
// Choice of depthRes, format and filter, measured with `cubeao bench depth` (res 512 bakes, 8 probes
// along the camera path, every camera-visible point of 8 frames at 160×90 paired with its 4 nearest
// probes, truth = an Embree ray from the probe to the point; commands and full tables in
// docs/BENCHMARKS.md). Rates: truly hidden pairs called visible / truly visible pairs called hidden,
// in %, under the default DepthTest below (tolerance 0.005, slope 0.7, facing on):
//                                  bytes per AO texel   cloister        Sibenik
//   res/1 r32float (full)          4                    0.89 / 0.25     2.21 / 0.32
//   res/2 r16unorm min             0.5                  0.48 / 0.98     1.59 / 1.71
//   res/4 r16unorm min  (chosen)   0.125                1.03 / 2.46     2.15 / 5.09
//   res/4 r16unorm nearest         0.125                2.83 / 0.86     7.41 / 1.59
//   res/8 r16unorm min             0.031                2.17 / 6.17     3.49 / 10.64
// res/4 is what the 1.25 bytes/texel budget allows (res/2 would make it 1.5). There the min filter
// keeps false "visible" (a probe's AO used for a point it cannot see: a visible artefact) at the
// full-resolution rate, paying with more false "hidden" at silhouettes (the probe is skipped and the
// next candidate used); nearest trades the other way. The format does not matter: r16unorm, r16float
// and r32float differ by < 0.05 points everywhere; r16unorm works at any scene scale (r16float stops
// at 65504 units). Both biases matter: without the slope term res/4 min needs tolerance 0.02 and still
// hides 11.6 % (cloister) / 11.6 % (Sibenik) of the visible pairs; without the facing test even full
// resolution calls 4.7 % / 8.3 % of the hidden pairs visible.
// The lifted second half (DepthTest::offset, off by default) at res/4 r16unorm min, 2026-12-07:
//   lift 0 (default)                                                 1.03 / 2.46     2.15 / 5.09
//   lift 0.71 (kThinWallLift)                                        0.49 / 3.34     1.62 / 6.30
//   lift 1.41 alone, without the slope bias                          -               11.2 / 3.8
// It takes nothing through a 2 cm wall at any level (builtin:two-rooms), but at a concave crease the
// lifted point is behind the floor in front of it as a room is behind a thin wall: on the Sibenik
// walk MAE 0.0124 → 0.0127 at level 0, 0.0219 → 0.0244 at level 2 (docs/BENCHMARKS.md "Thin walls").
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "common/depth_test.h"
#include "cubeao/cache/cache_file.h"

namespace cubeao::depth {

// How a coarse texel summarises the fine texels it covers.
enum class Filter {
    Min,      // the nearest non-empty surface among them (0 when all are empty): conservative, a
              // point behind any of them is hidden
    Nearest,  // the fine texel at the coarse texel's centre (for factor k: fine (k·I + k/2, k·J + k/2))
};
const char* filterName(Filter f);  // "min", "nearest"

// The defaults the bake uses (see the table above).
constexpr int kResDivisor = 4;                                // depthRes = res / 4
constexpr DepthFormat kDefaultFormat = DepthFormat::R16Unorm;  // 2 bytes: + 2/16 = 0.125 byte per AO texel
constexpr Filter kFilter = Filter::Min;
// The run-time test's biases (DepthTest below).
constexpr float kDepthTolerance = 0.005f;
constexpr float kDepthSlope = 0.7f;
constexpr bool kDepthFacing = true;
// The lift of the test's second half (DepthTest::offset): off by default. kThinWallLift passes the
// thin-wall test (two rooms behind a 2 cm wall: no point of one taken by the other's probe at any
// level) at a cost in false "hidden" (the table above; docs/BENCHMARKS.md "Thin walls").
constexpr float kDepthOffset = 0.0f;
constexpr float kThinWallLift = 0.71f;

// depthRes for a bake of `res` texels per side: max(1, res / kResDivisor).
int depthResFor(int res);

// Coarse texel (I, J) of a depthRes face covers the fine texels [⌊I·res/depthRes⌋, ⌊(I+1)·res/depthRes⌋)
// (the same in j), so any depthRes ≤ res works, not only divisors. `distances` (6·res² values) or the
// w of `gbuffer` (6·res² (normal, distance) texels, as CubeGBuffer stores them) in cube::texelIndex
// order, 0 = empty; returns 6·depthRes² distances in the same order. Throws std::invalid_argument for
// a bad size or depthRes outside 1..res.
std::vector<float> downsample(std::span<const float> distances, int res, int depthRes, Filter filter);
std::vector<float> downsample(std::span<const glm::vec4> gbuffer, int res, int depthRes, Filter filter);

// The scale an R16Unorm cube needs: the largest value of `coarse` (0 for an all-empty probe).
float maxDistance(std::span<const float> coarse);

// IEEE half with round-to-nearest-even, integer arithmetic only (common/depth_encode.h, which
// depth_encode.comp compiles too, so the bytes agree exactly): NaN → 0x7E00, ±inf and |f| ≥ 65520 → ±inf.
std::uint16_t floatToHalf(float f);
float halfToFloat(std::uint16_t h);

// One stored texel. 0 stays 0 (empty); a positive distance never becomes 0 (it is stored as at least
// the smallest positive value: 1/65535 of maxDistance, or the smallest half) and a finite one never
// becomes infinite (r16float clamps to 65504, so scenes whose probes see farther than 65504 units
// need r16unorm or r32float). r16unorm: round-to-nearest-even of distance / maxDistance · 65535,
// all in float.
std::uint32_t encodeTexel(float distance, DepthFormat format, float maxDistance);
float decodeTexel(std::uint32_t stored, DepthFormat format, float maxDistance);

// A cube of coarse distances → the bytes of a cache's distance section (little-endian texels, the
// order of `coarse`), and back. decode returns false, touching nothing, when size does not match.
std::vector<std::uint8_t> encode(std::span<const float> coarse, DepthFormat format, float maxDistance);
bool decode(std::span<const std::uint8_t> bytes, int depthRes, DepthFormat format, float maxDistance,
            std::vector<float>& out);

// The run-time depth test: is a surface point visible from the probe? The probe's distance cube is
// an omnidirectional shadow map, and the test has the shadow map's two biases: a relative one for
// quantisation, and a slope-scaled one (Williams 1978; "slope-scaled depth bias" in every shadow
// mapping text) because one coarse texel spans distances D·w·tan θ apart on a surface seen at
// incidence θ (w = 2/depthRes, the texel's angle at the face centre, its widest).
struct DepthTest {
    float tolerance = kDepthTolerance;  // relative: visible when distance ≤ stored · (1 + tolerance + slope term)
    float slope = kDepthSlope;          // slope term = slope · w · min(tan θ, kMaxTan)
    bool facing = kDepthFacing;         // a point whose seen side faces away from the probe is hidden
    float offset = kDepthOffset;        // the point lifted this many coarse texel widths off its surface
                                        // must not be behind the stored surface (liftedClear); 0: no lift
};
constexpr float kMaxTan = kernel::kMaxTan;  // θ ≈ 83°: beyond, the bias would accept everything behind the surface

// The test's second half (common/depth_test.h): surface point x with unit normal n (turned to the side
// seen) lifted off its surface by t.offset coarse texels, and what visible() reads there.
inline glm::vec3 liftedPoint(const DepthTest& t, const glm::vec3& probe, const glm::vec3& x, const glm::vec3& n,
                             int depthRes) {
    return kernel::depthLiftedPoint(x, n, glm::length(x - probe), t.offset, depthRes);
}
struct Lifted {
    float stored = 0.0f;    // the texel in the lifted point's direction
    float distance = 0.0f;  // the lifted point's distance from the probe
};

// The whole test (common/depth_test.h depthVisible). `stored`: the decoded texel in the point's
// direction; `distance`: from the probe to the point; `cosine`: cos θ between the point's normal,
// turned to the side the camera sees, and the direction from the point to the probe. An empty texel
// (0) hides nothing. Beyond the relative tolerance the lifted point must be clear as well (t.offset 0:
// no lift); without `lifted` (an empty texel there) that half passes, i.e. the first half alone.
inline bool visible(const DepthTest& t, float stored, float distance, float cosine, int depthRes,
                    Lifted lifted = {}) {
    if (t.facing && !(cosine > 0.0f)) return false;
    if (!(stored > 0.0f)) return true;
    return kernel::depthVisible(stored, distance, cosine, lifted.stored, lifted.distance, t.tolerance, t.slope,
                                t.offset, depthRes);
}

}  // namespace cubeao::depth
