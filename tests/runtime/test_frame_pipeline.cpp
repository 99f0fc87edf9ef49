// The non-stalling frame pipeline (src/cubeao/runtime/frame_pipeline.h, DESIGN.md §4 "Run time that
// grows"): it never waits for the GPU, its timer queries arrive frames later, and it renders what the
// measuring FrameRenderer renders.
//
// "Never waits" is checked through a GL wrapper, not by reading the source. This file is its own test
// executable (cubeao_pipeline_tests) because it defines, extern "C", the GL entry points that wait for
// the GPU or read its results back. The cubeao libraries are static and call GL directly
// (GL_GLEXT_PROTOTYPES, gl/gl.h), so at link time their calls bind to these definitions, ahead of
// libOpenGL's; each one counts the call while a StallRecorder is recording and forwards to the real
// entry point (dlsym(RTLD_NEXT, name)). The wrapper must be seen to work, or a zero would prove
// nothing: the same recorder has to count calls for FrameRenderer::render (glFinish, timer results,
// read-back), and count nothing for FramePipeline::render over several frames.
//
// Every test runs for each AO method in aoMethods(); the probe projection joins with one line there.
#include <gtest/gtest.h>

#include <dlfcn.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <memory>
#include <ostream>
#include <string>
#include <thread>
#include <vector>

#include "cubeao/core/image.h"
#include "cubeao/gl/handles.h"
#include "cubeao/runtime/blur.h"
#include "cubeao/runtime/frame_pipeline.h"
#include "cubeao/runtime/renderer.h"
#include "cubeao/cache/cache_file.h"
#include "cubeao/runtime/probe_projection.h"
#include "cubeao/ssao/gtao_fallback.h"
#include "cubeao/ssao/ssao_pass.h"
#include "bake_test_settings.h"
#include "runtime_test_util.h"
#include "test_util.h"

// ---- The GL wrapper ------------------------------------------------------------------------------

namespace stall {

// Every entry point that can make the CPU wait for the GPU. Reads into a pixel-pack buffer or a query
// buffer would not wait, but the pipeline has no reason to make any: they count too, so a future
// asynchronous read-back has to refine this rule on purpose.
enum Call : int {
    Finish,
    ReadPixels,
    ReadnPixels,
    GetTexImage,
    GetnTexImage,
    GetTextureImage,
    GetTextureSubImage,
    GetCompressedTexImage,
    GetnCompressedTexImage,
    GetCompressedTextureImage,
    GetCompressedTextureSubImage,
    GetBufferSubData,
    GetNamedBufferSubData,
    MapBuffer,            // only mappings for reading: a write-only one never waits for results
    MapBufferRange,
    MapNamedBuffer,
    MapNamedBufferRange,
    ClientWaitSync,       // only with a timeout > 0: timeout 0 is a poll
    GetQueryObjectiv,     // only GL_QUERY_RESULT: GL_QUERY_RESULT_AVAILABLE and _NO_WAIT never wait
    GetQueryObjectuiv,
    GetQueryObjecti64v,
    GetQueryObjectui64v,
    kCallCount
};

constexpr std::array<const char*, kCallCount> kNames = {
    "glFinish", "glReadPixels", "glReadnPixels", "glGetTexImage", "glGetnTexImage", "glGetTextureImage",
    "glGetTextureSubImage", "glGetCompressedTexImage", "glGetnCompressedTexImage", "glGetCompressedTextureImage",
    "glGetCompressedTextureSubImage", "glGetBufferSubData", "glGetNamedBufferSubData", "glMapBuffer",
    "glMapBufferRange", "glMapNamedBuffer", "glMapNamedBufferRange", "glClientWaitSync", "glGetQueryObjectiv",
    "glGetQueryObjectuiv", "glGetQueryObjecti64v", "glGetQueryObjectui64v"};

std::atomic<bool> recording{false};
std::array<std::atomic<unsigned>, kCallCount> counts{};

void note(Call c, bool waits = true) {
    if (waits && recording.load()) counts[std::size_t(c)].fetch_add(1);
}

// The next definition of `name` after this executable: libOpenGL's.
void* realSymbol(const char* name) {
    void* f = dlsym(RTLD_NEXT, name);
    if (f == nullptr) {
        std::fprintf(stderr, "test_frame_pipeline: dlsym(RTLD_NEXT, %s) failed: %s\n", name, dlerror());
        std::abort();
    }
    return f;
}

bool readsQueryResult(GLenum pname) { return pname == GL_QUERY_RESULT; }
bool mapsForReading(GLenum access) { return access == GL_READ_ONLY || access == GL_READ_WRITE; }
bool mapsRangeForReading(GLbitfield access) { return (access & GL_MAP_READ_BIT) != 0; }

}  // namespace stall

