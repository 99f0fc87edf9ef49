// Normal voting and its greedy cover (placement.h).
#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <queue>
#include <set>
#include <tuple>
#include <span>

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "cubeao/core/progress.h"
#include "cubeao/core/sampling.h"
#include "cubeao/core/stopwatch.h"
#include "cubeao/reference/embree_scene.h"
#include "site_greedy.h"
#include "votes.h"

namespace cubeao::placement {
namespace {

struct Vote {
    std::uint32_t candidate;
    float weight, area, scale;
};

}  // namespace

PlacementScene::Votes castVotes(const EmbreeScene& embree, const FreeSpace& space,
                                std::span<const SurfaceSample> samples, std::span<const std::uint8_t> cast,
                                const CoverageCriterion& criterion, int rays, std::uint32_t seed,
                                std::vector<std::uint8_t>* reached) {
    const VoxelGrid& grid = space.grid();
    const float maxDistance = criterion.maxDistance(), maxArea = criterion.maxArea();
    const float eps = embree.surfaceEpsilon();
    std::vector<std::vector<Vote>> perSample(samples.size());
    if (reached) reached->assign(samples.size(), 0);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, samples.size(), 16), [&](const auto& range) {
        std::vector<Vote> votes;
        std::vector<std::uint32_t> firstFree;  // per ray, the first candidate it crossed
        for (std::size_t i = range.begin(); i != range.end(); ++i) {
            if (!cast[i]) continue;
            const SurfaceSample& s = samples[i];
            const glm::vec3 origin = s.position + s.normal * eps;
            const std::uint32_t key = sampling::hashKey(std::uint32_t(i), seed, 0xC0FFEEu);
            votes.clear();
            firstFree.clear();
            for (int k = 0; k < rays; ++k) {
                const glm::vec3 dir =
                    sampling::cosineHemisphere(sampling::rotatedHammersley(std::uint32_t(k), std::uint32_t(rays), key),
                                               s.normal);
                const RayHit hit = embree.intersect(origin, dir, 0.0f, std::numeric_limits<float>::infinity());
                const float tEnd = hit.hit ? hit.t : std::numeric_limits<float>::infinity();
                bool seenFree = false;
                walkVoxels(grid, origin, dir, tEnd, [&](const glm::ivec3& c, float t) {
                    const std::int32_t candidate = space.candidateOf(grid.index(c));
                    if (t > maxDistance) {  // too far to vote; only the first free voxel matters (relevance)
                        if (candidate >= 0 && !seenFree) firstFree.push_back(std::uint32_t(candidate));
                        return candidate < 0 && !seenFree && reached != nullptr;
                    }
                    if (candidate < 0) return true;
                    if (!seenFree) firstFree.push_back(std::uint32_t(candidate));
                    seenFree = true;
                    const glm::vec3 center = grid.center(c);
                    const float distance = glm::distance(center, s.position);
                    if (distance > maxDistance) return true;
                    const float area = criterion.footprint(center, s.position, s.normal);
                    if (area <= maxArea) {
                        // The chance that one of the rays crosses this voxel: its solid angle (about
                        // voxel² / distance²) times the rays' cosine density, at most 1.
                        const float cosine = std::max(glm::dot(dir, s.normal), 1e-3f);
                        const float chance = std::min(1.0f, float(rays) * cosine / 3.14159265f * grid.voxel *
                                                                grid.voxel / std::max(distance * distance, 1e-12f));
                        votes.push_back({std::uint32_t(candidate), s.area / area, area, 1.0f / chance});
                    }
                    return true;
                });
            }
            std::sort(votes.begin(), votes.end(),
                      [](const Vote& a, const Vote& b) { return a.candidate < b.candidate; });
            votes.erase(std::unique(votes.begin(), votes.end(),
                                    [](const Vote& a, const Vote& b) { return a.candidate == b.candidate; }),
                        votes.end());
            // A ray crossed the voxel, but its centre, where the probe would stand, may be hidden: keep
            // the votes of centres the sample sees, so a vote means "this candidate covers me".
            auto sees = [&](std::uint32_t candidate) {
                const glm::vec3 to = space.candidatePosition(candidate) - origin;
                const float length = glm::length(to);
                return !embree.occluded(origin, to / length, 0.0f, length);
            };
            votes.erase(std::remove_if(votes.begin(), votes.end(), [&](const Vote& v) { return !sees(v.candidate); }),
                        votes.end());
            if (reached)
                (*reached)[i] = !votes.empty() || std::any_of(firstFree.begin(), firstFree.end(), sees) ? 1 : 0;
            perSample[i].assign(votes.begin(), votes.end());
        }
    });

    PlacementScene::Votes out;
    out.rays = std::size_t(rays) * std::size_t(std::count_if(cast.begin(), cast.end(), [](auto c) { return c != 0; }));
    const std::size_t candidates = space.candidates().size();
    out.offsets.assign(candidates + 1, 0);
    out.weight.assign(candidates, 0.0f);
    for (const auto& votes : perSample)
        for (const Vote& v : votes) ++out.offsets[v.candidate + 1];
    for (std::size_t c = 0; c < candidates; ++c) out.offsets[c + 1] += out.offsets[c];
    out.voters.resize(out.offsets.back());
    out.area.resize(out.offsets.back());
    out.scale.resize(out.offsets.back());
    std::vector<std::uint64_t> fill(out.offsets.begin(), out.offsets.end() - 1);
    for (std::size_t i = 0; i < perSample.size(); ++i)
        for (const Vote& v : perSample[i]) {
            const std::uint64_t k = fill[v.candidate]++;
            out.voters[k] = std::uint32_t(i);
            out.area[k] = v.area;
            out.scale[k] = v.scale;
            out.weight[v.candidate] += v.weight;
        }
    return out;
}

