// The fair grid (placement.h): a uniform lattice of free points whose spacing is searched, so the
// comparison with voting is made against the grid at its best rather than at a guess.
#include <algorithm>
#include <cmath>
#include <set>
#include <tuple>

#include <glm/geometric.hpp>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "cubeao/core/progress.h"
#include "cubeao/core/stopwatch.h"
#include "cubeao/placement/placement.h"
#include "cubeao/reference/embree_scene.h"
#include "cubeao/scene/scene.h"

namespace cubeao::placement {
namespace {

// Finer lattices than this are not tried: a grid that needs more probes has lost the comparison.
constexpr std::size_t kMaxGridProbes = 6000;
constexpr int kBisections = 10;
constexpr int kBudgetTrials = 8;  // spacings tried on each side of the finest lattice within a budget

struct GridTrial {
    float spacing = 0.0f;
    std::vector<glm::vec3> probes;
    double coverage = 0.0;
};

// coverage() and coverage2() of a probe set without per-probe sets: each relevant sample stops
// looking once two probes cover it, so a lattice of thousands costs little more than its nearest few.
std::pair<double, double> coverageOf(const PlacementScene& ps, const std::vector<glm::vec3>& probes) {
    const auto& samples = ps.samples();
    const auto& relevant = ps.relevant();
    std::vector<std::uint8_t> count(samples.size(), 0);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, samples.size(), 64), [&](const auto& range) {
        std::vector<std::pair<float, std::uint32_t>> near;
        for (std::size_t i = range.begin(); i != range.end(); ++i) {
            if (!relevant[i]) continue;
            const SurfaceSample& s = samples[i];
            near.clear();
            for (std::uint32_t k = 0; k < probes.size(); ++k)
                if (probeMayCover(ps.criterion(), probes[k], s))
                    near.emplace_back(glm::distance(probes[k], s.position), k);
            std::sort(near.begin(), near.end());  // nearest first: the likeliest to see the sample
            std::uint8_t n = 0;
            for (const auto& [distance, k] : near)
                if (probeCovers(ps.embree(), ps.criterion(), probes[k], s) && ++n == 2) break;
            count[i] = n;
        }
    });
    double area = 0.0, once = 0.0, twice = 0.0;
    for (std::size_t i = 0; i < samples.size(); ++i) {
        if (!relevant[i]) continue;
        area += samples[i].area;
        if (count[i] >= 1) once += samples[i].area;
        if (count[i] >= 2) twice += samples[i].area;
    }
    if (!(area > 0.0)) return {1.0, 1.0};
    return {once / area, twice / area};
}

}  // namespace

std::vector<glm::vec3> gridProbes(const PlacementScene& ps, float spacing) {
    const Bounds& b = ps.scene().bounds;
    const FreeSpace& space = ps.freeSpace();
    const VoxelGrid& grid = space.grid();
    const glm::vec3 extent = b.max - b.min;
    // The lattice points are the centres of cells `spacing` wide, as many as fit, centred in the box.
    VoxelGrid lattice;
    lattice.voxel = spacing;
    lattice.dims = glm::max(glm::ivec3(glm::floor(extent / spacing)), glm::ivec3(1));
    lattice.origin = b.min + 0.5f * (extent - glm::vec3(lattice.dims) * spacing);
    const std::size_t total = lattice.size();
    // A lattice point in a wall moves to the nearest free voxel centre within half a spacing, as
    // engines relocate grid probes (DDGI): the grid gets every chance a user would give it.
    const int reach = std::min(8, int(std::floor(0.5f * spacing / grid.voxel)));
    std::vector<glm::vec3> placed(total);
    std::vector<std::uint8_t> ok(total, 0);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, total, 16), [&](const auto& range) {
        for (std::size_t i = range.begin(); i != range.end(); ++i) {
            const glm::vec3 p = lattice.center(i);
            if (space.isFree(p)) {
                placed[i] = p, ok[i] = 1;
                continue;
            }
            const glm::ivec3 home = glm::ivec3(glm::floor((p - grid.origin) / grid.voxel));
            float best = 0.5f * spacing;
            for (int z = -reach; z <= reach; ++z)
                for (int y = -reach; y <= reach; ++y)
                    for (int x = -reach; x <= reach; ++x) {
                        const glm::ivec3 v = home + glm::ivec3(x, y, z);
                        if (!grid.contains(v) || space.candidateOf(grid.index(v)) < 0) continue;
                        const float d = glm::distance(grid.center(v), p);
                        if (d < best) best = d, placed[i] = grid.center(v), ok[i] = 1;
                    }
        }
    });
    // Two lattice points may move to one voxel centre: keep it once (the bake refuses duplicates).
    std::vector<glm::vec3> probes;
    std::set<std::tuple<float, float, float>> seen;
    for (std::size_t i = 0; i < total; ++i)
        if (ok[i] && seen.insert({placed[i].x, placed[i].y, placed[i].z}).second) probes.push_back(placed[i]);
    return probes;
}

