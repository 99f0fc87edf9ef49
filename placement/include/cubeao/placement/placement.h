// Where probes go (DESIGN.md §4 "Placement", issue 12). Every method works on one PlacementScene (the
// scene's samples, which of them are relevant, the free space and its candidates, the coverage
// criterion) and returns probes in the order chosen with the coverage each one added, measured by
// the one definition of coverage.h:
// - voting: each relevant sample casts rays in a cone around its normal; every candidate voxel a ray
//   crosses before it hits geometry, near enough to give a small enough texel, gets the sample's vote.
//   Lazy greedy then takes the candidate whose voters are the most still-uncovered area (second
//   coverage counting half), until the target or the budget; a pruning pass drops probes the target
//   does not need and each probe moves to a neighbouring voxel where it covers more;
// - grid: a uniform lattice of free points; the spacing is searched by bisection for the coarsest
//   that reaches the target (or the finest within the budget), so it is compared at its best;
// - path and coverage feedback produce their probes elsewhere (probe_set.h, coverage_feedback.h) and
//   are reported here by evaluate().
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <glm/vec3.hpp>
#include <nlohmann/json_fwd.hpp>

#include "cubeao/core/camera.h"
#include "cubeao/placement/coverage.h"
#include "cubeao/placement/error_model.h"
#include "cubeao/placement/free_space.h"

namespace cubeao {
class EmbreeScene;
class Progress;
struct Scene;
}  // namespace cubeao

namespace cubeao::placement {

struct PlaceSettings {
    float radius = 0.0f;           // AO radius; 0 → the scene's default (2 % of the diagonal)
    int res = 512;                 // the bake's face size the criterion assumes
    float texelsPerRadius = 16.0f;  // covered: one texel spans at most radius / texelsPerRadius
    float voxel = 0.0f;            // candidate voxel edge; 0 → about 150 000 voxels in the box
    float clearance = 0.0f;        // 0 → half a voxel
    std::size_t samples = 100000;  // surface points (two samples each); 12,000 left Sibenik's walk ~500 relevant
                                   // samples, too few for a stable prediction (fit rms 19 % or 29 % by the seed)
    int votingRays = 24;           // rays per relevant sample
    double target = 0.95;          // grid and coverage: coverage to reach (1 = as much as the budget allows)
    int budget = 0;                // voting: exactly this many probes (fewer only when no probe lowers the
                                   // expected error); grid: at most; 0 = no limit
    float targetError = 0.0f;      // voting: stop once the predicted walk MAE is at most this; 0 = automatic
                                   // (stop where the next probe would remove under kAutomaticStop of it)
    std::uint32_t seed = 0;

    // Throws UsageError naming the bad value.
    void validate() const;
    nlohmann::json toJson() const;
};

// Everything the methods share. Building it is the expensive common part: Embree, the free-space
// voxels, the samples and their relevance.
class PlacementScene {
public:
    // `camera` may be null: then the relevant samples are those free space sees. `seeds`: more points
    // known to be free, beside the walk's eyes (the viewer's camera, where a person stands).
    PlacementScene(const Scene& scene, const PlaceSettings& settings, const CameraPath* camera,
                   std::span<const glm::vec3> seeds = {});
    ~PlacementScene();
    PlacementScene(const PlacementScene&) = delete;
    PlacementScene& operator=(const PlacementScene&) = delete;

    const Scene& scene() const { return scene_; }
    const EmbreeScene& embree() const { return *embree_; }
    const FreeSpace& freeSpace() const { return *freeSpace_; }
    const PlaceSettings& settings() const { return settings_; }
    const CoverageCriterion& criterion() const { return criterion_; }
    const std::vector<SurfaceSample>& samples() const { return samples_; }
    const std::vector<std::uint8_t>& relevant() const { return relevant_; }
    // How much each sample weighs in the predicted MAE: the share of the walk's images it fills, or
    // without a walk its area where free space sees it; 0 when not relevant.
    const std::vector<float>& weights() const { return weights_; }
    const ErrorModel& errorModel() const { return errorModel_; }
    bool hasCamera() const { return hasCamera_; }
    // The walk's eyes (empty without a camera): known free space, and probe sites of their own.
    const std::vector<glm::vec3>& eyes() const { return eyes_; }

