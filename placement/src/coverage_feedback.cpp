#include "cubeao/placement/coverage_feedback.h"

#include <algorithm>
#include <limits>
#include <optional>

#include <glm/geometric.hpp>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "cubeao/core/progress.h"
#include "cubeao/core/stopwatch.h"
#include "cubeao/placement/gpu_coverage.h"
#include "cubeao/reference/embree_scene.h"
#include "votes.h"

namespace cubeao::placement {

FramePixels tracePixels(const EmbreeScene& embree, const PinholeCamera& camera) {
    FramePixels out;
    out.pixels = std::size_t(camera.width) * std::size_t(camera.height);
    std::vector<SurfaceSample> all(out.pixels);
    std::vector<std::uint8_t> hit(out.pixels, 0);
    tbb::parallel_for(tbb::blocked_range<int>(0, camera.height), [&](const auto& rows) {
        for (int y = rows.begin(); y != rows.end(); ++y)
            for (int x = 0; x < camera.width; ++x) {
                const glm::vec3 dir = camera.rayDirection(x, y);
                const RayHit h = embree.intersect(camera.eye, dir, 0.0f, std::numeric_limits<float>::infinity());
                if (!h.hit) continue;
                const std::size_t i = std::size_t(y) * std::size_t(camera.width) + std::size_t(x);
                const glm::vec3 n = glm::dot(h.normal, dir) < 0.0f ? h.normal : -h.normal;  // the side the eye sees
                all[i] = {camera.eye + dir * h.t, glm::normalize(n), 1.0f, h.primitive};
                hit[i] = 1;
            }
    });
    for (std::size_t i = 0; i < all.size(); ++i)
        if (hit[i]) out.points.push_back(all[i]);
    return out;
}

namespace {

// Share of a frame's surface pixels that a probe covers (mask from coveredMask, not empty).
double coveredShare(const std::vector<std::uint8_t>& covered) {
    return double(std::count(covered.begin(), covered.end(), 1)) / double(covered.size());
}

}  // namespace

CoverageFeedback::CoverageFeedback(const PlacementScene& ps, FeedbackSettings settings)
    : ps_(ps), settings_(settings) {}

std::vector<std::uint8_t> CoverageFeedback::coveredMask(const FramePixels& pixels) const {
    std::vector<std::uint8_t> covered(pixels.points.size(), 0);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, pixels.points.size(), 64), [&](const auto& range) {
        for (std::size_t i = range.begin(); i != range.end(); ++i)
            for (const glm::vec3& p : probes_)
                if (probeCovers(ps_.embree(), ps_.criterion(), p, pixels.points[i])) {
                    covered[i] = 1;
                    break;
                }
    });
    return covered;
}

double CoverageFeedback::frameCoverage(const FramePixels& pixels) const {
    if (pixels.points.empty()) return 1.0;
    return coveredShare(coveredMask(pixels));
}

CoverageFeedback::FrameResult CoverageFeedback::addFrame(const PinholeCamera& camera) {
    ++framesTraced_;
    const FramePixels pixels = tracePixels(ps_.embree(), camera);
    FrameResult r;
    if (pixels.points.empty()) return r;
    std::vector<std::uint8_t> covered = coveredMask(pixels);
    r.before = r.after = coveredShare(covered);
    const PlaceSettings& settings = ps_.settings();
    const std::size_t budget =
        settings.budget > 0 ? std::size_t(settings.budget) : std::numeric_limits<std::size_t>::max();
    while (r.after < settings.target && r.added < settings_.maxPerFrame && probes_.size() < budget) {
        // The uncovered pixels vote: the candidate most of them would see at a small enough texel.
        std::vector<std::uint8_t> uncovered(covered.size());
        for (std::size_t i = 0; i < covered.size(); ++i) uncovered[i] = covered[i] ? 0 : 1;
        const PlacementScene::Votes votes =
            castVotes(ps_.embree(), ps_.freeSpace(), pixels.points, uncovered, ps_.criterion(), settings.votingRays,
                      settings.seed ^ std::uint32_t(probes_.size()), nullptr);
        std::size_t best = votes.weight.size();
        std::uint64_t bestVoters = 0;
        for (std::size_t c = 0; c < votes.weight.size(); ++c) {
            const std::uint64_t voters = votes.offsets[c + 1] - votes.offsets[c];
            if (voters > bestVoters || (voters == bestVoters && voters > 0 && votes.weight[c] > votes.weight[best]))
                best = c, bestVoters = voters;
        }
        if (bestVoters == 0) {
            r.stalled = ps_.freeSpace().candidates().empty()
                            ? "no free space: no voxel is reached from the camera or the outside"
                            : "no free voxel sees the uncovered pixels with a small enough texel";
            break;
        }
        const glm::vec3 probe = ps_.freeSpace().candidatePosition(best);
        std::size_t gained = 0;
        for (std::size_t i = 0; i < covered.size(); ++i)
            if (!covered[i] && probeCovers(ps_.embree(), ps_.criterion(), probe, pixels.points[i])) {
                covered[i] = 1;
                ++gained;
            }
        if (gained == 0) {  // the votes' voxel centre is hidden from every voter: stop for this frame
            r.stalled = "the voxel the uncovered pixels voted for is hidden from them";
            break;
        }
        probes_.push_back(probe);
        ++r.added;
        r.after = coveredShare(covered);
    }
    return r;
}

