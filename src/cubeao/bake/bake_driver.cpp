#include "cubeao/bake/bake_driver.h"

#include <chrono>
#include <exception>

#include "cubeao/core/error.h"
#include "cubeao/core/progress.h"

namespace cubeao {
namespace {

using Clock = std::chrono::steady_clock;

double msSince(Clock::time_point start) { return std::chrono::duration<double, std::milli>(Clock::now() - start).count(); }

// Texel-weighted running mean of VerifyResults.
void accumulate(VerifyResult& sum, const VerifyResult& v) {
    const double n = double(sum.texels) + double(v.texels);
    if (n == 0.0) return;
    sum.mae = (sum.mae * double(sum.texels) + v.mae * double(v.texels)) / n;
    sum.noise = (sum.noise * double(sum.texels) + v.noise * double(v.texels)) / n;
    sum.texels += v.texels;
}

}  // namespace

// ---- ProbeBaker -----------------------------------------------------------------------------------

ProbeBaker::ProbeBaker(const Scene& scene, const BakeSettings& settings, ProbeBakerOptions options)
    : scene_(scene), settings_(settings), options_(options) {}

ProbeBaker::~ProbeBaker() = default;

void ProbeBaker::prepare() {
    if (prepared_) return;
    const Clock::time_point start = Clock::now();
    if (onGpu()) {
        gpu_ = std::make_unique<GpuBaker>(scene_, settings_);
        gpu_->setGBufferMode(options_.gbuffer);
        gpu_->setTimings(options_.timings);
        gpu_->setReadback(uncompressed_ ? BakeReadback::All : BakeReadback::Encoded);
    } else if (!embree_) {
        embree_ = std::make_unique<EmbreeScene>(scene_);
    }
    setupMs_ = msSince(start);
    prepared_ = true;
}

void ProbeBaker::setUncompressed(bool keep) {
    uncompressed_ = keep;
    if (gpu_) gpu_->setReadback(keep ? BakeReadback::All : BakeReadback::Encoded);
}

void ProbeBaker::setGBufferMode(GBufferMode mode) {
    options_.gbuffer = mode;
    if (gpu_) gpu_->setGBufferMode(mode);
}

BakedProbe ProbeBaker::bake(const glm::vec3& position, std::uint32_t index) {
    prepare();
    return gpu_ ? gpu_->bake(position, index) : bakeProbeCpu(*embree_, position, index, settings_);
}

const EmbreeScene& ProbeBaker::embree() {
    if (!embree_) embree_ = std::make_unique<EmbreeScene>(scene_);
    return *embree_;
}

// ---- the loop -------------------------------------------------------------------------------------

std::vector<std::uint32_t> probesToBake(std::size_t probeCount, const BakeShard& shard, const ProbeSink& sink) {
    if (shard.count < 1 || shard.index >= shard.count)
        throw UsageError("shard " + std::to_string(shard.index) + "/" + std::to_string(shard.count) +
                         ": expected I/N with 0 <= I < N");
    std::vector<std::uint32_t> todo;
    for (std::size_t i = shard.index; i < probeCount; i += shard.count)
        if (!sink.has(std::uint32_t(i))) todo.push_back(std::uint32_t(i));
    return todo;
}

BakeResult bakeProbes(ProbeBaker& baker, const BakeJob& job, ProbeSink& sink) {
    BakeResult r;
    const std::vector<std::uint32_t> todo = probesToBake(job.probes.size(), job.shard, sink);
    for (std::size_t i = job.shard.index; i < job.probes.size(); i += job.shard.count) ++r.inShard;
    r.skipped = r.inShard - todo.size();

    const BakeSettings& settings = baker.settings();
    std::optional<BakeSettings> reference;
    if (job.verify) {
        reference = verifyReferenceSettings(settings, job.verify->spp);
        r.verifySpp = reference->ao.spp;
    }
    // The identity check of the traced GPU path: its Embree twin traces the same rays (on the CPU
    // path the twin is the bake itself, so it would say nothing).
    const bool twin = job.verify && baker.onGpu() && settings.estimator == Estimator::Traced;
    baker.setUncompressed(job.verify.has_value() || bool(job.onProbe));

    if (!todo.empty()) baker.prepare();  // not in the first probe's time
    std::optional<Progress> progress;
    if (!job.progressLabel.empty()) progress.emplace(job.progressLabel, todo.size(), "probes");
    for (const std::uint32_t index : todo) {
        const glm::vec3 position = job.probes[index];
        const Clock::time_point start = Clock::now();
        BakedProbe probe = baker.bake(position, index);
        ProbeBakeResult p;
        p.ms = msSince(start);
        p.index = index;
        p.position = position;
        p.timings = probe.timings;
        p.surfaceTexels = probe.encoded.surfaceTexels;
        p.tracedTexels = probe.tracedTexels;
        p.rays = probe.rays;
        p.aoPsnr = aoPsnr(probe.encoded.aoSquaredError, probe.encoded.surfaceTexels);
        if (reference) {
            p.verify = verifyProbe(baker.embree(), probe, index, *reference);
            accumulate(r.verify, *p.verify);
        }
        if (twin) {
            p.twin = verifyProbe(baker.embree(), probe, index, settings);
            accumulate(r.twin, *p.twin);
        }
        if (job.onProbe) job.onProbe(index, probe);
        r.stats.add(probe, p.ms);
        r.probes.push_back(p);
        sink.add(probeRecord(index, position, std::move(probe.encoded)));
        if (progress) progress->advance();
    }
    return r;
}

}  // namespace cubeao
