#include <algorithm>
#include <cmath>
#include <cstdio>
#include <set>
#include <tuple>
#include <string>

#include <nlohmann/json.hpp>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "cubeao/core/error.h"
#include "cubeao/core/stopwatch.h"
#include "cubeao/placement/placement.h"
#include "cubeao/core/sampling.h"
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
    // Upper bounds far above any use (defaults 12000 samples, 24 rays) and below what exhausts memory
    // or runs for hours (issue 15).
    if (samples < 1 || samples > 1'000'000)
        throw UsageError("--samples must be between 1 and 1000000 (got " + std::to_string(samples) + ")");
    if (votingRays < 1 || votingRays > 4096)
        throw UsageError("--rays must be between 1 and 4096 (got " + std::to_string(votingRays) + ")");
    if (!(target > 0.0 && target <= 1.0)) throw UsageError("--coverage-target must lie in (0, 1]");
    if (!(std::isfinite(targetError) && targetError >= 0.0f && targetError < 1.0f))
        throw UsageError("--target-error must lie in [0, 1) (0: automatic)");
    if (budget < 0 || budget > 1'000'000)
        throw UsageError("--budget must be between 0 and 1000000 (0: no limit) (got " + std::to_string(budget) + ")");
}

nlohmann::json PlaceSettings::toJson() const {
    return {{"radius", radius},   {"res", res},         {"texels_per_radius", texelsPerRadius},
            {"voxel", voxel},     {"clearance", clearance}, {"samples", samples},
            {"rays", votingRays}, {"coverage_target", target}, {"budget", budget},
            {"target_error", targetError}, {"seed", seed}};
}

