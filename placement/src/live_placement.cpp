#include "cubeao/placement/live_placement.h"

#include <algorithm>
#include <chrono>
#include <deque>
#include <optional>
#include <string>

#include "cubeao/bake/bake.h"
#include "cubeao/bake/bake_settings.h"
#include "cubeao/bake/gpu_bake.h"
#include "cubeao/core/error.h"
#include "cubeao/gl/handles.h"
#include "cubeao/placement/error_feedback.h"
#include "cubeao/placement/gpu_coverage.h"
#include "cubeao/reference/embree_scene.h"
#include "cubeao/runtime/probe_projection.h"

namespace cubeao::placement {

void BakeBudget::newFrame() { balance_ = std::min(balance_ + msPerFrame_, msPerFrame_); }

namespace {

// The parameters of what a live bake makes: the bake's (cacheParamsFor), its AO kept as BC5 (the
// bakers' output, AO + confidence), so that fast and traced probes can replace each other in one pass.
CacheParams liveParams(const BakeSettings& s, const Scene& scene) {
    CacheParams p = cacheParamsFor(s, scene);
    p.aoFormat = AoFormat::Bc5;
    return p;
}

// The cache fields a fast and a traced probe must share to replace each other in one pass: what
// the sections' sizes and the run time's distances depend on (the estimator's own fields are free).
CacheParams sectionParams(CacheParams p) {
    p.estimator = 0;
    p.spp = 0;
    p.seed = 0;
    p.directions = 0;
    p.steps = 0;
    p.hybridThreshold = 0.0f;
    p.denoise = 0;  // the traced bake's AO filter
    return p;
}

std::string joined(const std::vector<std::string>& parts) {
    std::string out;
    for (const std::string& p : parts) out += (out.empty() ? "" : "; ") + p;
    return out;
}

bool sameView(const PinholeCamera& a, const PinholeCamera& b) {
    return a.eye == b.eye && a.forward == b.forward && a.right == b.right && a.up == b.up &&
           a.tanHalfFovY == b.tanHalfFovY;
}

double msSince(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace

struct LivePlacement::Impl {
    // One probe this object knows: placed here (queued, then fast, maybe traced) or adopted.
    struct Probe {
        std::uint32_t index = 0;
        glm::vec3 position{0.0f};
        std::optional<ProbeRecord> record;  // the version in the pass; none while the fast bake is pending
        std::optional<ProbeId> passId;
        bool traced = false;  // record is a traced bake (re-baked, or adopted from a traced cache)
    };

    const PlacementScene& ps;
    LiveSettings settings;
    CacheParams fastParams, tracedParams;
    CoverageFeedback feedback;                  // Coverage: places; Error: holds the probes for reports
    std::optional<ErrorFeedback> errorFeedback;  // Error only
    std::unique_ptr<GpuCoverageCount> count;     // Coverage only
    GpuBaker fastBaker;
    std::unique_ptr<GpuBaker> tracedBaker;  // null when re-baking is off
    BakeBudget budget;

    std::vector<Probe> probes;
    std::size_t feedbackSeen = 0;      // placing feedback's probes() already turned into Probes
    std::deque<std::size_t> queue;     // probes waiting for their fast bake, placement order
    std::optional<std::size_t> fastJob, tracedJob;  // the probe each baker is baking
    std::uint32_t nextIndex = 0;
    std::uint64_t frames = 0;
    bool countDue = false;  // a count is due and waits for a free slot
    std::optional<PinholeCamera> lastCounted;  // the view of the newest count submitted
    int idleFrames = 0;
    Stats stats;
    double bakeMsTotal = 0.0;

    Impl(const PlacementScene& ps, const BakeSettings& fast, const BakeSettings& traced, LiveSettings s)
        : ps(ps),
          settings(s),
          fastParams(liveParams(fast, ps.scene())),
          tracedParams(liveParams(traced, ps.scene())),
          feedback(ps, s.feedback),
          fastBaker(ps.scene(), fast),
          budget(s.bakeMsPerFrame) {
        if (settings.countEveryFrames < 1) throw Error("LivePlacement: countEveryFrames must be at least 1");
        if (!(settings.bakeMsPerFrame > 0.0)) throw Error("LivePlacement: bakeMsPerFrame must be positive");
        const std::vector<std::string> differ =
            cacheParamDifferences(sectionParams(fastParams), sectionParams(tracedParams));
        if (!differ.empty())
            throw Error("LivePlacement: the fast and the traced bake must make the same probe sections: " +
                        joined(differ));
        if (settings.idleFramesBeforeRebake >= 0) tracedBaker = std::make_unique<GpuBaker>(ps.scene(), traced);
        if (settings.objective == LiveSettings::Objective::Error)
            errorFeedback.emplace(ps);
        else
            count = std::make_unique<GpuCoverageCount>(ps.scene(), s.nearPlane);
    }

    // The probes of the feedback that places them.
    const std::vector<glm::vec3>& placedProbes() const {
        return errorFeedback ? errorFeedback->probes() : feedback.probes();
    }

    // Whether a count can be submitted now without waiting. (CoverageFeedback hands back finished
    // counts only when it submits the next one, and GpuCoverageCount::submit waits when every slot
    // is busy with an unfinished frame.)
    bool countSlotFree() { return !count || !count->submitWouldWait(); }

    void submitCount(const PinholeCamera& camera) {
        PinholeCamera counted = camera;  // eye, basis and field of view; the count's resolution
        counted.width = settings.feedback.width;
        counted.height = settings.feedback.height;
        if (errorFeedback) {
            const ErrorFeedback::FrameResult r = errorFeedback->addFrame(counted, settings.nearPlane, settings.farPlane,
                                                                         settings.feedback.maxPerFrame);
            stats.predictedMae = r.after;
            stats.stalled = r.added == 0 ? r.stalled : nullptr;
            ++stats.framesCounted;
            takeNewProbes();
            return;
        }
        handled(feedback.addFrame(counted, *count));
    }

    // New probes of the placing feedback join the queue, with the next indices (and the coverage
    // feedback's list, when it does not place them itself).
    void takeNewProbes() {
        const std::vector<glm::vec3>& placed = placedProbes();
        if (errorFeedback && placed.size() > feedbackSeen)
            feedback.addProbes(std::span(placed).subspan(feedbackSeen));
        for (; feedbackSeen < placed.size(); ++feedbackSeen) {
            Probe p;
            p.index = nextIndex++;
            p.position = placed[feedbackSeen];
            probes.push_back(std::move(p));
            queue.push_back(probes.size() - 1);
            ++stats.placed;
        }
    }

    void handled(const std::vector<CoverageFeedback::FrameResult>& results) {
        for (const CoverageFeedback::FrameResult& r : results) {
            stats.coverage = r.after;
            stats.stalled = r.added == 0 ? r.stalled : nullptr;
            ++stats.framesCounted;
        }
        takeNewProbes();
    }

    // A finished bake goes to the pass; a traced one replaces the fast version there.
    void handOver(std::size_t slot, BakedProbe&& baked, bool traced, ProbeProjectionPass& pass) {
        Probe& p = probes[slot];
        ProbeRecord record = probeRecord(p.index, p.position, std::move(baked.encoded));
        if (p.passId) pass.removeProbe(*p.passId);
        p.passId = pass.addProbe(record);  // copies: the record stays here for save()
        p.record = std::move(record);
        p.traced = traced;
        if (traced)
            ++stats.rebaked;
        else
            ++stats.baked;
    }

    // The next fast probe to re-bake with traced: the oldest one (placement order).
    std::optional<std::size_t> nextRebake() const {
        for (std::size_t i = 0; i < probes.size(); ++i)
            if (probes[i].record && !probes[i].traced) return i;
        return std::nullopt;
    }

    // The baker whose step comes next, beginning its job if needed; null: no bake work now.
    GpuBaker* nextBaker(bool mayBeginRebake) {
        if (!fastJob && !queue.empty()) {
            fastJob = queue.front();
            queue.pop_front();
            fastBaker.begin(probes[*fastJob].position, probes[*fastJob].index);
        }
        if (fastJob) return &fastBaker;
        if (!tracedBaker) return nullptr;
        if (!tracedJob && mayBeginRebake) {
            tracedJob = nextRebake();
            if (tracedJob) tracedBaker->begin(probes[*tracedJob].position, probes[*tracedJob].index);
        }
        return tracedJob ? tracedBaker.get() : nullptr;
    }

    // One step of `baker`; true when its probe was finished and handed over.
    bool step(GpuBaker& baker, ProbeProjectionPass& pass) {
        if (!baker.step()) return false;
        const bool traced = &baker != &fastBaker;
        std::optional<std::size_t>& job = traced ? tracedJob : fastJob;
        handOver(*job, baker.take(), traced, pass);
        job.reset();
        return true;
    }

};

LivePlacement::LivePlacement(const PlacementScene& ps, const BakeSettings& fast, const BakeSettings& traced,
                             LiveSettings settings)
    : impl_(std::make_unique<Impl>(ps, fast, traced, settings)) {}

LivePlacement::~LivePlacement() = default;

CacheParams LivePlacement::cacheParams() const { return impl_->fastParams; }

const CoverageFeedback& LivePlacement::feedback() const { return impl_->feedback; }

void LivePlacement::adopt(std::vector<ProbeRecord> probes, std::span<const ProbeId> passIds,
                          const CacheParams& params) {
    Impl& m = *impl_;
    if (m.frames != 0) throw Error("LivePlacement::adopt: call it before the first frame()");
    if (passIds.size() != probes.size())
        throw Error("LivePlacement::adopt: " + std::to_string(probes.size()) + " probes but " +
                    std::to_string(passIds.size()) + " pass ids");
    // The probes join the pass as BC5, whatever their cache stores (liveParams).
    const CacheParams held = withAoFormat(params, m.fastParams.aoFormat);
    const bool traced = held == m.tracedParams;
    if (!traced && held != m.fastParams)
        throw Error("LivePlacement::adopt: the cache was baked with other parameters than the live bake: " +
                    joined(cacheParamDifferences(held, m.fastParams)));
    std::vector<std::uint32_t> indices;
    for (const Impl::Probe& known : m.probes) indices.push_back(known.index);
    for (const ProbeRecord& r : probes) indices.push_back(r.index);
    std::sort(indices.begin(), indices.end());
    if (const auto twice = std::adjacent_find(indices.begin(), indices.end()); twice != indices.end())
        throw Error("LivePlacement::adopt: probe index " + std::to_string(*twice) + " twice");
    for (std::size_t i = 0; i < probes.size(); ++i) {
        Impl::Probe p;
        p.index = probes[i].index;
        p.position = probes[i].position;
        p.passId = passIds[i];
        p.traced = traced;
        p.record = withAoFormat(std::move(probes[i]), held.aoFormat, held.res, held.levels);
        m.nextIndex = std::max(m.nextIndex, p.index + 1);
        m.probes.push_back(std::move(p));
    }
    // The counts see the adopted probes; they are not the feedback's placements to bake.
    std::vector<glm::vec3> positions;
    for (std::size_t i = m.probes.size() - probes.size(); i < m.probes.size(); ++i) positions.push_back(m.probes[i].position);
    m.feedback.addProbes(positions);
    if (m.errorFeedback) m.errorFeedback->addProbes(positions);
    m.feedbackSeen = m.placedProbes().size();
}

void LivePlacement::frame(const PinholeCamera& camera, bool idle, ProbeProjectionPass& pass) {
    Impl& m = *impl_;
    // The coverage count, every countEveryFrames frames; a count due while every slot is in flight
    // moves to the next frame, since submitting it would wait for the oldest.
    if (m.frames % std::uint64_t(m.settings.countEveryFrames) == 0) m.countDue = true;
    ++m.frames;
    const auto countStart = std::chrono::steady_clock::now();
    // The view last counted again (a camera standing still) is not counted again: the probes its count
    // placed are all it can get, and a frame stuck below the target would be traced on the CPU anew.
    if (m.countDue && m.lastCounted && sameView(*m.lastCounted, camera)) m.countDue = false;
    if (m.countDue && m.countSlotFree()) {
        m.lastCounted = camera;
        m.submitCount(camera);  // also handles the counts that came back (a frame below the target: CPU)
        m.countDue = false;
    }
    m.stats.countMsLastFrame = msSince(countStart);

    m.idleFrames = idle ? m.idleFrames + 1 : 0;
    const int idleNeeded = m.settings.idleFramesBeforeRebake;
    const bool mayBeginRebake = idleNeeded >= 0 && m.idleFrames >= idleNeeded;
    m.budget.newFrame();
    double spent = 0.0;
    while (m.budget.canStep()) {
        GpuBaker* baker = m.nextBaker(mayBeginRebake);
        if (!baker) break;
        const bool waiting = baker->waiting();
        const auto start = std::chrono::steady_clock::now();
        const bool finished = m.step(*baker, pass);
        const double ms = msSince(start);
        m.budget.spend(ms);
        spent += ms;
        m.stats.stepMsMax = std::max(m.stats.stepMsMax, ms);
        if (waiting && !finished) break;  // polled a fence that has not signalled: the GPU is still on it
    }
    m.stats.bakeMsLastFrame = spent;
    m.bakeMsTotal += spent;
    m.stats.bakeMsMean = m.bakeMsTotal / double(m.frames);
}

void LivePlacement::drain(ProbeProjectionPass& pass) {
    Impl& m = *impl_;
    if (m.count) m.handled(m.feedback.drain(*m.count));
    // Bake to the end, waiting for each fence (glFinish) instead of polling it frame after frame.
    while (GpuBaker* baker = m.nextBaker(false)) {
        if (baker->waiting()) glFinish();
        m.step(*baker, pass);
    }
}

LivePlacement::Stats LivePlacement::stats() const {
    Stats s = impl_->stats;
    s.queued = impl_->queue.size() + (impl_->fastJob ? 1 : 0);
    s.inPass = 0;
    s.toRebake = 0;
    for (const Impl::Probe& p : impl_->probes) {
        s.inPass += p.passId ? 1 : 0;
        s.toRebake += p.passId && !p.traced ? 1 : 0;
    }
    return s;
}

std::size_t LivePlacement::save(const std::filesystem::path& path) const {
    const Impl& m = *impl_;
    std::vector<ProbeView> views;
    bool allTraced = true;
    for (const Impl::Probe& p : m.probes)
        if (p.record) {
            views.push_back(viewOf(*p.record));
            allTraced = allTraced && p.traced;
        }
    std::sort(views.begin(), views.end(), [](const ProbeView& a, const ProbeView& b) { return a.index < b.index; });
    // All traced: the cache a traced bake writes, AO stored as BC4 (writeCache converts the BC5 records).
    CacheParams params = m.fastParams;
    if (allTraced && !views.empty()) {
        params = m.tracedParams;
        params.aoFormat = defaultAoFormat(params.estimator);
    }
    writeCache(path, params, views);
    return views.size();
}

}  // namespace cubeao::placement