// The forwarding call, resolved once per entry point. decltype(&::name) is the header's prototype,
// so a definition below with the wrong signature does not compile.
#define CUBEAO_REAL(name) (reinterpret_cast<decltype(&::name)>([] {           \
    static void* const f = stall::realSymbol(#name);                          \
    return f;                                                                 \
}()))

extern "C" {

void APIENTRY glFinish(void) {
    stall::note(stall::Finish);
    CUBEAO_REAL(glFinish)();
}
void APIENTRY glReadPixels(GLint x, GLint y, GLsizei width, GLsizei height, GLenum format, GLenum type, void* pixels) {
    stall::note(stall::ReadPixels);
    CUBEAO_REAL(glReadPixels)(x, y, width, height, format, type, pixels);
}
void APIENTRY glReadnPixels(GLint x, GLint y, GLsizei width, GLsizei height, GLenum format, GLenum type,
                            GLsizei bufSize, void* data) {
    stall::note(stall::ReadnPixels);
    CUBEAO_REAL(glReadnPixels)(x, y, width, height, format, type, bufSize, data);
}
void APIENTRY glGetTexImage(GLenum target, GLint level, GLenum format, GLenum type, void* pixels) {
    stall::note(stall::GetTexImage);
    CUBEAO_REAL(glGetTexImage)(target, level, format, type, pixels);
}
void APIENTRY glGetnTexImage(GLenum target, GLint level, GLenum format, GLenum type, GLsizei bufSize, void* pixels) {
    stall::note(stall::GetnTexImage);
    CUBEAO_REAL(glGetnTexImage)(target, level, format, type, bufSize, pixels);
}
void APIENTRY glGetTextureImage(GLuint texture, GLint level, GLenum format, GLenum type, GLsizei bufSize,
                                void* pixels) {
    stall::note(stall::GetTextureImage);
    CUBEAO_REAL(glGetTextureImage)(texture, level, format, type, bufSize, pixels);
}
void APIENTRY glGetTextureSubImage(GLuint texture, GLint level, GLint xoffset, GLint yoffset, GLint zoffset,
                                   GLsizei width, GLsizei height, GLsizei depth, GLenum format, GLenum type,
                                   GLsizei bufSize, void* pixels) {
    stall::note(stall::GetTextureSubImage);
    CUBEAO_REAL(glGetTextureSubImage)(texture, level, xoffset, yoffset, zoffset, width, height, depth, format, type,
                                      bufSize, pixels);
}
void APIENTRY glGetCompressedTexImage(GLenum target, GLint level, void* img) {
    stall::note(stall::GetCompressedTexImage);
    CUBEAO_REAL(glGetCompressedTexImage)(target, level, img);
}
void APIENTRY glGetnCompressedTexImage(GLenum target, GLint lod, GLsizei bufSize, void* pixels) {
    stall::note(stall::GetnCompressedTexImage);
    CUBEAO_REAL(glGetnCompressedTexImage)(target, lod, bufSize, pixels);
}
void APIENTRY glGetCompressedTextureImage(GLuint texture, GLint level, GLsizei bufSize, void* pixels) {
    stall::note(stall::GetCompressedTextureImage);
    CUBEAO_REAL(glGetCompressedTextureImage)(texture, level, bufSize, pixels);
}
void APIENTRY glGetCompressedTextureSubImage(GLuint texture, GLint level, GLint xoffset, GLint yoffset, GLint zoffset,
                                             GLsizei width, GLsizei height, GLsizei depth, GLsizei bufSize,
                                             void* pixels) {
    stall::note(stall::GetCompressedTextureSubImage);
    CUBEAO_REAL(glGetCompressedTextureSubImage)(texture, level, xoffset, yoffset, zoffset, width, height, depth,
                                                bufSize, pixels);
}
void APIENTRY glGetBufferSubData(GLenum target, GLintptr offset, GLsizeiptr size, void* data) {
    stall::note(stall::GetBufferSubData);
    CUBEAO_REAL(glGetBufferSubData)(target, offset, size, data);
}
void APIENTRY glGetNamedBufferSubData(GLuint buffer, GLintptr offset, GLsizeiptr size, void* data) {
    stall::note(stall::GetNamedBufferSubData);
    CUBEAO_REAL(glGetNamedBufferSubData)(buffer, offset, size, data);
}
void* APIENTRY glMapBuffer(GLenum target, GLenum access) {
    stall::note(stall::MapBuffer, stall::mapsForReading(access));
    return CUBEAO_REAL(glMapBuffer)(target, access);
}
void* APIENTRY glMapBufferRange(GLenum target, GLintptr offset, GLsizeiptr length, GLbitfield access) {
    stall::note(stall::MapBufferRange, stall::mapsRangeForReading(access));
    return CUBEAO_REAL(glMapBufferRange)(target, offset, length, access);
}
void* APIENTRY glMapNamedBuffer(GLuint buffer, GLenum access) {
    stall::note(stall::MapNamedBuffer, stall::mapsForReading(access));
    return CUBEAO_REAL(glMapNamedBuffer)(buffer, access);
}
void* APIENTRY glMapNamedBufferRange(GLuint buffer, GLintptr offset, GLsizeiptr length, GLbitfield access) {
    stall::note(stall::MapNamedBufferRange, stall::mapsRangeForReading(access));
    return CUBEAO_REAL(glMapNamedBufferRange)(buffer, offset, length, access);
}
GLenum APIENTRY glClientWaitSync(GLsync sync, GLbitfield flags, GLuint64 timeout) {
    stall::note(stall::ClientWaitSync, timeout > 0);
    return CUBEAO_REAL(glClientWaitSync)(sync, flags, timeout);
}
void APIENTRY glGetQueryObjectiv(GLuint id, GLenum pname, GLint* params) {
    stall::note(stall::GetQueryObjectiv, stall::readsQueryResult(pname));
    CUBEAO_REAL(glGetQueryObjectiv)(id, pname, params);
}
void APIENTRY glGetQueryObjectuiv(GLuint id, GLenum pname, GLuint* params) {
    stall::note(stall::GetQueryObjectuiv, stall::readsQueryResult(pname));
    CUBEAO_REAL(glGetQueryObjectuiv)(id, pname, params);
}
void APIENTRY glGetQueryObjecti64v(GLuint id, GLenum pname, GLint64* params) {
    stall::note(stall::GetQueryObjecti64v, stall::readsQueryResult(pname));
    CUBEAO_REAL(glGetQueryObjecti64v)(id, pname, params);
}
void APIENTRY glGetQueryObjectui64v(GLuint id, GLenum pname, GLuint64* params) {
    stall::note(stall::GetQueryObjectui64v, stall::readsQueryResult(pname));
    CUBEAO_REAL(glGetQueryObjectui64v)(id, pname, params);
}

}  // extern "C"