namespace {

// `count` of `points` evenly spread along their order, as probesAlongPath spreads a walk's eyes.
std::vector<glm::vec3> evenlySpread(const std::vector<glm::vec3>& points, std::size_t count) {
    std::vector<glm::vec3> picked;
    const std::size_t n = std::min(count, points.size());
    for (std::size_t i = 0; i < n; ++i) picked.push_back(points[(2 * i + 1) * points.size() / (2 * n)]);
    return picked;
}

// The sites of the greedy: every free voxel that got a vote, then the walk's eyes where they keep a
// tenth of the clearance (the bake needs a probe outside geometry; the walk says its eyes are free).
std::vector<Site> sitesOf(const PlacementScene& ps) {
    const PlacementScene::Votes& votes = ps.votes();
    const FreeSpace& space = ps.freeSpace();
    std::vector<Site> sites;
    for (std::size_t c = 0; c < space.candidates().size(); ++c)
        if (votes.offsets[c + 1] > votes.offsets[c]) sites.push_back({space.candidatePosition(c), std::int64_t(c)});
    for (const glm::vec3& eye : ps.eyes())
        if (space.distanceToSurface(eye) >= 0.1f * space.clearance()) sites.push_back({eye, -1});
    return sites;
}

}  // namespace

Placement placeVoting(const PlacementScene& ps, Progress* progress) {
    Stopwatch watch;
    const PlaceSettings& settings = ps.settings();
    const PlacementScene::Votes& votes = ps.votes();
    Placement result;
    result.method = "voting";
    result.timings = ps.timings();
    watch.restart();

    // Lazy greedy on expected error removed (site_greedy.h).
    SiteGreedy greedy(ps, sitesOf(ps));
    const std::vector<Site>& sites = greedy.sites();
    ExpectedError error(ps);
    greedy.rank(error);
    struct Chosen {
        std::size_t site;
        glm::vec3 position;
        std::vector<SampleView> views;
    };
    std::vector<Chosen> chosen;
    const std::size_t budget = settings.budget > 0 ? std::size_t(settings.budget) : sites.size();
    const bool automatic = settings.budget == 0 && settings.targetError == 0.0f;  // kAutomaticStop decides
    result.stop = "no_gain";
    while (chosen.size() < budget) {
        if (settings.budget == 0 && settings.targetError > 0.0f && error.mae() <= settings.targetError) {
            result.stop = "target_error";
            break;
        }
        const std::optional<SiteGreedy::Pick> pick = greedy.next(error);
        if (!pick) break;
        if (automatic && pick->gain < kAutomaticStop * error.mae()) {
            result.stop = "automatic";
            break;
        }
        error.add(greedy.served(pick->site));
        greedy.take(pick->site);
        chosen.push_back({pick->site, sites[pick->site].position, greedy.served(pick->site)});
        if (progress) progress->advance();
    }
    if (chosen.size() == budget && settings.budget > 0) result.stop = "budget";
    result.timings.emplace_back("greedy", watch.restart());

    // Local move: each probe tries the six free voxels around it and takes the one that removes the
    // most expected error given all the other probes.
    const FreeSpace& space = ps.freeSpace();
    const VoxelGrid& grid = space.grid();
    std::size_t moves = 0, evaluations = greedy.exactEvaluations();
    std::set<std::tuple<float, float, float>> occupied;
    for (const Chosen& c : chosen) occupied.insert({c.position.x, c.position.y, c.position.z});
    // The predicted error of every chosen probe but the j-th.
    auto allBut = [&](std::size_t j) {
        ExpectedError others(ps);
        for (std::size_t i = 0; i < chosen.size(); ++i)
            if (i != j) others.add(chosen[i].views);
        return others;
    };
    for (std::size_t j = 0; j < chosen.size(); ++j) {
        const ExpectedError others = allBut(j);
        double best = others.gain(chosen[j].views);
        const glm::ivec3 cell =
            glm::clamp(glm::ivec3(glm::floor((chosen[j].position - grid.origin) / grid.voxel)), glm::ivec3(0), grid.dims - 1);
        static constexpr int kNeighbours[6][3] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
        for (const auto& step : kNeighbours) {
            const glm::ivec3 n = cell + glm::ivec3(step[0], step[1], step[2]);
            if (!grid.contains(n) || space.candidateOf(grid.index(n)) < 0) continue;
            const glm::vec3 position = grid.center(n);
            if (occupied.count({position.x, position.y, position.z})) continue;
            std::vector<SampleView> views = ps.views(position);
            ++evaluations;
            const double g = others.gain(views);
            if (g > best) {
                best = g;
                occupied.erase({chosen[j].position.x, chosen[j].position.y, chosen[j].position.z});
                occupied.insert({position.x, position.y, position.z});
                chosen[j].position = position;
                chosen[j].views = std::move(views);
                ++moves;
            }
        }
    }
    result.timings.emplace_back("move", watch.restart());

    // The automatic stop asks each probe to remove at least kAutomaticStop of the error. The greedy
    // checks that as a probe joins, but later probes and the moves take over part of what an earlier
    // one serves: drop the probe that removes least while it removes under that share of the error
    // without it, one at a time (the others' shares grow as one goes). Sibenik's walk: the 5th probe
    // removed 0.6 % once the 13 had moved; the 11 left predict as little as the greedy's own 12.
    std::size_t pruned = 0;
    while (automatic && chosen.size() > 1) {
        std::size_t weakest = 0;
        double weakestShare = 1.0;
        for (std::size_t j = 0; j < chosen.size(); ++j) {
            const ExpectedError others = allBut(j);
            const double share = others.mae() > 0.0 ? others.gain(chosen[j].views) / others.mae() : 0.0;
            if (share < weakestShare) weakest = j, weakestShare = share;
        }
        if (weakestShare >= kAutomaticStop) break;
        chosen.erase(chosen.begin() + std::ptrdiff_t(weakest));
        ++pruned;
    }
    if (pruned > 0) result.timings.emplace_back("prune", watch.restart());

    std::vector<glm::vec3> positions;
    for (const Chosen& c : chosen) positions.push_back(c.position);
    // The walk's own eyes, evenly spread, at the same count (the `path` method): the greedy is a
    // heuristic on estimates, so where that set predicts less error it is taken instead, and voting
    // never does worse than path by its own measure.
    bool pathWon = false;
    if (!ps.eyes().empty() && !chosen.empty()) {
        const std::vector<glm::vec3> path = evenlySpread(ps.eyes(), chosen.size());
        ExpectedError ours(ps), theirs(ps);
        for (const Chosen& c : chosen) ours.add(c.views);
        for (const glm::vec3& p : path) theirs.add(ps.views(p));
        if (theirs.mae() < ours.mae()) positions = path, pathWon = true;
    }
    Placement report = evaluate(ps, positions, "voting");
    result.probes = std::move(report.probes);
    result.coverage = report.coverage;
    result.coverage2 = report.coverage2;
    result.relevantArea = report.relevantArea;
    result.predictedMae = report.predictedMae;
    result.served = report.served;
    result.timings.emplace_back("report", watch.restart());
    std::size_t eyes = 0, eyesChosen = 0;
    for (const Site& site : sites) eyes += site.voxel < 0;
    for (const Chosen& c : chosen) eyesChosen += sites[c.site].voxel < 0;
    result.figures = {{"candidates", double(sites.size())},
                      {"eye_candidates", double(eyes)},
                      {"eyes_chosen", double(eyesChosen)},
                      {"votes", double(votes.voters.size())},
                      {"vote_rays", double(votes.rays)},
                      {"exact_evaluations", double(evaluations)},
                      {"bound_evaluations", double(greedy.boundEvaluations())},
                      {"moves", double(moves)},
                      {"pruned", double(pruned)},
                      {"path_set_taken", pathWon ? 1.0 : 0.0}};
    return result;
}

}  // namespace cubeao::placement
