// One definition of coverage for every placement method (DESIGN.md §4 "Placement"):
// - the surface is sampled by area; each point is two oriented samples (one per side), because AO is
//   read on the side a viewer sees and a wall has two;
// - a sample is *relevant* when a viewer can see it: from the camera path when one is given (in a
//   frame's view, facing the eye, nothing in between), else from free space (placement.h);
// - a probe *covers* a sample when nothing lies between them (Embree ray) and the probe texel that
//   sees it spans at most maxTexel on the surface: texelFootprint() of src/cubeao/runtime/projection.h,
//   the area by which the projection ranks probes;
// - coverage = covered relevant area / relevant area, coverage2 = the same for two or more probes (the
//   run time blends the best two).
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

#include "cubeao/core/camera.h"
#include "cubeao/core/surface_samples.h"

namespace cubeao {
class EmbreeScene;
struct Scene;
}  // namespace cubeao

namespace cubeao::kernel {
struct CoverageParams;
}

namespace cubeao::placement {

// The quality threshold of "covered".
struct CoverageCriterion {
    int res = 512;           // the bake's probe face size (texels per side)
    float maxTexel = 0.0f;   // largest texel side on the surface, world units (> 0)
    float minFacing = 0.05f; // as the projection's ProjectSettings::minFacing

    float maxArea() const { return maxTexel * maxTexel; }
    // No probe farther than this can cover anything: a texel at a face centre, seen head-on, spans
    // distance · 2/res.
    float maxDistance() const { return maxTexel * float(res) / 2.0f; }
    // The texel area a probe at `probe` gives surface point x with unit normal n (+inf when the side
    // faces away), the quantity compared with maxArea().
    float footprint(const glm::vec3& probe, const glm::vec3& x, const glm::vec3& n) const;
    // The criterion as the shared kernel (shaders/common/coverage.h) takes it.
    kernel::CoverageParams kernelParams() const;
};

// How much of a camera path's images each sample fills: the mean over frames of the solid angle it
// subtends (area · cos / distance², in the frame's view within the far plane, facing its eye, nothing
// in between) as a share of the frame's. 0: no frame sees it (not relevant). At most `maxFrames` frames,
// evenly spread, are used.
// The same for given frames (all of one aspect), visible between nearPlane and farPlane.
std::vector<float> imageShare(const EmbreeScene& embree, std::span<const SurfaceSample> samples,
                              std::span<const PinholeCamera> cameras, float nearPlane, float farPlane);
std::vector<float> imageShareFromCamera(const EmbreeScene& embree, std::span<const SurfaceSample> samples,
                                        const CameraPath& path, std::size_t maxFrames = 240);
// The samples imageShareFromCamera() finds a frame that sees (weight > 0).
std::vector<std::uint8_t> relevantFromCamera(const EmbreeScene& embree, std::span<const SurfaceSample> samples,
                                             const CameraPath& path, std::size_t maxFrames = 240);

// A relevant sample a probe sees or serves, and the projection's texel area there
// (CoverageCriterion::footprint). The error model is derived from these.
struct SampleView {
    std::uint32_t sample;
    float area;
};
// Every relevant sample (relevant[i] != 0) that a probe at `probe` sees (its side faces the probe,
// nothing lies in between: one Embree ray each), ascending by sample.
std::vector<SampleView> visibleSamples(const EmbreeScene& embree, std::span<const SurfaceSample> samples,
                                       std::span<const std::uint8_t> relevant, const CoverageCriterion& criterion,
                                       const glm::vec3& probe);
// Those of `seen` (visibleSamples of the same probe) that the probe *serves*: what the projection does,
// not only what it sees. The run-time tests each point against the probe's distance cube at
// depth::depthResFor(res), whose texel keeps the nearest of its fine texels (the bake's min filter,
// src/cubeao/cache/depth_cube.h), so a point beside a silhouette, past a nearer edge in the same coarse
// texel, fails and takes another probe or the fallback. The cube is traced here where needed (one
// Embree ray per fine texel of each coarse texel a tested sample falls in: 16 at the default res/4),
// and the test is the run-time's depth::visible with the default biases. With `occlusion` (per sample,
// 1 − AO), samples at 0 pass untested: whatever serves them, their AO is 1 and the expected error 0,
// so the error model is unchanged and only the "served" figure counts them by the ray alone.
// Measured (docs/BENCHMARKS.md "Placement by predicted error", 2026-12-07): of the probe–sample pairs
// an Embree ray finds, 6.8 % fail it for 54 candidates along FZK-Haus's walk, 10.0 % for 52 along
// Sibenik's; with it the prediction correlates with 205 measured 6-probe sets at 0.894 / 0.966
// (FZK-Haus / Sibenik) instead of 0.874 / 0.952, and among the FZK-Haus sets that serve nearly
// everything at 0.75 instead of 0.60. Tracing only the four corner fine texels (a quarter of the
// rays) moved FZK-Haus's 6-probe walk from 0.891× path's MAE to 0.901×.
std::vector<SampleView> servedSamples(const EmbreeScene& embree, std::span<const SurfaceSample> samples,
                                      const CoverageCriterion& criterion, const glm::vec3& probe,
                                      std::span<const SampleView> seen, std::span<const float> occlusion = {});

// Whether a probe at `probe` covers sample s: in range, s faces it, the texel is small enough, and an
// Embree ray finds nothing in between. The one test behind every coverage figure.
bool probeCovers(const EmbreeScene& embree, const CoverageCriterion& criterion, const glm::vec3& probe,
                 const SurfaceSample& s);
// The part of probeCovers() without the ray: cheap, for sorting out probes before tracing.
bool probeMayCover(const CoverageCriterion& criterion, const glm::vec3& probe, const SurfaceSample& s);

// The samples a probe at `probe` covers, ascending; only those with relevant[i] != 0 are tested.
std::vector<std::uint32_t> coveredSamples(const EmbreeScene& embree, std::span<const SurfaceSample> samples,
                                          std::span<const std::uint8_t> relevant, const CoverageCriterion& criterion,
                                          const glm::vec3& probe);

// How often each relevant sample is covered, as probes come and go.
class CoverageCounts {
public:
    CoverageCounts(std::span<const SurfaceSample> samples, std::span<const std::uint8_t> relevant);

    void add(std::span<const std::uint32_t> covered);
    void remove(std::span<const std::uint32_t> covered);
    double relevantArea() const { return relevantArea_; }
    double coverage() const;   // covered once or more / relevant area (1 when nothing is relevant)
    double coverage2() const;  // covered twice or more / relevant area
    std::uint32_t count(std::uint32_t sample) const { return counts_[sample]; }
    // Relevant area that `covered` would add to coverage (samples now at 0) and to coverage2 (at 1).
    double gain(std::span<const std::uint32_t> covered) const;
    double gain2(std::span<const std::uint32_t> covered) const;

private:
    std::span<const SurfaceSample> samples_;
    std::vector<std::uint32_t> counts_;
    double relevantArea_ = 0.0, once_ = 0.0, twice_ = 0.0;
};

}  // namespace cubeao::placement