namespace {

using namespace cubeao;
using namespace cubeao::test;

// What one recording saw, per entry point.
struct StallCounts {
    std::array<unsigned, stall::kCallCount> calls{};
    unsigned total() const {
        unsigned n = 0;
        for (unsigned c : calls) n += c;
        return n;
    }
    unsigned operator[](stall::Call c) const { return calls[std::size_t(c)]; }
    std::string text() const {  // "glFinish x8, glGetTextureImage x2" or "none"
        std::string s;
        for (std::size_t i = 0; i < calls.size(); ++i)
            if (calls[i] != 0)
                s += (s.empty() ? "" : ", ") + std::string(stall::kNames[i]) + " x" + std::to_string(calls[i]);
        return s.empty() ? "none" : s;
    }
};

// Counts the waiting GL calls made between construction and stop() (one recorder at a time).
class StallRecorder {
public:
    StallRecorder() {
        for (auto& c : stall::counts) c.store(0);
        stall::recording.store(true);
    }
    ~StallRecorder() { stall::recording.store(false); }
    StallRecorder(const StallRecorder&) = delete;
    StallRecorder& operator=(const StallRecorder&) = delete;
    StallCounts stop() {
        stall::recording.store(false);
        StallCounts out;
        for (std::size_t i = 0; i < out.calls.size(); ++i) out.calls[i] = stall::counts[i].load();
        return out;
    }
};

// ---- The AO methods under test -------------------------------------------------------------------

struct AoCase {
    const char* name;
    std::function<std::unique_ptr<AoPass>(const Scene&)> make;
};

void PrintTo(const AoCase& c, std::ostream* os) { *os << c.name; }  // gtest's "where GetParam() = …"

// Five probes baked small into the box room (once per process), as a pass with room for two of them,
// one upload per frame at most, and the GTAO fallback for what the resident ones do not see.
std::unique_ptr<AoPass> streamingProbes(const Scene& scene) {
    static const test::TempDir dir("pipeline-probes");
    static const CacheReader cache = [] {
        const glm::vec3 probes[] = {{1.0f, 1.2f, 1.5f}, {3.0f, 1.2f, 1.5f}, {5.0f, 1.2f, 1.5f}, {7.0f, 1.2f, 1.5f},
                                    {4.0f, 2.0f, 3.0f}};
        const std::string file = (dir / "probes.cubeao").string();
        test::bakeCache(boxRoom(), probes, test::bakeSettings(Estimator::Traced, 16, 1.0f, 4), file);
        return CacheReader(file);
    }();
    const std::size_t perProbe = probeGpuBytes(cache.params());
    ProbeProjectionSettings settings;
    settings.residency.uploadBytesPerFrame = perProbe;
    const ProbeProjectionPass unbudgeted(cache, scene.positions, scene.indices, settings);
    // (+ the staging ring a budgeted pass holds from the start, + the slack: feedback padding reserved)
    const std::size_t all = unbudgeted.gpuBytes() + unbudgeted.residency().stagingBytes();
    settings.residency.gpuBudgetBytes = all - 3 * perProbe + 1024;
    auto pass = std::make_unique<ProbeProjectionPass>(cache, scene.positions, scene.indices, settings);
    pass->setFallback(std::make_unique<GtaoFallback>(methodSettings(SsaoMethod::Gtao, cache.params().radius)));
    return pass;
}

std::vector<AoCase> aoMethods() {
    std::vector<AoCase> cases;
    for (SsaoMethod m : kMethods)
        cases.push_back({ssaoMethodName(m), [m](const Scene& s) {
                             return std::make_unique<SsaoPass>(methodSettings(m, s.defaultRadius()));
                         }});
    // The probe projection streaming under a budget (uploads through the staging ring, feedback read
    // through fences) with the GTAO fallback: all of it inside the frames.
    cases.push_back({"probes", [](const Scene& s) -> std::unique_ptr<AoPass> { return streamingProbes(s); }});
    return cases;
}

// Small frames keep llvmpipe quick; two sizes so the pipeline's texture reallocation is exercised too.
constexpr int kWidth = 64, kHeight = 48;

CameraView boxRoomView(std::size_t frame, int w = kWidth, int h = kHeight) {
    return viewOf(boxRoomPath(), frame % boxRoomPath().frames.size(), w, h);
}

Image readTexture(GLuint texture, int w, int h) {
    Image out(w, h);
    glGetTextureImage(texture, 0, GL_RED, GL_FLOAT, GLsizei(out.pixels.size() * sizeof(float)), out.pixels.data());
    return out;
}

std::vector<float> readRgb(GLuint texture, int w, int h) {
    std::vector<float> out(3 * std::size_t(w) * std::size_t(h));
    glGetTextureImage(texture, 0, GL_RGB, GL_FLOAT, GLsizei(out.size() * sizeof(float)), out.data());
    return out;
}

float maxAbsDifference(const std::vector<float>& a, const std::vector<float>& b) {
    float d = 0.0f;
    for (std::size_t i = 0; i < a.size(); ++i) d = std::max(d, std::abs(a[i] - b[i]));
    return d;
}

class PipelineGl : public GlTest, public ::testing::WithParamInterface<AoCase> {
protected:
    std::unique_ptr<FramePipeline> makePipeline() const {
        const Scene& scene = boxRoom();
        return std::make_unique<FramePipeline>(scene.positions, scene.indices, GetParam().make(scene), BlurSettings{},
                                               compositeSettings());
    }
    std::unique_ptr<FrameRenderer> makeRenderer() const {
        const Scene& scene = boxRoom();
        return std::make_unique<FrameRenderer>(scene.positions, scene.indices, GetParam().make(scene), BlurSettings{},
                                               compositeSettings());
    }
};

// Non-parameterised checks of the wrapper's own rules share the GL context fixture.
class StallWrapperGl : public GlTest {};

// ---- Tests ---------------------------------------------------------------------------------------

// The wrapper's rules on direct calls: what waits counts, the polls next to it do not.
TEST_F(StallWrapperGl, CountsWaitsAndNotPolls) {
    gl::Query query = gl::Query::create(GL_TIME_ELAPSED);
    glBeginQuery(GL_TIME_ELAPSED, query.id());
    glEndQuery(GL_TIME_ELAPSED);
    gl::Buffer buffer = gl::Buffer::create();
    glNamedBufferStorage(buffer.id(), 16, nullptr, GL_MAP_READ_BIT | GL_MAP_WRITE_BIT);
    const GLsync sync = glFenceSync(GL_SYNC_GPU_COMMANDS_COMPLETE, 0);

    StallRecorder polls;
    GLint available = 0;
    GLuint64 ns = 0;
    glGetQueryObjectiv(query.id(), GL_QUERY_RESULT_AVAILABLE, &available);
    glGetQueryObjectui64v(query.id(), GL_QUERY_RESULT_NO_WAIT, &ns);
    glClientWaitSync(sync, 0, 0);
    glMapNamedBufferRange(buffer.id(), 0, 16, GL_MAP_WRITE_BIT);
    glUnmapNamedBuffer(buffer.id());
    const StallCounts none = polls.stop();
    EXPECT_EQ(none.total(), 0u) << none.text();

    StallRecorder waits;
    glClientWaitSync(sync, GL_SYNC_FLUSH_COMMANDS_BIT, 1'000'000'000);
    glGetQueryObjectui64v(query.id(), GL_QUERY_RESULT, &ns);
    glMapNamedBufferRange(buffer.id(), 0, 16, GL_MAP_READ_BIT);
    glUnmapNamedBuffer(buffer.id());
    glFinish();
    const StallCounts some = waits.stop();
    EXPECT_EQ(some[stall::ClientWaitSync], 1u) << some.text();
    EXPECT_EQ(some[stall::GetQueryObjectui64v], 1u) << some.text();
    EXPECT_EQ(some[stall::MapNamedBufferRange], 1u) << some.text();
    EXPECT_EQ(some[stall::Finish], 1u) << some.text();
    EXPECT_EQ(some.total(), 4u) << some.text();
    glDeleteSync(sync);
}

// The point of the file. The measuring renderer first, through the same recorder: it must be seen to
// wait (glFinish and timer results in gl::timeGpu, the read-back), which proves that calls made inside
// the static libraries reach the wrapper. Then the pipeline over several frames, polling its timings
// every frame and changing the frame size half-way (texture reallocation): not one waiting call.
TEST_P(PipelineGl, NeverWaitsWhereTheMeasuringRendererDoes) {
    {
        const std::unique_ptr<FrameRenderer> renderer = makeRenderer();
        StallRecorder recorder;
        renderer->render(boxRoomView(0), 0);
        const StallCounts seen = recorder.stop();
        EXPECT_GT(seen[stall::Finish], 0u) << seen.text();
        EXPECT_GT(seen[stall::GetQueryObjectui64v], 0u) << seen.text();
        EXPECT_GT(seen[stall::GetTextureImage], 0u) << seen.text();
        std::printf("[ info ] %s: FrameRenderer::render, one frame: %s\n", GetParam().name, seen.text().c_str());
    }
    const std::unique_ptr<FramePipeline> pipeline = makePipeline();
    StallRecorder recorder;
    for (std::uint32_t f = 0; f < 8; ++f) {
        const bool small = f >= 4;
        pipeline->render(boxRoomView(f, small ? 48 : kWidth, small ? 32 : kHeight), f);
        (void)pipeline->latestTimings();
    }
    const StallCounts seen = recorder.stop();
    EXPECT_EQ(seen.total(), 0u) << GetParam().name << ", FramePipeline::render, 8 frames: " << seen.text();
    EXPECT_EQ(pipeline->width(), 48);
    EXPECT_EQ(pipeline->height(), 32);
}

// Timer results arrive from the ring by polling alone: render until one has (bounded), then check it
// names a frame that was rendered. After a glFinish (outside the pipeline) every pending frame's
// results are available, so the newest must be the last frame.
TEST_P(PipelineGl, TimingsArriveFromTheRing) {
    const std::unique_ptr<FramePipeline> pipeline = makePipeline();
    std::optional<PipelineTimings> t;
    std::uint64_t rendered = 0;
    for (; rendered < 200 && !(t && rendered >= FramePipeline::kTimingFrames); ++rendered) {
        pipeline->render(boxRoomView(rendered), std::uint32_t(100 + rendered));
        t = pipeline->latestTimings();
        if (!t) std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    ASSERT_TRUE(t.has_value()) << GetParam().name << ": no timings after " << rendered << " frames, "
                               << pipeline->droppedTimings() << " dropped";
    EXPECT_LT(t->serial, rendered);
    EXPECT_EQ(t->frame, std::uint32_t(100 + t->serial));
    // Only sanity: on llvmpipe GL_TIME_ELAPSED reads 0 for compute passes and the host's uptime for the
    // G-buffer's draw (frame_pipeline.h), so the values themselves say nothing there.
    for (double ms : {t->passes.gbuffer, t->passes.ao, t->passes.blur, t->passes.composite})
        EXPECT_TRUE(std::isfinite(ms) && ms >= 0.0) << ms;
    EXPECT_EQ(t->passes.readback, 0.0);
    std::printf("[ info ] %s: first timings (frame %llu) after %llu frames, %llu dropped; gbuffer %.3f ao %.3f blur "
                "%.3f composite %.3f ms (GL_TIME_ELAPSED, %s)\n",
                GetParam().name, static_cast<unsigned long long>(t->serial), static_cast<unsigned long long>(rendered),
                static_cast<unsigned long long>(pipeline->droppedTimings()), t->passes.gbuffer, t->passes.ao,
                t->passes.blur, t->passes.composite,
                pipeline->timesAreExecution() ? "execution time" : "not execution time on this renderer");

    glFinish();
    const std::optional<PipelineTimings> last = pipeline->latestTimings();
    ASSERT_TRUE(last.has_value());
    EXPECT_EQ(last->serial, rendered - 1);
    EXPECT_EQ(last->frame, std::uint32_t(100 + rendered - 1));
}

// The same frame through both: the pipeline's textures, read back after the fact (not recorded), equal
// the measuring renderer's read-back and raw AO. Two frames, so per-frame noise keys and reuse of the
// pipeline's textures are both covered; the AO must show some occlusion, or equality would be empty.
TEST_P(PipelineGl, RendersWhatTheMeasuringRendererRenders) {
    const std::unique_ptr<FrameRenderer> renderer = makeRenderer();
    const std::unique_ptr<FramePipeline> pipeline = makePipeline();
    for (std::uint32_t f : {0u, 7u}) {
        const CameraView view = boxRoomView(f);
        const RenderedFrame expected = renderer->render(view, f);
        const Image expectedRaw = renderer->readRawAo();
        pipeline->render(view, f);
        const Image ao = readTexture(pipeline->aoTexture(), kWidth, kHeight);
        const Image raw = readTexture(pipeline->rawAoTexture(), kWidth, kHeight);
        const std::vector<float> shaded = readRgb(pipeline->shadedTexture(), kWidth, kHeight);
        EXPECT_EQ(maxAbsDifference(raw.pixels, expectedRaw.pixels), 0.0f) << GetParam().name << " frame " << f;
        EXPECT_EQ(maxAbsDifference(ao.pixels, expected.ao.pixels), 0.0f) << GetParam().name << " frame " << f;
        EXPECT_EQ(maxAbsDifference(shaded, expected.shadedRgb), 0.0f) << GetParam().name << " frame " << f;
        EXPECT_LT(*std::min_element(ao.pixels.begin(), ao.pixels.end()), 0.9f) << GetParam().name << " frame " << f;
    }
}

// The probe pass's pixel shares for a frame loop (a viewer's panel): latestPixelShares() polls a fenced
// ring and never waits (recorded), and once the GPU is done (glFinish outside the recording) the newest
// it returns equals the blocking read of the last frame's counters.
TEST_F(StallWrapperGl, ProbePixelSharesArriveWithoutWaiting) {
    const Scene& scene = boxRoom();
    FramePipeline pipeline(scene.positions, scene.indices, streamingProbes(scene), BlurSettings{}, compositeSettings());
    auto& pass = dynamic_cast<ProbeProjectionPass&>(pipeline.method());
    StallRecorder recorder;
    std::optional<ProbeProjectionPass::PixelShares> shares;
    for (std::uint32_t f = 0; f < 8; ++f) {
        pipeline.render(boxRoomView(f), f);
        if (auto s = pass.latestPixelShares()) shares = s;
    }
    const StallCounts seen = recorder.stop();
    EXPECT_EQ(seen.total(), 0u) << seen.text();
    glFinish();
    const std::optional<ProbeProjectionPass::PixelShares> last = pass.latestPixelShares();
    ASSERT_TRUE(last.has_value());
    const ProbeProjectionPass::PixelShares now = pass.pixelShares();  // blocking read of the same frame
    EXPECT_EQ(last->geometry, now.geometry);
    EXPECT_EQ(last->uncovered, now.uncovered);
    EXPECT_EQ(last->fallbackProbe, now.fallbackProbe);
    EXPECT_GT(last->geometry, 0.5);
}

INSTANTIATE_TEST_SUITE_P(Methods, PipelineGl, ::testing::ValuesIn(aoMethods()),
                         [](const ::testing::TestParamInfo<AoCase>& info) { return std::string(info.param.name); });

}  // namespace
