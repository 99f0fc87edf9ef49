// Live probe placement for the walkthrough viewer (issue 14): coverage feedback watches the frames the
// viewer shows (CoverageFeedback with its GPU count, coverage_feedback.h), each probe it places is baked
// with the fast GPU estimator in time slices of a stated ms budget per frame (GpuBaker's stepped bake,
// bake/gpu_bake.h) and handed to the projection pass as soon as it is ready, and while the camera stays
// still the fast probes are re-baked one at a time with `traced` and replace their fast versions. The
// frame never waits for the GPU; save() writes what has been baked as a cache, atomically.
// Needs a current GL 4.5 context for its whole life (it owns two GpuBakers and a GpuCoverageCount).
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

#include "cubeao/cache/cache_file.h"
#include "cubeao/core/camera.h"
#include "cubeao/placement/coverage_feedback.h"
#include "cubeao/runtime/probe_id.h"

namespace cubeao {
struct BakeSettings;  // bake/bake_settings.h (cubeao_offline, a private dependency of this library)
class ProbeProjectionPass;
}  // namespace cubeao

namespace cubeao::placement {

class CoverageFeedback;
class PlacementScene;

// The time slicing of the bake work: a token bucket. Each frame adds msPerFrame to the balance, capped
// at msPerFrame (a frame without bake work banks nothing for a burst later); a step may run while the
// balance is positive, and its measured wall time is subtracted. One step may overrun the balance; the
// frames after it then skip until the balance is positive again, so over N frames the bake spends at
// most N·msPerFrame plus one step. Pure arithmetic: tests feed it given step costs.
class BakeBudget {
public:
    explicit BakeBudget(double msPerFrame) : msPerFrame_(msPerFrame) {}
    void newFrame();                            // balance = min(balance + msPerFrame, msPerFrame)
    bool canStep() const { return balance_ > 0.0; }
    void spend(double ms) { balance_ -= ms; }   // a step's measured wall time
    double balance() const { return balance_; }
    double msPerFrame() const { return msPerFrame_; }

private:
    double msPerFrame_ = 0.0, balance_ = 0.0;
};

struct LiveSettings {
    // What places the probes: Error, the predicted AO error of the walk so far (error_feedback.h, the
    // objective of offline voting; counted on the CPU), or Coverage, the share of each frame's pixels a
    // probe covers finely (coverage_feedback.h, counted on the GPU).
    enum class Objective { Error, Coverage };
    Objective objective = Objective::Error;
    FeedbackSettings feedback;        // count resolution (the count's aspect: choose the window's), probes per frame
    int countEveryFrames = 4;         // submit a coverage count every N frames (1 = every frame)
    double bakeMsPerFrame = 4.0;      // BakeBudget: average wall ms per frame spent issuing bake steps
    int idleFramesBeforeRebake = 30;  // idle this many frames in a row → re-bake fast probes with traced;
                                      // < 0: never (no traced baker is built)
    float nearPlane = 0.05f;          // the GPU count's camera G-buffer clip distance (CameraPath::nearPlane)
    float farPlane = 1e30f;           // Error: what a frame shows lies within this distance (CameraPath::farPlane)
};

class LivePlacement {
public:
    // `ps`: the scene, its coverage criterion and free space (the coverage feedback's; it must outlive
    // this). `fast` and `traced`: resolved bake settings (resolveBakeSettings), normally hsplit and
    // traced; they must make the same cache sections and radius (res, depthRes, depth format, radius,
    // falloff; cubeao::Error naming the differences otherwise), so a re-baked probe replaces its fast
    // version in the same pass. Builds both GpuBakers and the GPU count (shader compilation, mesh and
    // BVH upload): construct it before the walk, not inside a frame.
    LivePlacement(const PlacementScene& ps, const BakeSettings& fast, const BakeSettings& traced,
                  LiveSettings settings);
    ~LivePlacement();
    LivePlacement(const LivePlacement&) = delete;
    LivePlacement& operator=(const LivePlacement&) = delete;

    // The parameters of the fast bake with the scene's hash: what the projection pass is built with
    // (ProbeProjectionPass's empty-start constructor) and what save() writes unless every probe is traced.
    CacheParams cacheParams() const;

