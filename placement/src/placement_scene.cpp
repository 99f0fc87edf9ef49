#include <cmath>
#include <set>
#include <tuple>
#include <string>

#include <nlohmann/json.hpp>

#include "cubeao/core/error.h"
#include "cubeao/core/stopwatch.h"
#include "cubeao/placement/placement.h"
#include "cubeao/reference/embree_scene.h"
#include "cubeao/scene/scene.h"
#include "votes.h"

namespace cubeao::placement {

void PlaceSettings::validate() const {
    auto positive = [](float v) { return std::isfinite(v) && v >= 0.0f; };
    if (!positive(radius)) throw UsageError("--radius must be a finite number ≥ 0 (0: the scene's default)");
    if (res < 8 || res > 4096) throw UsageError("--res must lie in [8, 4096]");
    if (!(texelsPerRadius > 0.0f) || !std::isfinite(texelsPerRadius))
        throw UsageError("--texels-per-radius must be a finite number > 0");
    if (!positive(voxel)) throw UsageError("--voxel must be a finite length ≥ 0 (0: automatic)");
    if (!positive(clearance)) throw UsageError("--clearance must be a finite length ≥ 0 (0: half a voxel)");
    if (samples < 1) throw UsageError("--samples must be at least 1");
    if (votingRays < 1) throw UsageError("--rays must be at least 1");
    if (!(target > 0.0 && target <= 1.0)) throw UsageError("--coverage-target must lie in (0, 1]");
    if (budget < 0) throw UsageError("--budget must be ≥ 0 (0: no limit)");
}

nlohmann::json PlaceSettings::toJson() const {
    return {{"radius", radius},   {"res", res},         {"texels_per_radius", texelsPerRadius},
            {"voxel", voxel},     {"clearance", clearance}, {"samples", samples},
            {"rays", votingRays}, {"coverage_target", target}, {"budget", budget},
            {"seed", seed}};
}

PlacementScene::PlacementScene(const Scene& scene, const PlaceSettings& settings, const CameraPath* camera)
    : scene_(scene), settings_(settings), hasCamera_(camera != nullptr) {
    settings_.validate();
    if (scene.triangleCount() == 0) throw Error("placement: " + scene.source + " has no triangles");
    Stopwatch watch;
    if (settings_.radius == 0.0f) settings_.radius = scene.defaultRadius();
    criterion_ = {settings_.res, settings_.radius / settings_.texelsPerRadius, 0.05f};
    embree_ = std::make_unique<EmbreeScene>(scene);
    samples_ = sampleSurface(scene, settings_.samples, settings_.seed);
    timings_.emplace_back("samples", watch.restart());
    freeSpace_ = std::make_unique<FreeSpace>(scene, *embree_, settings_.voxel, settings_.clearance);
    settings_.voxel = freeSpace_->grid().voxel;
    settings_.clearance = freeSpace_->clearance();
    timings_.emplace_back("free_space", watch.restart());
    if (camera) {
        relevant_ = relevantFromCamera(*embree_, samples_, *camera);
        timings_.emplace_back("relevance", watch.restart());
    } else {
        // Without a camera the relevant samples are those free space sees: the voting rays find
        // them, and their votes are kept for the voting method.
        const std::vector<std::uint8_t> all(samples_.size(), 1);
        std::vector<std::uint8_t> reached;
        Votes v = castVotes(*embree_, *freeSpace_, samples_, all, criterion_, settings_.votingRays, settings_.seed,
                            &reached);
        relevant_ = std::move(reached);
        // Votes of samples that turned out irrelevant (no free voxel) cannot exist: a vote needs one.
        votes_ = std::move(v);
        timings_.emplace_back("relevance_and_votes", watch.restart());
    }
}

PlacementScene::~PlacementScene() = default;

std::vector<std::uint32_t> PlacementScene::covered(const glm::vec3& probe) const {
    return coveredSamples(*embree_, samples_, relevant_, criterion_, probe);
}

const PlacementScene::Votes& PlacementScene::votes() const {
    if (!votes_) {
        Stopwatch watch;
        votes_ = castVotes(*embree_, *freeSpace_, samples_, relevant_, criterion_, settings_.votingRays,
                           settings_.seed, nullptr);
        timings_.emplace_back("votes", watch.restart());
    }
    return *votes_;
}

Placement evaluate(const PlacementScene& ps, const std::vector<glm::vec3>& probes, std::string method) {
    Stopwatch watch;
    Placement result;
    result.method = std::move(method);
    // The bake refuses two probes at one position; every method must give distinct ones.
    std::set<std::tuple<float, float, float>> seen;
    for (const glm::vec3& p : probes)
        if (!seen.insert({p.x, p.y, p.z}).second)
            throw Error("placement (" + result.method + "): two probes at (" + std::to_string(p.x) + ", " +
                        std::to_string(p.y) + ", " + std::to_string(p.z) + ")");
    CoverageCounts counts(ps.samples(), ps.relevant());
    for (const glm::vec3& p : probes) {
        const std::vector<std::uint32_t> covered = ps.covered(p);
        const double before = counts.coverage(), before2 = counts.coverage2();
        counts.add(covered);
        result.probes.push_back({p, counts.coverage() - before, counts.coverage2() - before2});
    }
    result.coverage = counts.coverage();
    result.coverage2 = counts.coverage2();
    result.relevantArea = counts.relevantArea();
    result.timings = ps.timings();
    result.timings.emplace_back("report", watch.seconds());
    return result;
}

}  // namespace cubeao::placement
