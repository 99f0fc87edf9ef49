// Live placement on the predicted error (issue 31; DESIGN.md §4 "Placement"): the objective of offline
// voting (placement.h ExpectedError, error_model.h), over the walk seen so far instead of the whole
// walk. Each frame the viewer counts adds its image shares to the samples' weights; then, while the
// best site would remove at least kAutomaticStop of the walk-so-far's predicted MAE (or, with
// --target-error, while the MAE is above it), the frame places that probe. Sites are the free voxels
// the samples voted for and the eyes of the frames so far, priced as offline voting prices them
// (site_greedy.h: votes, then the ray-only bound, then the exact gain with the depth test) but at a
// bounded cost per probe, since it runs inside a frame (SiteGreedy::bestOfFew). The
// viewer runs it frame by frame (live_placement.h); placeFeedback runs it over a recorded walk, so the
// live objective's probes can be measured without a window.
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <unordered_set>
#include <vector>

#include <glm/vec3.hpp>

#include "cubeao/core/camera.h"
#include "cubeao/placement/placement.h"

namespace cubeao {
class Progress;
}

namespace cubeao::placement {

class SiteGreedy;

class ErrorFeedback {
public:
    // `ps` must outlive this object; its settings give the budget and the target error.
    explicit ErrorFeedback(const PlacementScene& ps);
    ~ErrorFeedback();

    struct FrameResult {
        double before = 0.0, after = 0.0;  // predicted MAE of the walk so far (this frame included)
        int added = 0;
        // Why the frame shows samples no probe serves and got no probe for them (a static string; null
        // otherwise): no free space at all, or no free voxel sees them.
        const char* stalled = nullptr;
    };
    // Adds `camera`'s frame (its aspect and field of view; the resolution does not matter) and places
    // at most `maxPerFrame` probes for the walk so far.
    FrameResult addFrame(const PinholeCamera& camera, float nearPlane, float farPlane, int maxPerFrame);

    const std::vector<glm::vec3>& probes() const { return probes_; }
    // Probes placed elsewhere (a cache the viewer opened): they serve from the start.
    void addProbes(std::span<const glm::vec3> probes);
    double predictedMae() const { return error_.mae(); }
    std::size_t frames() const { return frames_; }
    std::size_t exactEvaluations() const;  // sites priced with the depth test
    std::size_t boundEvaluations() const;  // sites priced by the samples their rays reach

private:
    const PlacementScene& ps_;
    ExpectedError error_;
    std::vector<glm::vec3> probes_;
    std::unique_ptr<SiteGreedy> greedy_;  // the voted voxels and the eyes seen so far
    std::unordered_set<std::size_t> eyeCells_;  // voxels an eye site stands in
    std::size_t frames_ = 0;
};

// ErrorFeedback over every `everyFrames`-th frame of `path` (the viewer counts every 4th), reported
// like the other methods (method "live").
Placement placeFeedback(const PlacementScene& ps, const CameraPath& path, int everyFrames = 4,
                        int maxPerFrame = 4, Progress* progress = nullptr);

}  // namespace cubeao::placement