    // Probes of a cache the viewer opened, already added to the pass under `passIds` (one per probe, in
    // order; a pass built from the cache gives probe i the id i). `params` is that cache's: it must equal
    // the fast or the traced bake's parameters (cubeao::Error listing the differences to the fast ones
    // otherwise; also for a probe index already known). They are saved with the rest, re-baked with
    // traced when idle if they are fast ones, and new probes get indices above theirs.
    // The coverage counts see them as covering (CoverageFeedback::addProbes). Call before the first
    // frame() (cubeao::Error otherwise).
    void adopt(std::vector<ProbeRecord> probes, std::span<const ProbeId> passIds, const CacheParams& params);

    // Once per frame, with the camera the frame shows and whether the viewer is idle (camera still):
    //  - Error: every countEveryFrames frames (unless it shows exactly the view counted last) adds the
    //    frame to the walk so far and places what the predicted error asks for, on the CPU at once
    //    (ErrorFeedback::addFrame; tens of ms on a large building). Coverage:
    //  - every countEveryFrames frames submits a GPU coverage count of `camera` at the feedback
    //    resolution (eye, basis and field of view kept; the count's aspect is feedback.width/height)
    //    unless it shows exactly the view counted last (a camera standing still is counted once). While
    //    GpuCoverageCount::kSlots counts are in flight and the oldest is not done (submitting would
    //    wait; a fence of its own tells) the count is put off to the next frame. Counts that
    //    have come back are handled (a frame below the target is traced and voted on, on the CPU, and
    //    may place probes), and new probes join the bake queue;
    //  - spends the BakeBudget on bake steps: the fast bake of the queued probes first, in placement
    //    order; otherwise a traced re-bake already begun; otherwise, after idleFramesBeforeRebake idle
    //    frames, the next fast probe's re-bake. A poll of a fence not yet signalled ends the frame's
    //    bake work (the GPU is busy with it anyway);
    //  - a finished fast probe goes to the pass (addProbe); a finished re-bake replaces its fast version
    //    (removeProbe, then addProbe).
    // Never waits for the GPU.
    void frame(const PinholeCamera& camera, bool idle, ProbeProjectionPass& pass);

    // End of a scripted walk, and the tests: handles every count still in flight (waits for them),
    // bakes every queued probe with the fast bake and finishes a re-bake in progress (waits for the
    // GPU), handing everything to the pass. Starts no new re-bake.
    void drain(ProbeProjectionPass& pass);

    struct Stats {
        std::size_t placed = 0;   // probes the coverage feedback placed (adopted ones not counted)
        std::size_t baked = 0;    // fast bakes handed to the pass
        std::size_t rebaked = 0;  // traced re-bakes that replaced a fast version (adopted ones included)
        std::size_t toRebake = 0; // probes in the pass still in their fast version (what idling would re-bake)
        std::size_t queued = 0;   // placed, fast bake not finished yet (the one in progress included)
        std::size_t inPass = 0;   // probes this object has in the pass (adopted ones included)
        std::size_t framesCounted = 0;  // coverage counts handled
        double coverage = 1.0;    // Coverage: covered share of the newest counted frame, after the probes it placed
        double predictedMae = 0.0;  // Error: predicted MAE of the walk so far, after the probes it placed
        const char* stalled = nullptr;  // why the newest counted frame below the target got no probe (null: it
                                        // did not stall; coverage_feedback.h FrameResult::stalled)
        double bakeMsLastFrame = 0.0;  // wall ms of the bake steps issued in the last frame()
        double bakeMsMean = 0.0;       // the same, mean over every frame() so far
        double stepMsMax = 0.0;        // the longest single step so far (what one frame may overrun by)
        double countMsLastFrame = 0.0; // wall ms of the last frame()'s coverage count: submitting, and the
                                       // CPU tracing and voting of a returned frame below the target
    };
    Stats stats() const;

    // The coverage feedback (its probes, frameCoverage for a walk's report): with the Error objective
    // it places nothing but holds every probe, so its frameCoverage reports the same.
    const CoverageFeedback& feedback() const;

    // Every probe baked so far, by index (the traced version where re-baked; adopted probes as adopted),
    // written atomically with writeCache: a viewer killed mid-walk keeps the previous file whole.
    // The header's parameters are the traced bake's only when every saved probe is traced, else the fast
    // bake's: a cache never claims `traced` for a probe that is not. Returns the probe count.
    std::size_t save(const std::filesystem::path& path) const;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace cubeao::placement
