// Normal voting and its greedy cover (placement.h).
#include <algorithm>
#include <cmath>
#include <limits>
#include <queue>
#include <span>

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "cubeao/core/progress.h"
#include "cubeao/core/sampling.h"
#include "cubeao/core/stopwatch.h"
#include "cubeao/reference/embree_scene.h"
#include "votes.h"

namespace cubeao::placement {
namespace {

// Second coverage counts half as much as first in the greedy gain: the run time blends the best two
// probes, but a point no probe sees is far worse off than one only one probe sees.
constexpr double kSecondWeight = 0.5;

// The greedy's objective: what `covered` adds to first coverage, plus half of what it adds to second.
double objectiveGain(const CoverageCounts& counts, std::span<const std::uint32_t> covered) {
    return counts.gain(covered) + kSecondWeight * counts.gain2(covered);
}

struct Vote {
    std::uint32_t candidate;
    float weight;
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
                    if (glm::distance(center, s.position) > maxDistance) return true;
                    const float area = criterion.footprint(center, s.position, s.normal);
                    if (area <= maxArea) votes.push_back({std::uint32_t(candidate), s.area / area});
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
    std::vector<std::uint64_t> fill(out.offsets.begin(), out.offsets.end() - 1);
    for (std::size_t i = 0; i < perSample.size(); ++i)
        for (const Vote& v : perSample[i]) {
            out.voters[fill[v.candidate]++] = std::uint32_t(i);
            out.weight[v.candidate] += v.weight;
        }
    return out;
}

Placement placeVoting(const PlacementScene& ps, Progress* progress) {
    Stopwatch watch;
    const PlaceSettings& settings = ps.settings();
    const PlacementScene::Votes& votes = ps.votes();
    Placement result;
    result.method = "voting";
    result.timings = ps.timings();
    watch.restart();

    const std::vector<SurfaceSample>& samples = ps.samples();
    CoverageCounts counts(samples, ps.relevant());
    const std::size_t candidates = ps.freeSpace().candidates().size();
    // The objective's gain if candidate c covered exactly its voters.
    auto voterGain = [&](std::size_t c) {
        const std::uint64_t first = votes.offsets[c], count = votes.offsets[c + 1] - first;
        return objectiveGain(counts, std::span(votes.voters).subspan(first, count));
    };
    // Lazy greedy: the gains only fall as coverage grows (a sum of concave functions of the counts),
    // so a candidate whose refreshed gain still beats every stale bound above it is the best.
    using Entry = std::pair<double, std::int64_t>;  // (gain bound, −candidate): ties go to the lowest index
    std::priority_queue<Entry> queue;
    for (std::size_t c = 0; c < candidates; ++c)
        if (votes.offsets[c + 1] > votes.offsets[c]) queue.push({voterGain(c), -std::int64_t(c)});

    struct Chosen {
        std::size_t candidate;
        glm::vec3 position;
        std::vector<std::uint32_t> covered;
    };
    std::vector<Chosen> chosen;
    const std::size_t budget = settings.budget > 0 ? std::size_t(settings.budget) : candidates;
    std::size_t evaluations = 0;
    while (!queue.empty() && chosen.size() < budget && counts.coverage() < settings.target) {
        const auto [bound, negative] = queue.top();
        queue.pop();
        const std::size_t c = std::size_t(-negative);
        const double gain = voterGain(c);
        if (!(gain > 0.0)) continue;
        if (!queue.empty() && gain < queue.top().first) {
            queue.push({gain, negative});
            continue;
        }
        // The votes said so; the exact test decides (a voxel's centre can be hidden where its ray was not).
        const glm::vec3 position = ps.freeSpace().candidatePosition(c);
        std::vector<std::uint32_t> covered = ps.covered(position);
        ++evaluations;
        if (!(objectiveGain(counts, covered) > 0.0)) continue;
        counts.add(covered);
        chosen.push_back({c, position, std::move(covered)});
        if (progress) progress->advance();
    }
    result.timings.emplace_back("greedy", watch.restart());

    // Pruning: drop probes, least unique area first, while the target still holds.
    if (counts.coverage() >= settings.target) {
        bool dropped = true;
        while (dropped && chosen.size() > 1) {
            dropped = false;
            std::size_t weakest = chosen.size();
            double weakestArea = std::numeric_limits<double>::infinity();
            for (std::size_t k = 0; k < chosen.size(); ++k) {
                double unique = 0.0;
                for (const std::uint32_t s : chosen[k].covered)
                    if (counts.count(s) == 1) unique += samples[s].area;
                if (unique < weakestArea) weakestArea = unique, weakest = k;
            }
            counts.remove(chosen[weakest].covered);
            if (counts.coverage() >= settings.target) {
                chosen.erase(chosen.begin() + std::ptrdiff_t(weakest));
                dropped = true;
            } else {
                counts.add(chosen[weakest].covered);
            }
        }
    }
    result.timings.emplace_back("prune", watch.restart());

    // Local move: each probe tries the six neighbouring candidate voxels and takes the one that adds
    // the most (first coverage, plus half of second coverage) given all other probes.
    const VoxelGrid& grid = ps.freeSpace().grid();
    std::size_t moves = 0;
    // Two probes never share a voxel (the bake refuses a probe set with two at one position).
    std::vector<std::uint8_t> taken(candidates, 0);
    for (const Chosen& c : chosen) taken[c.candidate] = 1;
    for (Chosen& probe : chosen) {
        counts.remove(probe.covered);
        double best = objectiveGain(counts, probe.covered);
        const glm::ivec3 cell = grid.cell(ps.freeSpace().candidates()[probe.candidate]);
        static constexpr int kNeighbours[6][3] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
        for (const auto& step : kNeighbours) {
            const glm::ivec3 n = cell + glm::ivec3(step[0], step[1], step[2]);
            if (!grid.contains(n)) continue;
            const std::int32_t candidate = ps.freeSpace().candidateOf(grid.index(n));
            if (candidate < 0 || taken[std::size_t(candidate)]) continue;
            const glm::vec3 position = ps.freeSpace().candidatePosition(std::size_t(candidate));
            std::vector<std::uint32_t> covered = ps.covered(position);
            ++evaluations;
            const double g = objectiveGain(counts, covered);
            if (g > best) {
                best = g;
                taken[probe.candidate] = 0;
                taken[std::size_t(candidate)] = 1;
                probe = {std::size_t(candidate), position, std::move(covered)};
                ++moves;
            }
        }
        counts.add(probe.covered);
    }
    result.timings.emplace_back("move", watch.restart());

    std::vector<glm::vec3> positions;
    for (const Chosen& c : chosen) positions.push_back(c.position);
    Placement report = evaluate(ps, positions, "voting");
    result.probes = std::move(report.probes);
    result.coverage = report.coverage;
    result.coverage2 = report.coverage2;
    result.relevantArea = report.relevantArea;
    result.timings.emplace_back("report", watch.restart());
    result.figures = {{"candidates", double(candidates)},
                      {"votes", double(votes.voters.size())},
                      {"vote_rays", double(votes.rays)},
                      {"exact_evaluations", double(evaluations)},
                      {"moves", double(moves)}};
    return result;
}

}  // namespace cubeao::placement