PlacementScene::PlacementScene(const Scene& scene, const PlaceSettings& settings, const CameraPath* camera,
                               std::span<const glm::vec3> seeds)
    : scene_(scene), settings_(settings), hasCamera_(camera != nullptr) {
    settings_.validate();
    if (scene.triangleCount() == 0) throw Error("placement: " + scene.source + " has no triangles");
    Stopwatch watch;
    if (settings_.radius == 0.0f) settings_.radius = scene.defaultRadius();
    criterion_ = {settings_.res, settings_.radius / settings_.texelsPerRadius, 0.05f};
    // An explicit --voxel sets the grid's size in the scene's box: refuse one too fine for memory before
    // anything is allocated (issue 15; the count would also overflow the grid's int dimensions).
    if (settings_.voxel > 0.0f) {
        const glm::vec3 extent = glm::max(scene.bounds.max - scene.bounds.min, glm::vec3(1e-6f));
        const double voxels = std::ceil(double(extent.x) / settings_.voxel) *
                              std::ceil(double(extent.y) / settings_.voxel) *
                              std::ceil(double(extent.z) / settings_.voxel);
        constexpr double kMaxVoxels = double(1 << 26);  // ~67 M: a byte or two each per pass
        if (voxels > kMaxVoxels) {
            const double smallest = std::cbrt(double(extent.x) * extent.y * extent.z / kMaxVoxels);
            char buf[256];
            std::snprintf(buf, sizeof buf,
                          "--voxel %g gives %.3g voxels in the scene's %g x %g x %g box: at most %.0f, so --voxel "
                          "must be at least about %.3g (or 0: automatic)",
                          double(settings_.voxel), voxels, double(extent.x), double(extent.y), double(extent.z),
                          kMaxVoxels, smallest * 1.01);
            throw UsageError(buf);
        }
    }
    embree_ = std::make_unique<EmbreeScene>(scene);
    samples_ = sampleSurface(scene.positions, scene.indices, settings_.samples, settings_.seed);
    timings_.emplace_back("samples", watch.restart());
    // The walk's eyes are known to be free: they seed the flood of free space (free_space.h).
    if (camera)
        for (const CameraFrame& f : camera->frames) eyes_.push_back(f.eye);
    std::vector<glm::vec3> known = eyes_;
    known.insert(known.end(), seeds.begin(), seeds.end());
    freeSpace_ = std::make_unique<FreeSpace>(scene, *embree_, settings_.voxel, settings_.clearance, known);
    if (camera && !eyes_.empty() && freeSpace_->stats().seeds == 0)
        throw Error("placement: " + scene.source + ": none of the walk's " + std::to_string(eyes_.size()) +
                    " eyes stands in free space (each is within --clearance " + std::to_string(freeSpace_->clearance()) +
                    " of geometry, or sees no clear voxel centre around it): is the walk made for this model "
                    "(same units and coordinates), or --clearance/--voxel too large?");
    settings_.voxel = freeSpace_->grid().voxel;
    settings_.clearance = freeSpace_->clearance();
    timings_.emplace_back("free_space", watch.restart());
    if (camera) {
        weights_ = imageShareFromCamera(*embree_, samples_, *camera);
        relevant_.resize(weights_.size());
        for (std::size_t i = 0; i < weights_.size(); ++i) relevant_[i] = weights_[i] > 0.0f ? 1 : 0;
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
        weights_.assign(samples_.size(), 0.0f);
        for (std::size_t i = 0; i < samples_.size(); ++i)
            if (relevant_[i]) weights_[i] = samples_[i].area;
        timings_.emplace_back("relevance_and_votes", watch.restart());
    }
    // Each relevant sample's occlusion and the mean distance of what occludes it (R when nothing does),
    // from cosine-distributed rays as the reference casts them: the AO's scale of variation there.
    occlusion_.assign(samples_.size(), 0.0f);
    occluderDistance_.assign(samples_.size(), settings_.radius);
    const float eps = embree_->surfaceEpsilon(), radius = settings_.radius;
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, samples_.size(), 64), [&](const auto& range) {
        for (std::size_t i = range.begin(); i != range.end(); ++i) {
            if (!relevant_[i]) continue;
            const SurfaceSample& s = samples_[i];
            const glm::vec3 origin = s.position + eps * s.normal;
            int hits = 0;
            double distance = 0.0;
            for (int k = 0; k < kOcclusionRays; ++k) {
                const glm::vec2 u = sampling::rotatedHammersley(std::uint32_t(k), kOcclusionRays, std::uint32_t(i));
                const RayHit h = embree_->intersect(origin, sampling::cosineHemisphere(u, s.normal), 0.0f, radius);
                if (h.hit) ++hits, distance += h.t;
            }
            occlusion_[i] = float(hits) / float(kOcclusionRays);
            if (hits > 0) occluderDistance_[i] = std::max(float(distance / hits), 1e-3f * radius);
        }
    });
    timings_.emplace_back("occlusion", watch.restart());
}

PlacementScene::~PlacementScene() = default;

std::vector<std::uint32_t> PlacementScene::covered(const glm::vec3& probe) const {
    return coveredSamples(*embree_, samples_, relevant_, criterion_, probe);
}

std::vector<SampleView> PlacementScene::seen(const glm::vec3& probe) const {
    return visibleSamples(*embree_, samples_, relevant_, criterion_, probe);
}

std::vector<SampleView> PlacementScene::served(const glm::vec3& probe, std::span<const SampleView> seen) const {
    return servedSamples(*embree_, samples_, criterion_, probe, seen, occlusion_);
}

std::vector<SampleView> PlacementScene::views(const glm::vec3& probe) const { return served(probe, seen(probe)); }

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
    ExpectedError error(ps);
    const float maxArea = ps.criterion().maxArea();
    std::vector<std::uint8_t> served(ps.samples().size(), 0);
    for (const glm::vec3& p : probes) {
        const std::vector<SampleView> views = ps.views(p);
        std::vector<std::uint32_t> covered;
        for (const SampleView& v : views) {
            served[v.sample] = 1;
            if (v.area <= maxArea) covered.push_back(v.sample);
        }
        const double before = counts.coverage(), before2 = counts.coverage2(), beforeMae = error.mae();
        counts.add(covered);
        error.add(views);
        result.probes.push_back({p, counts.coverage() - before, counts.coverage2() - before2, beforeMae - error.mae()});
    }
    result.coverage = counts.coverage();
    result.coverage2 = counts.coverage2();
    result.relevantArea = counts.relevantArea();
    result.predictedMae = error.mae();
    double servedArea = 0.0;
    for (std::size_t i = 0; i < served.size(); ++i)
        if (served[i]) servedArea += ps.samples()[i].area;
    result.served = result.relevantArea > 0.0 ? servedArea / result.relevantArea : 1.0;
    result.timings = ps.timings();
    result.timings.emplace_back("report", watch.seconds());
    return result;
}