CoverageFeedback::FrameResult CoverageFeedback::handleCount(const PinholeCamera& camera, double gpuCoverage) {
    if (gpuCoverage >= ps_.settings().target) return {gpuCoverage, gpuCoverage, 0};
    FrameResult r = addFrame(camera);
    r.before = std::min(r.before, gpuCoverage);  // probes added since the count can only have helped
    return r;
}

std::vector<CoverageFeedback::FrameResult> CoverageFeedback::addFrame(const PinholeCamera& camera,
                                                                      GpuCoverageCount& gpu) {
    gpu.submit(camera, probes_, ps_.criterion(), ps_.embree().surfaceEpsilon());
    inFlight_.push_back(camera);
    std::vector<FrameResult> handled;
    while (const std::optional<GpuCoverageCount::Result> r = gpu.poll()) {
        handled.push_back(handleCount(inFlight_.front(), r->coverage()));
        inFlight_.pop_front();
    }
    return handled;
}

std::vector<CoverageFeedback::FrameResult> CoverageFeedback::drain(GpuCoverageCount& gpu) {
    std::vector<FrameResult> handled;
    while (!inFlight_.empty()) {
        const GpuCoverageCount::Result r = gpu.wait();
        handled.push_back(handleCount(inFlight_.front(), r.coverage()));
        inFlight_.pop_front();
    }
    return handled;
}

Placement placeCoverage(const PlacementScene& ps, const CameraPath& path, FeedbackSettings settings,
                        Progress* progress, GpuCoverageCount* gpu) {
    Stopwatch watch;
    CoverageFeedback feedback(ps, settings);
    double before = 0.0, after = 0.0;
    auto tally = [&](const CoverageFeedback::FrameResult& r) {
        before += r.before;
        after += r.after;
        if (progress) progress->advance();
    };
    for (std::size_t f = 0; f < path.frames.size(); ++f) {
        const PinholeCamera camera(path, f, settings.width, settings.height);
        if (!gpu) {
            tally(feedback.addFrame(camera));
            continue;
        }
        for (const auto& r : feedback.addFrame(camera, *gpu)) tally(r);
    }
    if (gpu)
        for (const auto& r : feedback.drain(*gpu)) tally(r);
    const double walkSeconds = watch.restart();
    Placement result = evaluate(ps, feedback.probes(), "coverage");
    result.timings.emplace(result.timings.end() - 1, "walk", walkSeconds);
    const double frames = double(std::max<std::size_t>(path.frames.size(), 1));
    result.figures = {{"frames", double(path.frames.size())},
                      {"frame_coverage_before", before / frames},
                      {"frame_coverage_after", after / frames},
                      {"pixels_per_frame", double(settings.width * settings.height)},
                      {"frames_traced_on_cpu", double(feedback.framesTraced())},
                      {"gpu_count", gpu ? 1.0 : 0.0}};
    return result;
}

}  // namespace cubeao::placement
