#include "cubeao/placement/error_feedback.h"

#include <algorithm>
#include <limits>

#include <glm/common.hpp>

#include "cubeao/core/progress.h"
#include "cubeao/core/stopwatch.h"
#include "site_greedy.h"

namespace cubeao::placement {
namespace {

// Per probe a frame places: how many sites are bounded (by their gain as known: votes at first) and
// how many of the best bounds priced exactly (SiteGreedy::bestOfFew). Along Sibenik's / FZK-Haus's
// walks (`place --method live`, dev VM beside a test run): 16 and 3 give 20 / 21 probes at predicted
// MAE 0.00946 / 0.00498, the longest counted frame 0.56 / 0.67 s; placeVoting's full lazy greedy 20 /
// 20 at 0.00932 / 0.00496 but 4.4 s for one frame (1,653 sites bounded on Sibenik); 8 and 2: 19 / 20
// at 0.0095 / 0.00511, 0.29 / 0.52 s; the votes' best 3 priced exactly, as before the depth test
// joined "served": 28 / 27 at 0.0104 / 0.0058.
constexpr std::size_t kBoundedPerRound = 16;
constexpr std::size_t kExactPerRound = 3;

// Every free voxel some sample voted for: the eyes join as the frames come.
std::vector<Site> votedVoxels(const PlacementScene& ps) {
    const PlacementScene::Votes& votes = ps.votes();
    const FreeSpace& space = ps.freeSpace();
    std::vector<Site> sites;
    for (std::size_t c = 0; c + 1 < votes.offsets.size(); ++c)
        if (votes.offsets[c + 1] > votes.offsets[c]) sites.push_back({space.candidatePosition(c), std::int64_t(c)});
    return sites;
}

}  // namespace

ErrorFeedback::ErrorFeedback(const PlacementScene& ps)
    : ps_(ps), error_(ps, /*fromWalk=*/false), greedy_(std::make_unique<SiteGreedy>(ps, votedVoxels(ps))) {}

ErrorFeedback::~ErrorFeedback() = default;

std::size_t ErrorFeedback::exactEvaluations() const { return greedy_->exactEvaluations(); }
std::size_t ErrorFeedback::boundEvaluations() const { return greedy_->boundEvaluations(); }

void ErrorFeedback::addProbes(std::span<const glm::vec3> probes) {
    for (const glm::vec3& p : probes) {
        error_.add(ps_.views(p));
        probes_.push_back(p);
    }
}

ErrorFeedback::FrameResult ErrorFeedback::addFrame(const PinholeCamera& camera, float nearPlane, float farPlane,
                                                   int maxPerFrame) {
    ++frames_;
    const std::vector<float> share = imageShare(ps_.embree(), ps_.samples(), std::span(&camera, 1), nearPlane, farPlane);
    error_.addWeights(share);
    FrameResult r;
    r.before = r.after = error_.mae();
    const PlaceSettings& settings = ps_.settings();
    const std::size_t budget =
        settings.budget > 0 ? std::size_t(settings.budget) : std::numeric_limits<std::size_t>::max();
    const FreeSpace& space = ps_.freeSpace();
    // The camera's own eye is a site where it keeps a tenth of the clearance from geometry, as
    // placeVoting's eye sites; one per voxel the walk passes through, since every site keeps its views
    // and a long walk in the viewer would otherwise add one each counted frame without bound.
    const VoxelGrid& grid = space.grid();
    const glm::ivec3 cell(glm::floor((camera.eye - grid.origin) / grid.voxel));
    if (space.distanceToSurface(camera.eye) >= 0.1f * space.clearance() &&
        (!grid.contains(cell) || eyeCells_.insert(grid.index(cell)).second))
        greedy_->addSite({camera.eye, -1});
    // Worth a probe: removes at least kAutomaticStop of the MAE so far, or anything while it is above
    // --target-error.
    auto enough = [&](double gain) {
        return settings.targetError > 0.0f ? gain > 0.0 : gain >= kAutomaticStop * error_.mae() && gain > 0.0;
    };
    while (r.added < maxPerFrame && probes_.size() < budget) {
        if (settings.targetError > 0.0f && error_.mae() <= settings.targetError) break;
        const std::optional<SiteGreedy::Pick> pick = greedy_->bestOfFew(error_, kBoundedPerRound, kExactPerRound);
        if (!pick) {
            // Nothing would help: a stall when this frame shows surfaces and there is no free space at
            // all, or shows samples no probe serves.
            bool shows = false, unserved = false;
            for (std::size_t i = 0; i < share.size() && !unserved; ++i) {
                if (!(share[i] > 0.0f)) continue;
                shows = true;
                unserved = ps_.relevant()[i] && ps_.occlusion()[i] > 0.0f &&
                           error_.current(std::uint32_t(i)) >= ps_.expectedError(std::uint32_t(i), INFINITY);
            }
            if (shows && space.candidates().empty())
                r.stalled = "no free space: no voxel is reached from the camera or the outside";
            else if (unserved)
                r.stalled = "no free voxel or eye sees what this frame shows unserved";
            break;
        }
        if (!enough(pick->gain)) break;
        const glm::vec3 position = greedy_->site(pick->site).position;
        greedy_->take(pick->site);
        if (std::find(probes_.begin(), probes_.end(), position) != probes_.end()) continue;  // adopted there
        error_.add(greedy_->served(pick->site));
        probes_.push_back(position);
        ++r.added;
        r.after = error_.mae();
    }
    return r;
}

Placement placeFeedback(const PlacementScene& ps, const CameraPath& path, int everyFrames, int maxPerFrame,
                        Progress* progress) {
    Stopwatch watch;
    ErrorFeedback feedback(ps);
    const std::size_t step = std::size_t(std::max(everyFrames, 1));
    std::size_t stalled = 0;
    double frameMsMax = 0.0;
    for (std::size_t f = 0; f < path.frames.size(); f += step) {
        // The aspect and field of view are the walk's; the resolution only sets the aspect here.
        const PinholeCamera camera(path, f, path.width, path.height);
        Stopwatch frame;
        stalled += feedback.addFrame(camera, path.nearPlane, path.farPlane, maxPerFrame).stalled != nullptr;
        frameMsMax = std::max(frameMsMax, 1e3 * frame.restart());
        if (progress) progress->advance(step);
    }
    const double walkSeconds = watch.restart();
    Placement result = evaluate(ps, feedback.probes(), "live");
    result.timings.emplace(result.timings.end() - 1, "walk", walkSeconds);
    result.stop = "walk_end";
    result.figures = {{"frames_counted", double(feedback.frames())},
                      {"every_frames", double(step)},
                      {"frames_stalled", double(stalled)},
                      {"exact_evaluations", double(feedback.exactEvaluations())},
                      {"bound_evaluations", double(feedback.boundEvaluations())},
                      {"frame_ms_max", frameMsMax},
                      {"predicted_mae_walk_so_far", feedback.predictedMae()}};
    return result;
}

}  // namespace cubeao::placement
