// Live placement for the viewer (issue 14): the stepped GPU bake (GpuBaker::begin/step/take) gives the
// bytes of bake() and leaves a frame of the pipeline unchanged when its steps are interleaved with
// frames; the time-slicing token bucket on given step costs; and LivePlacement on builtin:box-room's
// own walk from no probes, with a FramePipeline rendering each frame, reaching the coverage target and
// saving a cache whose every checksum holds, also when saved again over itself.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <glm/common.hpp>

#include "bake_test_settings.h"
#include "cli_run.h"
#include "cubeao/bake/gpu_bake.h"
#include "cubeao/cache/cache_file.h"
#include "cubeao/core/error.h"
#include "cubeao/core/image.h"
#include "cubeao/gl/handles.h"
#include "cubeao/placement/coverage_feedback.h"
#include "cubeao/placement/error_feedback.h"
#include "cubeao/placement/live_placement.h"
#include "cubeao/placement/placement.h"
#include "cubeao/reference/embree_scene.h"
#include "cubeao/runtime/blur.h"
#include "cubeao/runtime/frame_pipeline.h"
#include "cubeao/runtime/probe_projection.h"
#include "cubeao/ssao/ssao_pass.h"
#include "cubeao/scene/builtin.h"
#include "cubeao/scene/import.h"
#include "runtime_test_util.h"
#include "test_util.h"

