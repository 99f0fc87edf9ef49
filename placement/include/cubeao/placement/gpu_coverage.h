// The GPU twin of CoverageFeedback::frameCoverage (coverage_feedback.h): per camera frame, the surface
// pixels no probe covers, by coverage.h's definition (shaders/placement/coverage_count.comp: the shared
// kernel probeMayCoverPoint, then a BVH occlusion ray from the point to the probe), counted without
// stalling the caller. submit() queues a frame (camera G-buffer, count, the two counters into a
// read-back ring, gl/sync.h); poll() hands back finished frames in submission order without
// blocking; wait() blocks for the oldest. The CPU count traces primary rays with Embree, this one
// rasterises them, so the two differ only at silhouettes (tests/placement/test_placement.cpp measures it).
// Needs a current GL 4.5 context for its whole life (gl/handles.h).
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>

#include <glm/vec3.hpp>

namespace cubeao {
struct PinholeCamera;
struct Scene;
}  // namespace cubeao

namespace cubeao::placement {

struct CoverageCriterion;

class GpuCoverageCount {
public:
    // Frames in flight at most: submit() blocks on the oldest when all slots are in use.
    static constexpr std::size_t kSlots = 3;

    struct Result {
        std::uint64_t ticket = 0;     // what submit() returned for the frame
        std::uint64_t pixels = 0;     // pixels showing geometry
        std::uint64_t uncovered = 0;  // of those, the ones no probe covers
        // Covered share of the surface pixels, 1 when none shows a surface (as frameCoverage).
        double coverage() const { return pixels ? 1.0 - double(uncovered) / double(pixels) : 1.0; }
    };

    // Uploads the mesh to a camera G-buffer and the scene's BVH, builds the program. nearPlane: the
    // G-buffer's clip distance (CameraPath::nearPlane); the CPU count has none, so keep it small.
    explicit GpuCoverageCount(const Scene& scene, float nearPlane = 0.05f);
    ~GpuCoverageCount();
    GpuCoverageCount(const GpuCoverageCount&) = delete;
    GpuCoverageCount& operator=(const GpuCoverageCount&) = delete;

    // Queues the count of one frame (camera.width × camera.height pixels) for these probes and
    // returns its ticket (0, 1, 2, ... in submission order). Returns at once unless kSlots frames are
    // still in flight: then it waits for the oldest (its result stays queued for poll()/wait()).
    // surfaceEpsilon: EmbreeScene::surfaceEpsilon(), how far the ray to a probe starts off the surface.
    std::uint64_t submit(const PinholeCamera& camera, std::span<const glm::vec3> probes,
                         const CoverageCriterion& criterion, float surfaceEpsilon);

    // The oldest submitted frame's result if the GPU has finished it, without blocking; each result is
    // returned once, in ticket order.
    std::optional<Result> poll();
    // The oldest submitted frame's result, blocking until the GPU has finished it. Throws cubeao::Error
    // when nothing is pending.
    Result wait();
    // Frames submitted and not yet returned by poll() or wait().
    std::size_t pending() const;
    // Whether submit() would wait now: kSlots frames on the GPU and the oldest not finished.
    bool submitWouldWait();

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace cubeao::placement
