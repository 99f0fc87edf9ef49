#include "cubeao/placement/error_feedback.h"

#include <algorithm>
#include <limits>

#include "cubeao/core/progress.h"
#include "cubeao/core/stopwatch.h"

namespace cubeao::placement {
namespace {

// The best few voxels by estimated gain are evaluated exactly: the votes are an unbiased but noisy
// estimate (a few rays per sample), and one exact evaluation costs a visibility ray per relevant sample.
constexpr std::size_t kExactPerRound = 3;

}  // namespace

ErrorFeedback::ErrorFeedback(const PlacementScene& ps)
    : ps_(ps), error_(ps, /*fromWalk=*/false), taken_(ps.freeSpace().candidates().size(), 0) {}

const std::vector<SampleView>& ErrorFeedback::viewsOf(std::uint32_t candidate) {
    auto it = views_.find(candidate);
    if (it == views_.end()) {
        it = views_.emplace(candidate, ps_.views(ps_.freeSpace().candidatePosition(candidate))).first;
        ++evaluations_;
    }
    return it->second;
}

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
    const PlacementScene::Votes& votes = ps_.votes();
    const FreeSpace& space = ps_.freeSpace();
    const double total = error_.totalWeight();
    // Worth a probe: removes at least kAutomaticStop of the MAE so far, or anything while it is above
    // --target-error.
    auto enough = [&](double gain) {
        return settings.targetError > 0.0f ? gain > 0.0 : gain >= kAutomaticStop * error_.mae() && gain > 0.0;
    };
    while (r.added < maxPerFrame && probes_.size() < budget) {
        if (settings.targetError > 0.0f && error_.mae() <= settings.targetError) break;
        // Every voted voxel's gain estimated from its votes (as placeVoting's lazy greedy does).
        std::vector<std::pair<double, std::uint32_t>> estimates;
        for (std::size_t c = 0; c + 1 < votes.offsets.size(); ++c) {
            if (taken_[c]) continue;
            double g = 0.0;
            for (std::uint64_t v = votes.offsets[c]; v < votes.offsets[c + 1]; ++v) {
                const std::uint32_t s = votes.voters[v];
                const float w = error_.weight(s);
                if (!(w > 0.0f)) continue;
                const float e = ps_.expectedError(s, votes.area[v]);
                if (e < error_.current(s)) g += double(votes.scale[v]) * double(w) * double(error_.current(s) - e);
            }
            if (g > 0.0) estimates.emplace_back(total > 0.0 ? g / total : 0.0, std::uint32_t(c));
        }
        const std::size_t exact = std::min(kExactPerRound, estimates.size());
        std::partial_sort(estimates.begin(), estimates.begin() + std::ptrdiff_t(exact), estimates.end(),
                          [](const auto& a, const auto& b) { return a.first > b.first; });
        // The best exact gain among the top estimates and the camera's own eye (a site where the walk
        // stands, if it keeps a tenth of the clearance from geometry, as placeVoting's eye sites).
        double best = 0.0;
        glm::vec3 position{0.0f};
        std::int64_t bestCandidate = -1;
        const std::vector<SampleView>* bestViews = nullptr;
        for (std::size_t k = 0; k < exact; ++k) {
            const std::vector<SampleView>& views = viewsOf(estimates[k].second);
            const double g = error_.gain(views);
            if (g > best) best = g, bestCandidate = estimates[k].second, bestViews = &views;
        }
        std::vector<SampleView> eyeViews;
        const bool eyeFree = space.distanceToSurface(camera.eye) >= 0.1f * space.clearance() &&
                             std::find(probes_.begin(), probes_.end(), camera.eye) == probes_.end();
        if (eyeFree) {
            eyeViews = ps_.views(camera.eye);
            ++evaluations_;
            const double g = error_.gain(eyeViews);
            if (g > best) best = g, bestCandidate = -1, bestViews = &eyeViews;
        }
        if (!bestViews || !enough(best)) {
            if (!bestViews) {
                // Nothing would help: a stall when this frame shows surfaces and there is no free space
                // at all, or shows samples no probe serves.
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
            }
            break;
        }
        if (bestCandidate >= 0) {
            position = space.candidatePosition(std::size_t(bestCandidate));
            taken_[std::size_t(bestCandidate)] = 1;
        } else {
            position = camera.eye;
        }
        if (std::find(probes_.begin(), probes_.end(), position) != probes_.end()) break;  // an eye on a voxel centre
        error_.add(*bestViews);
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
    for (std::size_t f = 0; f < path.frames.size(); f += step) {
        // The aspect and field of view are the walk's; the resolution only sets the aspect here.
        const PinholeCamera camera(path, f, path.width, path.height);
        stalled += feedback.addFrame(camera, path.nearPlane, path.farPlane, maxPerFrame).stalled != nullptr;
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
                      {"predicted_mae_walk_so_far", feedback.predictedMae()}};
    return result;
}

}  // namespace cubeao::placement
