// Coverage feedback (thesis 003, made better; DESIGN.md §4 "Placement"): walk a camera path one frame
// at a time; per frame count the surface pixels no probe covers (coverage.h's criterion), and while
// the frame is below the target add the candidate voxel the uncovered pixels' surface points vote
// for (normal voting restricted to what this frame shows), not simply the camera's eye. The viewer
// feeds the same class live.
#pragma once

#include <cstdint>
#include <deque>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

#include "cubeao/core/camera.h"
#include "cubeao/placement/placement.h"

namespace cubeao::placement {

class GpuCoverageCount;

struct FeedbackSettings {
    int width = 64, height = 36;  // pixels per frame the coverage is counted at
    int maxPerFrame = 4;          // probes one frame may add
};

// One frame's surface pixels as the coverage count sees them: position and normal turned to the eye.
struct FramePixels {
    std::vector<SurfaceSample> points;  // area 1 each: pixels count equally
    std::size_t pixels = 0;             // all pixels, background included
};

FramePixels tracePixels(const EmbreeScene& embree, const PinholeCamera& camera);

class CoverageFeedback {
public:
    CoverageFeedback(const PlacementScene& ps, FeedbackSettings settings);

    struct FrameResult {
        double before = 1.0, after = 1.0;  // covered share of the frame's surface pixels
        int added = 0;
        // Why the frame stays below the target with no probe added for it (a static string; null when
        // it reached the target or gained a probe): no free space at all, nothing free sees what is
        // uncovered, or the voted voxel is hidden from every pixel that voted.
        const char* stalled = nullptr;
    };
    FrameResult addFrame(const PinholeCamera& camera);

    // The same with the count on the GPU (gpu_coverage.h), as the viewer runs it: queues this frame's
    // count and returns at once with the frames whose counts have come back meanwhile (earlier ones,
    // in order). Only a frame the GPU finds below the target is traced on the CPU, where its
    // uncovered pixels vote as in addFrame; probes added since its count are taken into account.
    std::vector<FrameResult> addFrame(const PinholeCamera& camera, GpuCoverageCount& gpu);
    // Waits for the counts still in flight and handles them (the end of a walk).
    std::vector<FrameResult> drain(GpuCoverageCount& gpu);
    std::size_t framesTraced() const { return framesTraced_; }

    // Covered share of the pixels (1 when none shows a surface) with the current probes: the count the
    // GPU count is checked against.
    double frameCoverage(const FramePixels& pixels) const;
    const std::vector<glm::vec3>& probes() const { return probes_; }
    // Probes placed elsewhere (a cache the viewer opened) that the counts should see as covering.
    void addProbes(std::span<const glm::vec3> probes) { probes_.insert(probes_.end(), probes.begin(), probes.end()); }

private:
    std::vector<std::uint8_t> coveredMask(const FramePixels& pixels) const;

    const PlacementScene& ps_;
    FeedbackSettings settings_;
    FrameResult handleCount(const PinholeCamera& camera, double gpuCoverage);

    std::vector<glm::vec3> probes_;
    std::deque<PinholeCamera> inFlight_;  // cameras of the GPU counts not yet handled, oldest first
    std::size_t framesTraced_ = 0;
};

// Runs CoverageFeedback over every frame of `path` (at settings' resolution) and reports the probes
// with coverage.h's definition. With `gpu` the frames are counted there (a current GL context needed).
Placement placeCoverage(const PlacementScene& ps, const CameraPath& path, FeedbackSettings settings = {},
                        Progress* progress = nullptr, GpuCoverageCount* gpu = nullptr);

}  // namespace cubeao::placement
