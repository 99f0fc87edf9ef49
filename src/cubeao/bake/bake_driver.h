// The one bake loop (DESIGN.md §4 "Bake"): which probes of a set to bake (a shard, less those the sink
// already holds), each baked by the GPU or the CPU path behind one interface (ProbeBaker), optionally
// checked against an independent Embree reference (`bake --verify`, DESIGN.md §5), handed to a sink
// (bake_cache.h: the cache writer, or memory), with progress and stats. `cubeao bake`, `bench bake`,
// `bench render`'s sweep and the tests all bake through it.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "cubeao/bake/bake.h"
#include "cubeao/bake/bake_cache.h"
#include "cubeao/bake/bake_stats.h"
#include "cubeao/bake/gpu_bake.h"
#include "cubeao/scene/scene.h"

namespace cubeao {

// `--shard I/N`: this run bakes the probes whose index ≡ I (mod N), keeping their global indices, so
// `merge` of the N shard caches is the unsharded cache.
struct BakeShard {
    std::size_t index = 0, count = 1;
};
// "I/N" with 0 <= I < N; "" is the whole set. UsageError otherwise.
BakeShard parseBakeShard(const std::string& text);

struct ProbeBakerOptions {
    GBufferMode gbuffer = GBufferMode::Layered;  // GPU path only
    // Per-stage times (BakedProbe::timings). On the GPU path each stage is then timed on its own
    // (gl::timeGpu: glFinish and a timer query between stages), which stalls the pipeline: for
    // `bench bake` and `bake --timings`, never a plain bake. The CPU path always times its stages
    // (a clock read; nothing waits).
    bool timings = false;
};

// One interface over the two bakers: GpuBaker (gpu_bake.h; needs a current GL 4.5 context from
// prepare() to the ProbeBaker's end) for settings.device == Gpu, bakeProbeCpu (bake.h, Embree) for
// Cpu. Nothing is set up before prepare() or the first bake(), so a bake with nothing left to do
// needs no device.
class ProbeBaker {
public:
    // `settings` resolved (resolveBakeSettings). `scene` must outlive the baker.
    ProbeBaker(const Scene& scene, const BakeSettings& settings, ProbeBakerOptions options = {});
    // Uploads the scene (GPU: mesh, BVH, programs; CPU: the Embree scene); once.
    void prepare();
    ~ProbeBaker();
    ProbeBaker(const ProbeBaker&) = delete;
    ProbeBaker& operator=(const ProbeBaker&) = delete;

    // Keep the G-buffer, AO and confidence on the CPU (they always are on the CPU path; the GPU
    // path then reads them back: BakeReadback::All). --verify and --dump need them.
    void setUncompressed(bool keep);
    void setGBufferMode(GBufferMode mode);  // GPU path only

    BakedProbe bake(const glm::vec3& position, std::uint32_t index);

    const BakeSettings& settings() const { return settings_; }
    bool onGpu() const { return settings_.device == BakeDevice::Gpu; }
    double setupMs() const { return setupMs_; }  // prepare(): upload, BVH build, shader compilation
    // The scene in Embree: the CPU baker's, or built on first use for the GPU path's --verify.
    const EmbreeScene& embree();

private:
    const Scene& scene_;
    BakeSettings settings_;
    ProbeBakerOptions options_;
    bool prepared_ = false, uncompressed_ = false;
    std::unique_ptr<GpuBaker> gpu_;
    std::unique_ptr<EmbreeScene> embree_;
    double setupMs_ = 0.0;
};

// `bake --verify`: the reference's rays per texel; 0: kVerifyRayFactor × the bake's (bake.h).
struct VerifySpec {
    int spp = 0;
};

struct BakeJob {
    std::span<const glm::vec3> probes;  // probe i at probes[i] (probes.json, placement/probe_set.h)
    BakeShard shard;
    std::optional<VerifySpec> verify;
    // Called with every probe once baked, before its record goes to the sink (e.g. --dump). Makes
    // the baker keep the uncompressed probe.
    std::function<void(std::uint32_t index, const BakedProbe&)> onProbe;
    std::string progressLabel = "bake";  // the progress bar's; empty: none
};

// What one probe's bake reported.
struct ProbeBakeResult {
    std::uint32_t index = 0;
    glm::vec3 position{0.0f};
    double ms = 0.0;  // wall clock around the bake
    BakeTimings timings;
    std::uint64_t surfaceTexels = 0, tracedTexels = 0, rays = 0;
    double aoPsnr = 0.0;
    std::optional<VerifyResult> verify;  // against the independent reference (BakeJob::verify)
    std::optional<VerifyResult> twin;    // GPU traced with --verify: against the Embree twin, same rays
};

struct BakeResult {
    BakeStats stats;
    std::vector<ProbeBakeResult> probes;  // in bake order
    std::size_t inShard = 0;              // probes of the shard, baked or not
    std::size_t skipped = 0;              // of those, already in the sink
    int verifySpp = 0;                    // the reference's rays per texel (with verify)
    // Texel-weighted means over the probes (with verify; twin: GPU traced only).
    VerifyResult verify, twin;
};

// Bakes the probes of job.shard that the sink does not hold, in index order, into `sink`.
BakeResult bakeProbes(ProbeBaker& baker, const BakeJob& job, ProbeSink& sink);

// The probes of `shard` that `sink` does not hold yet, in index order.
std::vector<std::uint32_t> probesToBake(std::size_t probeCount, const BakeShard& shard, const ProbeSink& sink);

}  // namespace cubeao