    std::vector<std::uint32_t> covered(const glm::vec3& probe) const;
    // The relevant samples a probe at `probe` serves (sees, and the projection's depth test accepts:
    // servedSamples, which passes samples without occlusion untested), with the texel area it gives each.
    std::vector<SampleView> views(const glm::vec3& probe) const;
    // The first half of views(): the samples it sees (one ray each, ~16× cheaper than the depth test).
    // A superset of views(), so the expected error it would remove bounds views()'s from above: the
    // greedy ranks by it and tests depth only where a site may win.
    std::vector<SampleView> seen(const glm::vec3& probe) const;
    std::vector<SampleView> served(const glm::vec3& probe, std::span<const SampleView> seen) const;
    // 1 − AO of each relevant sample (Embree, kOcclusionRays cosine rays within R; 0 for the others):
    // where nothing is near, any texel gets the AO right.
    const std::vector<float>& occlusion() const { return occlusion_; }
    // The mean distance to what occludes each relevant sample within R (R when nothing does).
    const std::vector<float>& occluderDistance() const { return occluderDistance_; }
    static constexpr int kOcclusionRays = 64;
    // Expected AO error of `sample` served by a texel of `area` (ErrorModel::expected at the scene's
    // radius; area +inf: no probe sees it).
    float expectedError(std::uint32_t sample, float area) const {
        return errorModel_.expected(area, occluderDistance_[sample], occlusion_[sample]);
    }

    // Voters per candidate (CSR: candidate c's samples are voters[offsets[c] .. offsets[c + 1])), the
    // quality-weighted vote of each candidate (Σ area / footprint), and per vote the texel area and
    // the inverse of the chance that the sample's rays found that voxel (its solid angle against the
    // rays' cosine density), so that Σ scale · f(sample) over a candidate's voters estimates Σ f over
    // every sample it sees. Cast on first use.
    struct Votes {
        std::vector<std::uint64_t> offsets;
        std::vector<std::uint32_t> voters;
        std::vector<float> area, scale;  // per vote, beside voters
        std::vector<float> weight;
        std::size_t rays = 0;
    };
    const Votes& votes() const;