ExpectedError::ExpectedError(const PlacementScene& ps, bool fromWalk)
    : ps_(ps), current_(ps.samples().size(), 0.0f) {
    weights_ = fromWalk ? ps.weights() : std::vector<float>(ps.samples().size(), 0.0f);
    // Every relevant sample carries its error, weighted or not, so that weight added later meets the
    // error of the probes already there.
    for (std::size_t i = 0; i < current_.size(); ++i) {
        if (!ps.relevant()[i]) continue;
        current_[i] = ps.expectedError(std::uint32_t(i), INFINITY);
        const double w = weights_[i];
        totalWeight_ += w;
        weighted_ += w * current_[i];
    }
}

void ExpectedError::addWeights(std::span<const float> share) {
    for (std::size_t i = 0; i < share.size(); ++i) {
        if (!(share[i] > 0.0f) || !ps_.relevant()[i]) continue;
        weights_[i] += share[i];
        totalWeight_ += share[i];
        weighted_ += double(share[i]) * double(current_[i]);
    }
}

double ExpectedError::gain(std::span<const SampleView> views) const {
    double g = 0.0;
    for (const SampleView& v : views) {
        const float e = ps_.expectedError(v.sample, v.area);
        if (e < current_[v.sample]) g += double(weights_[v.sample]) * double(current_[v.sample] - e);
    }
    return totalWeight_ > 0.0 ? g / totalWeight_ : 0.0;
}

void ExpectedError::add(std::span<const SampleView> views) {
    for (const SampleView& v : views) {
        const float e = ps_.expectedError(v.sample, v.area);
        if (e < current_[v.sample]) {
            weighted_ -= double(weights_[v.sample]) * double(current_[v.sample] - e);
            current_[v.sample] = e;
        }
    }
}

ErrorTerms errorTerms(const PlacementScene& ps, const std::vector<glm::vec3>& probes) {
    std::vector<float> best(ps.samples().size(), INFINITY);
    for (const glm::vec3& p : probes)
        for (const SampleView& v : ps.views(p)) best[v.sample] = std::min(best[v.sample], v.area);
    ErrorTerms t;
    double total = 0.0;
    const float radius = ps.settings().radius;
    for (std::size_t i = 0; i < best.size(); ++i) {
        const double w = ps.weights()[i], o = ps.occlusion()[i];
        if (!(w > 0.0)) continue;
        total += w;
        if (!(best[i] < INFINITY)) {
            t.unserved += w;
            t.unservedOccluded += w * o;
            continue;
        }
        t.served += w;
        t.occluded += w * o;
        t.texel += w * o * std::sqrt(double(best[i])) / double(radius);
        t.texelNear += w * o * std::sqrt(double(best[i])) / double(ps.occluderDistance()[i]);
        const auto sample = std::uint32_t(i);
        if (ps.expectedError(sample, best[i]) >= ps.expectedError(sample, INFINITY)) t.capped += w;
    }
    if (total > 0.0)
        for (double* x : {&t.served, &t.occluded, &t.texel, &t.texelNear, &t.unserved, &t.unservedOccluded, &t.capped})
            *x /= total;
    return t;
}

double ExpectedError::mae() const { return totalWeight_ > 0.0 ? std::max(0.0, weighted_) / totalWeight_ : 0.0; }

}  // namespace cubeao::placement