Placement placeGrid(const PlacementScene& ps, Progress* progress) {
    Stopwatch watch;
    const PlaceSettings& settings = ps.settings();
    const glm::vec3 extent = ps.scene().bounds.max - ps.scene().bounds.min;
    const float coarsest = std::max({extent.x, extent.y, extent.z});
    const float finest = ps.freeSpace().grid().voxel;
    int trials = 0;
    auto lattice = [&](float spacing) {
        ++trials;
        if (progress) progress->advance();
        return GridTrial{spacing, gridProbes(ps, spacing), 0.0};
    };
    auto measured = [&](GridTrial t) {
        if (t.probes.size() <= kMaxGridProbes) t.coverage = coverageOf(ps, t.probes).first;
        return t;
    };

    // With a budget: the finest lattice within it (the count falls as the spacing grows).
    GridTrial best;
    if (settings.budget > 0) {
        float fine = finest, coarse = coarsest;
        GridTrial within = lattice(coarse);
        if (within.probes.size() <= std::size_t(settings.budget)) {
            for (int k = 0; k < 2 * kBisections; ++k) {
                const float mid = std::sqrt(fine * coarse);
                GridTrial t = lattice(mid);
                if (t.probes.size() <= std::size_t(settings.budget)) {
                    coarse = mid;
                    within = std::move(t);
                } else {
                    fine = mid;
                }
            }
        }
        best = measured(std::move(within));
        // The count is not monotonic in the spacing (lattice points fall in and out of walls), so the
        // finest lattice within the budget may use far less of it: spacings around it are tried too,
        // and the one that covers most within the budget is kept.
        const float around = best.spacing;
        for (int k = -kBudgetTrials; k <= kBudgetTrials; ++k) {
            if (k == 0) continue;
            const float spacing = around * std::pow(1.5f, float(k) / float(kBudgetTrials));
            if (spacing < finest) continue;
            GridTrial t = lattice(spacing);
            if (t.probes.size() > std::size_t(settings.budget)) continue;
            t = measured(std::move(t));
            if (t.coverage > best.coverage) best = std::move(t);
        }
    }
    // The coarsest lattice that reaches the target: halve until it does, then bisect.
    if (settings.budget == 0 || best.coverage >= settings.target) {
        const float start = settings.budget > 0 ? best.spacing : coarsest;
        GridTrial good = settings.budget > 0 ? best : measured(lattice(start));
        float bad = start;
        if (settings.budget == 0) {
            while (good.coverage < settings.target && good.spacing / 2.0f >= finest) {
                GridTrial finer = lattice(good.spacing / 2.0f);
                if (finer.probes.size() > kMaxGridProbes) break;  // keep the finest lattice measured
                bad = good.spacing;
                good = measured(std::move(finer));
            }
        } else {
            bad = coarsest;  // look for a coarser lattice that still reaches the target
        }
        if (good.coverage >= settings.target) {
            for (int k = 0; k < kBisections && bad > good.spacing * 1.02f; ++k) {
                GridTrial t = measured(lattice(std::sqrt(good.spacing * bad)));
                if (t.coverage >= settings.target)
                    good = std::move(t);
                else
                    bad = t.spacing;
            }
        }
        best = std::move(good);
    }
    const double searchSeconds = watch.restart();
    Placement result = evaluate(ps, best.probes, "grid");
    result.timings.emplace(result.timings.end() - 1, "search", searchSeconds);
    result.figures = {{"spacing", best.spacing},
                      {"lattices_tried", trials},
                      {"reached_target", result.coverage >= settings.target ? 1.0 : 0.0},
                      {"max_lattice_probes", double(kMaxGridProbes)}};
    return result;
}

}  // namespace cubeao::placement