namespace cubeao::placement {
namespace {

using test::boxRoom;
using test::boxRoomPath;

// ---- The stepped bake ----------------------------------------------------------------------------

class GpuBakeStepGl : public GlTest {};

double msSince(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

// Steps a begun job to the end: each step is timed (into `stepMs` when given); a step that only
// polls a fence not yet signalled is retried after glFinish, so the loop ends.
BakedProbe stepToEnd(GpuBaker& baker, std::vector<double>* stepMs = nullptr,
                     const std::function<void()>& between = {}) {
    for (int guard = 0; guard < 100; ++guard) {
        const bool polling = baker.waiting();
        const auto start = std::chrono::steady_clock::now();
        const bool done = baker.step();
        if (stepMs) stepMs->push_back(msSince(start));
        if (done) return baker.take();
        if (polling) glFinish();
        if (between) between();
    }
    ADD_FAILURE() << "the stepped bake did not finish in 100 steps";
    return {};
}

void expectSameBake(const BakedProbe& a, const BakedProbe& b, const std::string& what) {
    EXPECT_EQ(a.encoded.aoConfidence, b.encoded.aoConfidence) << what;
    EXPECT_EQ(a.encoded.depth, b.encoded.depth) << what;
    EXPECT_EQ(a.encoded.maxDistance, b.encoded.maxDistance) << what;
    EXPECT_EQ(a.encoded.aoSquaredError, b.encoded.aoSquaredError) << what;
    EXPECT_EQ(a.encoded.surfaceTexels, b.encoded.surfaceTexels) << what;
    EXPECT_EQ(a.tracedTexels, b.tracedTexels) << what;
    EXPECT_EQ(a.rays, b.rays) << what;
    EXPECT_EQ(a.fetches, b.fetches) << what;
    EXPECT_EQ(a.ao, b.ao) << what;
    EXPECT_EQ(a.confidence, b.confidence) << what;
    ASSERT_EQ(a.gbuffer.texels.size(), b.gbuffer.texels.size()) << what;
    for (std::size_t i = 0; i < a.gbuffer.texels.size(); ++i)
        ASSERT_EQ(a.gbuffer.texels[i], b.gbuffer.texels[i]) << what << " texel " << i;
}

// Bit-identical to bake() for the same probe and index, with hsplit, traced and hybrid (whose AO step is
// three dispatches and whose traced-texel count is read back at the end), with the encoded and
// with the full read-back; several probes through one baker (the job's buffers are reused), and steps
// in a different order against bake() calls (bake first, then stepped, and the other way round).
TEST_F(GpuBakeStepGl, StepsGiveTheBytesOfBake) {
    const Scene& scene = boxRoom();
    // Near the crate, under the table's edge, by the cabinet: probes that see occlusion.
    const std::vector<glm::vec3> probes = {{1.3f, 0.9f, 4.0f}, {5.2f, 1.0f, 3.2f}, {7.0f, 0.5f, 2.3f}};
    const float radius = scene.defaultRadius();
    for (const Estimator e : {Estimator::HorizonSplit, Estimator::Traced, Estimator::Hybrid}) {
        for (const BakeReadback readback : {BakeReadback::Encoded, BakeReadback::All}) {
            const BakeSettings s = test::bakeSettings(e, 16, radius, 16);
            GpuBaker baker(scene, s);
            baker.setReadback(readback);
            std::vector<double> stepMs;
            for (std::size_t k = 0; k < probes.size(); ++k) {
                const std::uint32_t index = std::uint32_t(10 + k);
                const std::string what = std::string(estimatorName(e)) +
                                         (readback == BakeReadback::All ? " all" : " encoded") + " probe " +
                                         std::to_string(k);
                BakedProbe direct, stepped;
                EXPECT_FALSE(baker.busy());
                if (k % 2 == 0) direct = baker.bake(probes[k], index);
                baker.begin(probes[k], index);
                EXPECT_TRUE(baker.busy());
                EXPECT_FALSE(baker.ready());
                EXPECT_THROW(baker.begin(probes[k], index), Error) << "one job at a time";
                EXPECT_THROW(baker.take(), Error) << "nothing ready yet";
                EXPECT_THROW(baker.bake(probes[k], index), Error) << "the job's buffers are in use";
                stepped = stepToEnd(baker, k == 0 ? &stepMs : nullptr);
                EXPECT_FALSE(baker.busy());
                if (k % 2 == 1) direct = baker.bake(probes[k], index);
                expectSameBake(stepped, direct, what);
                EXPECT_GT(stepped.encoded.surfaceTexels, 0u) << what;
                if (readback == BakeReadback::All) {
                    // Some occlusion, or equal AO would mean little (16² faces in an open room see a little).
                    EXPECT_LT(*std::min_element(direct.ao.begin(), direct.ao.end()), 0.99f) << what;
                }
            }
            std::string steps;
            for (double ms : stepMs) {  // += twice: " " + std::string gives g++ 12 a false -Wstringop-overflow
                steps += ' ';
                steps += std::to_string(ms).substr(0, 6);
            }
            std::printf("stepped bake %s res %d (%s read-back): step wall ms:%s\n", estimatorName(e), s.res,
                        readback == BakeReadback::All ? "full" : "encoded", steps.c_str());
        }
    }
}

std::vector<float> readTexture(GLuint texture, int w, int h, GLenum format, int channels) {
    std::vector<float> out(std::size_t(channels) * std::size_t(w) * std::size_t(h));
    glGetTextureImage(texture, 0, format, GL_FLOAT, GLsizei(out.size() * sizeof(float)), out.data());
    return out;
}

struct FrameImages {
    std::vector<float> raw, ao, shaded;
};

FrameImages renderFrame(FramePipeline& pipeline, std::uint32_t frame, int w, int h) {
    pipeline.render(test::viewOf(boxRoomPath(), frame, w, h), frame);
    return {readTexture(pipeline.rawAoTexture(), w, h, GL_RED, 1), readTexture(pipeline.aoTexture(), w, h, GL_RED, 1),
            readTexture(pipeline.shadedTexture(), w, h, GL_RGBA, 4)};
}

struct FrameState {
    GLint viewport[4], program, drawFramebuffer, readFramebuffer, vertexArray, depthFunc, clipOrigin, clipDepth;
    GLboolean depthTest, cull;
    bool operator==(const FrameState& o) const {
        return std::equal(viewport, viewport + 4, o.viewport) && program == o.program &&
               drawFramebuffer == o.drawFramebuffer && readFramebuffer == o.readFramebuffer &&
               vertexArray == o.vertexArray && depthFunc == o.depthFunc && clipOrigin == o.clipOrigin &&
               clipDepth == o.clipDepth && depthTest == o.depthTest && cull == o.cull;
    }
};

FrameState frameState() {
    FrameState s{};
    glGetIntegerv(GL_VIEWPORT, s.viewport);
    glGetIntegerv(GL_CURRENT_PROGRAM, &s.program);
    glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &s.drawFramebuffer);
    glGetIntegerv(GL_READ_FRAMEBUFFER_BINDING, &s.readFramebuffer);
    glGetIntegerv(GL_VERTEX_ARRAY_BINDING, &s.vertexArray);
    glGetIntegerv(GL_DEPTH_FUNC, &s.depthFunc);
    glGetIntegerv(GL_CLIP_ORIGIN, &s.clipOrigin);
    glGetIntegerv(GL_CLIP_DEPTH_MODE, &s.clipDepth);
    s.depthTest = glIsEnabled(GL_DEPTH_TEST);
    s.cull = glIsEnabled(GL_CULL_FACE);
    return s;
}

// The viewer interleaves bake steps with its frames in one context: a pipeline frame rendered after
// some steps is the frame rendered before them, bit for bit; each step leaves the frame's GL state as
// it found it (set to unusual values here, so a step that resets to defaults is caught too); and the
// probe baked between frames is still bake()'s.
TEST_F(GpuBakeStepGl, PipelineFramesAndStepsInterleaveUnchanged) {
    const Scene& scene = boxRoom();
    constexpr int w = 48, h = 32;
    const SsaoSettings gtao = test::methodSettings(SsaoMethod::Gtao, scene.defaultRadius());
    FramePipeline pipeline(scene.positions, scene.indices, std::make_unique<SsaoPass>(gtao), BlurSettings{},
                           test::compositeSettings());
    const BakeSettings s = test::bakeSettings(Estimator::HorizonSplit, 16, scene.defaultRadius(), 16);
    GpuBaker baker(scene, s);
    const glm::vec3 probe{3.0f, 1.2f, 2.5f};
    const BakedProbe expected = baker.bake(probe, 5);

    const FrameImages before = renderFrame(pipeline, 3, w, h);
    EXPECT_LT(*std::min_element(before.ao.begin(), before.ao.end()), 0.9f) << "the frame must show occlusion";
    // Frame state a step must not disturb: an odd viewport, a bound VAO, culling on, GL_LEQUAL.
    gl::VertexArray vao = gl::VertexArray::create();
    glBindVertexArray(vao.id());
    glViewport(1, 2, 30, 20);
    glEnable(GL_CULL_FACE);
    glDepthFunc(GL_LEQUAL);
    const FrameState state = frameState();
    baker.begin(probe, 5);
    std::vector<FrameImages> between;
    const BakedProbe stepped = stepToEnd(baker, nullptr, [&] {
        EXPECT_TRUE(frameState() == state) << "a bake step changed the frame's GL state";
        glBindVertexArray(0);
        glViewport(0, 0, w, h);
        glDisable(GL_CULL_FACE);
        glDepthFunc(GL_LESS);
        between.push_back(renderFrame(pipeline, 3, w, h));
        glBindVertexArray(vao.id());
        glViewport(1, 2, 30, 20);
        glEnable(GL_CULL_FACE);
        glDepthFunc(GL_LEQUAL);
    });
    glBindVertexArray(0);
    glViewport(0, 0, w, h);
    glDisable(GL_CULL_FACE);
    glDepthFunc(GL_LESS);
    ASSERT_GE(between.size(), 3u) << "G-buffer, AO and encode steps each followed by a frame";
    for (std::size_t k = 0; k < between.size(); ++k) {
        EXPECT_EQ(between[k].raw, before.raw) << "frame after step " << k;
        EXPECT_EQ(between[k].ao, before.ao) << "frame after step " << k;
        EXPECT_EQ(between[k].shaded, before.shaded) << "frame after step " << k;
    }
    const FrameImages after = renderFrame(pipeline, 3, w, h);
    EXPECT_EQ(after.shaded, before.shaded);
    expectSameBake(stepped, expected, "stepped between frames");
}

// ---- The time slicing ----------------------------------------------------------------------------

// Runs `frames` frames of a bake whose steps cost `costs` in turn (cycled), as LivePlacement::frame
// spends the budget; returns the ms spent per frame.
std::vector<double> spendFrames(BakeBudget& budget, const std::vector<double>& costs, int frames) {
    std::vector<double> spent;
    std::size_t next = 0;
    for (int f = 0; f < frames; ++f) {
        budget.newFrame();
        double ms = 0.0;
        while (budget.canStep()) {
            const double cost = costs[next++ % costs.size()];
            budget.spend(cost);
            ms += cost;
        }
        spent.push_back(ms);
    }
    return spent;
}

TEST(LivePlacement, BakeBudgetSlicesGivenStepCosts) {
    {  // cheap steps: four of 1 ms fill a 4 ms frame exactly, every frame
        BakeBudget b(4.0);
        EXPECT_FALSE(b.canStep()) << "nothing before the first frame";
        EXPECT_EQ(spendFrames(b, {1.0}, 3), (std::vector<double>{4.0, 4.0, 4.0}));
    }
    {  // steps dearer than the frame: one overruns, the next frames skip until the debt is paid
        BakeBudget b(4.0);
        // 10 ms: balance 4 → −6 → −2 → 2 (step) → −8 → −4 → 0 (not positive: skip) → 4 (step) …
        EXPECT_EQ(spendFrames(b, {10.0}, 8), (std::vector<double>{10.0, 0.0, 10.0, 0.0, 0.0, 10.0, 0.0, 10.0}));
    }
    {  // mixed costs: over any run of frames, at most frames · budget plus one step
        BakeBudget b(4.0);
        const std::vector<double> costs = {0.5, 3.0, 7.0, 1.5, 0.2, 12.0};
        const std::vector<double> spent = spendFrames(b, costs, 200);
        double total = 0.0;
        for (std::size_t f = 0; f < spent.size(); ++f) {
            total += spent[f];
            EXPECT_LE(total, 4.0 * double(f + 1) + 12.0) << "frame " << f;
        }
        EXPECT_GE(total, 4.0 * 200.0 - 12.0) << "and the budget is used when there is work";
    }
    {  // frames without work bank nothing: the balance never exceeds one frame's budget
        BakeBudget b(4.0);
        for (int f = 0; f < 10; ++f) b.newFrame();
        EXPECT_EQ(b.balance(), 4.0);
        EXPECT_EQ(spendFrames(b, {1.0}, 1), (std::vector<double>{4.0}));
    }
}

// ---- Live placement on builtin:box-room ------------------------------------------------------------

class LivePlacementGl : public GlTest {};

// Placement settings under which a probe covers a few metres of the box room (those of the coverage
// feedback test in test_placement.cpp), and bakes at 16² per face so the walk stays quick on llvmpipe
// (the criterion assumes 128²: placement and bake resolution are independent knobs here).
PlaceSettings liveRoomSettings(const Scene& scene) {
    PlaceSettings s;
    const glm::vec3 extent = scene.bounds.max - scene.bounds.min;
    s.voxel = std::max({extent.x, extent.y, extent.z}) / 25.0f;
    s.samples = 1500;
    s.votingRays = 12;
    s.res = 128;
    s.texelsPerRadius = 4.0f;
    s.target = 0.95;
    s.seed = 7;
    return s;
}

// From no probes: walk the room's own path with a FramePipeline showing the live pass each frame,
// then stand still until fast probes are re-baked with traced, drain, and save.
TEST_F(LivePlacementGl, BoxRoomWalkFromNoProbesReachesTargetAndSavesAVerifiedCache) {
    const Scene scene = loadScene("builtin:box-room");
    const CameraPath path = resolveCameraPath("", "builtin:box-room");
    ASSERT_FALSE(path.frames.empty());
    const PlaceSettings placeSettings = liveRoomSettings(scene);
    const PlacementScene ps(scene, placeSettings, &path);
    const float radius = scene.defaultRadius();
    const BakeSettings fast = test::bakeSettings(Estimator::HorizonSplit, 16, radius, 16);
    const BakeSettings traced = test::bakeSettings(Estimator::Traced, 16, radius, 16);
    LiveSettings live;
    live.feedback.width = 48;
    live.feedback.height = 27;
    live.countEveryFrames = 1;  // every frame of the walk counted, as placeCoverage does
    live.bakeMsPerFrame = 20.0;
    live.idleFramesBeforeRebake = 5;
    live.nearPlane = path.nearPlane;
    live.objective = LiveSettings::Objective::Coverage;  // the target this test checks
    LivePlacement placement(ps, fast, traced, live);
    const CacheParams params = placement.cacheParams();
    EXPECT_EQ(params.estimator, std::uint8_t(Estimator::HorizonSplit));
    EXPECT_EQ(params.sceneHash, scene.hash);

    auto owned = std::make_unique<ProbeProjectionPass>(params, scene.positions, scene.indices);
    ProbeProjectionPass& pass = *owned;
    FramePipeline pipeline(scene.positions, scene.indices, std::move(owned), BlurSettings{}, test::compositeSettings());
    constexpr int w = 64, h = 36;
    const auto showFrame = [&](std::size_t f, bool idle) {
        pipeline.render(CameraView::fromPinhole(PinholeCamera(path, f, w, h), path.nearPlane), std::uint32_t(f));
        placement.frame(PinholeCamera(path, f, w, h), idle, pass);
    };
    const auto start = std::chrono::steady_clock::now();
    for (std::size_t f = 0; f < path.frames.size(); ++f) showFrame(f, false);
    const LivePlacement::Stats walked = placement.stats();
    const double walkMs = msSince(start);
    // Standing still at the end: once the fast queue is done and idleFramesBeforeRebake frames have
    // passed, the traced re-bakes begin. How many frames that takes depends on the step times (the
    // budget is wall clock: a step of 700 ms, as under the sanitizers on a loaded machine, takes the
    // next 35 frames' budget), so the bound is wall clock too, generous, and only its being reached is
    // asserted.
    // standStill(frames, enough, asserted): idle `frames` frames or until `enough`, and past `frames`
    // for up to 120 s more while what the test asserts has not happened yet.
    const auto standStill = [&](int frames, auto enough, auto asserted) {
        const auto since = std::chrono::steady_clock::now();
        for (int f = 0; !enough() && (f < frames || (!asserted() && msSince(since) < 120'000.0)); ++f)
            showFrame(path.frames.size() - 1, true);
    };
    const auto anyRebaked = [&] { return placement.stats().rebaked > 0; };
    standStill(500, anyRebaked, anyRebaked);
    const LivePlacement::Stats idled = placement.stats();
    placement.drain(pass);
    const LivePlacement::Stats s = placement.stats();
    std::printf("live box-room: walk %zu frames in %.0f ms (bake %.2f ms/frame mean, longest step %.2f ms); after the "
                "walk %zu placed, %zu baked, %zu queued; after idling %zu re-baked; drained: %zu placed, %zu baked, "
                "%zu re-baked, %zu in the pass, coverage of the last counted frame %.3f (%zu counted)\n",
                path.frames.size(), walkMs, walked.bakeMsMean, walked.stepMsMax, walked.placed, walked.baked,
                walked.queued, idled.rebaked, s.placed, s.baked, s.rebaked, s.inPass, s.coverage, s.framesCounted);

    ASSERT_GT(s.placed, 1u);
    EXPECT_EQ(s.baked, s.placed) << "drain bakes everything placed";
    EXPECT_EQ(s.queued, 0u);
    EXPECT_EQ(s.inPass, s.placed);
    EXPECT_EQ(pass.source().probes().liveCount(), s.placed)
        << "the pass holds every probe once (re-bakes replaced theirs)";
    EXPECT_GE(idled.rebaked, 1u) << "standing still re-bakes with traced";
    // Every walk frame asks for a count (one is put off to the next frame only while kSlots are in
    // flight, and drain() handles what is left); standing still, the view counted last is not counted
    // again, so the idle frames add nothing.
    EXPECT_LE(s.framesCounted, path.frames.size());
    EXPECT_GE(s.framesCounted, path.frames.size() - 2);

    // The walk's coverage by coverage.h's definition over the relevant samples (as placeCoverage
    // reports it) and frame by frame by the count the feedback runs on.
    const std::vector<glm::vec3>& probes = placement.feedback().probes();
    const Placement report = evaluate(ps, probes, "live");
    double frameMean = 0.0, frameMin = 1.0;
    for (std::size_t f = 0; f < path.frames.size(); ++f) {
        const double c = placement.feedback().frameCoverage(tracePixels(ps.embree(), PinholeCamera(path, f, 48, 27)));
        frameMean += c / double(path.frames.size());
        frameMin = std::min(frameMin, c);
    }
    std::printf("live box-room: coverage %.4f (target %.2f), per frame mean %.4f, min %.4f\n", report.coverage,
                placeSettings.target, frameMean, frameMin);
    EXPECT_GE(report.coverage, placeSettings.target);
    EXPECT_GE(frameMean, placeSettings.target);

    // The pass shows them: a frame rendered now leaves fewer pixels to nothing than before any probe.
    pipeline.render(CameraView::fromPinhole(PinholeCamera(path, 0, w, h), path.nearPlane), 0);
    glFinish();
    EXPECT_LT(pass.pixelShares().uncovered, 0.5 * pass.pixelShares().geometry);

    // Save, then save again over the same path with more probes re-baked: the first file stays whole
    // for a reader that has it open, and the second verifies as `cubeao info --verify` does.
    const test::TempDir dir("live");
    const std::filesystem::path file = dir / "live.cubeao";
    ASSERT_EQ(placement.save(file), s.placed);
    const CacheReader first(file);
    EXPECT_NO_THROW(first.verifyAll());
    EXPECT_EQ(first.probeCount(), s.placed);
    EXPECT_EQ(first.params(), params) << "some probes are fast: the file must not claim traced";
    for (std::size_t i = 0; i < first.probeCount(); ++i) {
        EXPECT_EQ(first.index(i), std::uint32_t(i)) << "indices unique and increasing from 0";
        EXPECT_EQ(first.position(i), probes[i]);
    }
    standStill(200, [&] { return placement.stats().rebaked == s.placed; },
               [&] { return placement.stats().rebaked > s.rebaked; });
    placement.drain(pass);
    const LivePlacement::Stats resaved = placement.stats();
    EXPECT_GT(resaved.rebaked, s.rebaked);
    EXPECT_EQ(resaved.toRebake, s.placed - resaved.rebaked);
    ASSERT_EQ(placement.save(file), s.placed);
    EXPECT_NO_THROW(first.verifyAll()) << "the open reader keeps the first file";
    const CacheReader second(file);
    EXPECT_NO_THROW(second.verifyAll());
    const test::CliRun info = test::runCli("info " + file.string() + " --verify");
    EXPECT_EQ(info.code, 0) << info.out;
    EXPECT_TRUE(test::contains(info.out, "every checksum matches")) << info.out;
    EXPECT_EQ(second.probeCount(), s.placed);
    if (resaved.rebaked == s.placed) {
        EXPECT_EQ(second.params().estimator, std::uint8_t(Estimator::Traced)) << "every probe traced: say so";
        EXPECT_EQ(second.params().aoFormat, AoFormat::Bc4) << "stored as a traced bake stores it";
    } else {
        EXPECT_EQ(second.params(), params);
    }
    std::printf("live box-room: %zu of %zu probes traced at the second save\n", resaved.rebaked, s.placed);

    // The viewer reopens the cache: a pass built from it (probe i has id i), its probes adopted, saved
    // again as they were; a cache of other parameters and a probe index twice are refused.
    LivePlacement reopened(ps, fast, traced, live);
    ProbeProjectionPass fromCache(second, scene.positions, scene.indices);
    std::vector<ProbeRecord> records;
    std::vector<ProbeId> ids;
    for (std::size_t i = 0; i < second.probeCount(); ++i) {
        records.push_back(second.copyProbe(i));
        ids.push_back(ProbeId{std::uint32_t(i)});
    }
    CacheParams other = second.params();
    other.radius *= 2.0f;
    EXPECT_THROW(reopened.adopt(records, ids, other), Error);
    reopened.adopt(records, ids, second.params());
    EXPECT_EQ(reopened.stats().inPass, s.placed);
    EXPECT_EQ(reopened.stats().placed, 0u) << "adopted, not placed";
    EXPECT_EQ(reopened.stats().toRebake, resaved.rebaked == s.placed ? 0u : s.placed);
    EXPECT_THROW(reopened.adopt({records.front()}, std::vector<ProbeId>{ProbeId{0}}, second.params()), Error);
    const std::filesystem::path again = dir / "again.cubeao";
    ASSERT_EQ(reopened.save(again), s.placed);
    const CacheReader third(again);
    EXPECT_NO_THROW(third.verifyAll());
    EXPECT_EQ(third.params(), second.params());
    for (std::size_t i = 0; i < third.probeCount(); ++i) {
        EXPECT_EQ(third.index(i), second.index(i));
        const ProbeRecord a = third.copyProbe(i), b = second.copyProbe(i);
        EXPECT_EQ(a.aoConfidence, b.aoConfidence) << i;
        EXPECT_EQ(a.depth, b.depth) << i;
    }
}

// With the error objective (the default) the viewer's live placement places, frame by frame, exactly
// what ErrorFeedback places over the same counted frames (the twin `place --method live` runs), and
// bakes them all.
TEST_F(LivePlacementGl, ErrorObjectivePlacesWhatTheOfflineTwinPlaces) {
    const Scene scene = loadScene("builtin:box-room");
    const CameraPath path = resolveCameraPath("", "builtin:box-room");
    PlaceSettings placeSettings = liveRoomSettings(scene);
    placeSettings.texelsPerRadius = 16.0f;  // the error model's texels, as `place` has them
    const PlacementScene ps(scene, placeSettings, &path);
    const float radius = scene.defaultRadius();
    LiveSettings live;
    live.feedback.width = 48;
    live.feedback.height = 27;
    live.countEveryFrames = 2;
    live.bakeMsPerFrame = 20.0;
    live.idleFramesBeforeRebake = -1;  // no traced baker: not what this test is about
    live.nearPlane = path.nearPlane;
    live.farPlane = path.farPlane;
    ASSERT_EQ(live.objective, LiveSettings::Objective::Error) << "the default";
    LivePlacement placement(ps, test::bakeSettings(Estimator::HorizonSplit, 16, radius, 16),
                            test::bakeSettings(Estimator::Traced, 16, radius, 16), live);
    ProbeProjectionPass pass(placement.cacheParams(), scene.positions, scene.indices);
    for (std::size_t f = 0; f < path.frames.size(); ++f) placement.frame(PinholeCamera(path, f, 64, 36), false, pass);
    placement.drain(pass);
    const LivePlacement::Stats s = placement.stats();

    ErrorFeedback twin(ps);
    for (std::size_t f = 0; f < path.frames.size(); f += 2)
        twin.addFrame(PinholeCamera(path, f, 48, 27), path.nearPlane, path.farPlane, live.feedback.maxPerFrame);
    std::printf("live box-room, error objective: %zu placed, %zu baked, predicted MAE so far %.4f (twin %zu, %.4f)\n",
                s.placed, s.baked, s.predictedMae, twin.probes().size(), twin.predictedMae());
    ASSERT_GT(s.placed, 0u);
    EXPECT_EQ(s.baked, s.placed);
    EXPECT_EQ(s.framesCounted, (path.frames.size() + 1) / 2);
    EXPECT_EQ(s.stalled, nullptr);
    EXPECT_EQ(placement.feedback().probes(), twin.probes()) << "the coverage report sees the same probes, in order";
    EXPECT_DOUBLE_EQ(s.predictedMae, twin.predictedMae());
    EXPECT_EQ(pass.source().probes().liveCount(), s.placed);
}

// A fast and a traced bake that would make different sections cannot replace each other in one pass.
TEST_F(LivePlacementGl, RefusesBakesWithDifferentSections) {
    const Scene scene = loadScene("builtin:box-room");
    const CameraPath path = resolveCameraPath("", "builtin:box-room");
    const PlacementScene ps(scene, liveRoomSettings(scene), &path);
    const float radius = scene.defaultRadius();
    const BakeSettings fast = test::bakeSettings(Estimator::HorizonSplit, 16, radius, 16);
    const BakeSettings traced = test::bakeSettings(Estimator::Traced, 32, radius, 16);
    EXPECT_THROW(LivePlacement(ps, fast, traced, LiveSettings{}), Error);
}

}  // namespace
}  // namespace cubeao::placement