    // Seconds per stage so far ("samples", "free_space", "relevance", "votes").
    const std::vector<std::pair<std::string, double>>& timings() const { return timings_; }

private:
    const Scene& scene_;
    PlaceSettings settings_;
    CoverageCriterion criterion_;
    std::unique_ptr<EmbreeScene> embree_;
    std::unique_ptr<FreeSpace> freeSpace_;
    std::vector<SurfaceSample> samples_;
    std::vector<std::uint8_t> relevant_;
    std::vector<float> weights_;
    std::vector<float> occlusion_, occluderDistance_;
    ErrorModel errorModel_;
    std::vector<glm::vec3> eyes_;
    bool hasCamera_ = false;
    mutable std::optional<Votes> votes_;
    mutable std::vector<std::pair<std::string, double>> timings_;
};

struct PlacedProbe {
    glm::vec3 position{0.0f};
    double gain = 0.0;   // coverage this probe added after the ones before it
    double gain2 = 0.0;  // the same for coverage2
    double errorRemoved = 0.0;  // predicted walk MAE this probe removed after the ones before it
};

struct Placement {
    std::string method;
    std::vector<PlacedProbe> probes;
    // coverage / coverage2: the fine coverage (a texel at most R / texels-per-radius), once and twice.
    double coverage = 0.0, coverage2 = 0.0, relevantArea = 0.0;
    double predictedMae = 0.0;  // the error model's walk MAE (image-weighted; unserved samples at the fallback)
    double served = 0.0;        // relevant area some probe serves (views(): the projection's "covered")
    std::string stop;           // why the method stopped adding probes (voting)
    std::vector<std::pair<std::string, double>> timings;  // seconds per stage
    std::vector<std::pair<std::string, double>> figures;  // method-specific numbers (grid spacing, ...)
};

// The predicted walk MAE of a probe set as probes join it: every relevant sample at the error of the
// best probe that sees it (the projection ranks by texel area, and the error model grows with it),
// the fallback's where none does, weighted by PlacementScene::weights().
// The weights start as PlacementScene::weights() (the whole walk), or at 0 with `fromWalk` false for a
// walk seen one frame at a time (live placement, error_feedback.h), which adds each frame's image
// shares with addWeights().
class ExpectedError {
public:
    explicit ExpectedError(const PlacementScene& ps, bool fromWalk = true);
    // What adding a probe with these views would remove from mae().
    double gain(std::span<const SampleView> views) const;
    void add(std::span<const SampleView> views);
    // More weight on samples (one frame's image shares, imageShare()); irrelevant samples are skipped:
    // the scene has no occlusion for them.
    void addWeights(std::span<const float> share);
    double mae() const;
    float current(std::uint32_t sample) const { return current_[sample]; }
    float weight(std::uint32_t sample) const { return weights_[sample]; }
    double totalWeight() const { return totalWeight_; }

private:
    const PlacementScene& ps_;
    std::vector<float> weights_, current_;
    double totalWeight_ = 0.0, weighted_ = 0.0;
};

// The coverage report of given probes, in their order (path, coverage feedback, any probes.json).
Placement evaluate(const PlacementScene& ps, const std::vector<glm::vec3>& probes, std::string method);

// The parts of a probe set's predicted MAE, each a mean over the relevant samples' weight (image share
// along a walk): served (some probe sees the sample), occluded (its occlusion o, over the served), texel
// (o · s / R, s the side of its best probe's texel), texelNear (o · s / L, L the occluders' distance),
// unserved and unservedOccluded (1 and o over the others), capped (served, but at the fallback's error
// already). Without the cap the prediction is occluded-constant · occluded + slope · texelNear + screen ·
// unservedOccluded: linear in the model's constants, which is how tools/calibrate_error.sh fits them.
struct ErrorTerms {
    double served = 0.0, occluded = 0.0, texel = 0.0, texelNear = 0.0, unserved = 0.0, unservedOccluded = 0.0;
    double capped = 0.0;  // texelNear: texel's o · s over the occluders' mean distance instead of R
};
ErrorTerms errorTerms(const PlacementScene& ps, const std::vector<glm::vec3>& probes);

// The automatic stop of voting without --budget or --target-error (and of live placement): the next
// probe would lower the predicted MAE by less than this share of it. At 2 % Sibenik's walk stopped at
// 6 probes (measured MAE 0.91× that of 12 probes along the walk), at 1.5 % at 8 (0.79×, but 0.0102 on
// the frames 0:12 where 0.010 is asked; FZK-Haus 0.903× at 9); probes 9–13 there remove 0.9–1.6 %
// each (docs/BENCHMARKS.md "Placement by predicted error"). Voting holds every probe of its final set to
// it: after the local moves, a probe that removes less given the others is dropped (placeVoting).
inline constexpr double kAutomaticStop = 0.01;

Placement placeVoting(const PlacementScene& ps, Progress* progress = nullptr);
Placement placeGrid(const PlacementScene& ps, Progress* progress = nullptr);
// The points of a lattice with spacing `spacing`, centred in the scene's box, that are free or have a
// free voxel centre within half a spacing (where they move).
std::vector<glm::vec3> gridProbes(const PlacementScene& ps, float spacing);

}  // namespace cubeao::placement
