// The viewer's view modes (issue 14, "Every view mode renders without GL errors") and the probe
// projection's diagnostics they show (ProbeProjectionPass::setDiagnostics): diagnostics change
// nothing of the AO or the counters, their path codes are the counters' pixels, their probe ids are
// live probes exactly where a probe shaded the pixel; every mode draws into an FBO without a GL error
// (glGetError and the debug output, which gl/context.cpp logs at error level) and shows an image.
//
// ViewModesGl.DISABLED_WriteEveryModeOfACloisterFrame writes a PNG per mode for people to look at:
// run it with --gtest_also_run_disabled_tests and CUBEAO_VIEW_MODES_PNGS=DIR.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <mutex>
#include <set>
#include <string>
#include <vector>

#include <spdlog/sinks/base_sink.h>
#include <spdlog/spdlog.h>

#include "common/viewer_layout.h"
#include "cubeao-view/view_modes.h"
#include "cubeao/cache/cache_file.h"
#include "cubeao/core/camera.h"
#include "cubeao/metrics/image_io.h"
#include "cubeao/reference/ao_reference.h"
#include "cubeao/reference/embree_scene.h"
#include "cubeao/runtime/probe_projection.h"
#include "cubeao/runtime/renderer.h"
#include "cubeao/scene/builtin.h"
#include "cubeao/ssao/gtao_fallback.h"
#include "cubeao/ssao/ssao_pass.h"
#include "bake_test_settings.h"
#include "gl_interface.h"
#include "runtime_test_util.h"
#include "test_util.h"

namespace {

using namespace cubeao;
using viewer::ViewInputs;
using viewer::ViewMode;

// ---- the scene, its cache and the frames -------------------------------------------------------

const Scene& cloister() {
    static const Scene scene = makeBuiltinScene("builtin:cloister");
    return scene;
}

// Seven probes along the south walk and in the garth, seen from the start of the builtin walk: the
// far walks are left to the screen-space fallback, so every path shows up.
struct CloisterCache {
    test::TempDir dir{"view-modes"};
    std::string path = (dir / "cloister.cubeao").string();
    CloisterCache() {
        const std::vector<glm::vec3> probes = {{-5.0f, 1.6f, -9.75f}, {-1.0f, 1.6f, -9.75f}, {3.0f, 1.6f, -9.75f},
                                               {7.0f, 1.6f, -9.75f},  {-4.0f, 1.5f, -4.0f},  {2.0f, 1.5f, -3.0f},
                                               {6.0f, 1.5f, -5.0f}};
        // hsplit: quick, and its confidence varies (traced's is 1 everywhere).
        const float radius = cloister().defaultRadius();
        test::bakeCache(cloister(), probes, test::bakeSettings(Estimator::HorizonSplit, 32, radius, 32), path);
    }
};

const CloisterCache& cloisterCache() {
    static const CloisterCache cache;
    return cache;
}

CameraView frameView(std::size_t frame, int w, int h) {
    return test::viewOf(builtinCameraPath("builtin:cloister"), frame, w, h);
}

SsaoSettings gtaoSettings() { return test::methodSettings(SsaoMethod::Gtao, cloister().defaultRadius()); }

// A probe pass over the cloister with the GTAO fallback, under a budget that holds all probes but
// three (so some pixels pass over a probe that is not resident: the fallback-probe path), loading one
// probe per frame after the first.
std::unique_ptr<FrameRenderer> probeRenderer(const CacheReader& cache) {
    const std::size_t perProbe = probeGpuBytes(cache.params());
    ProbeProjectionSettings s;
    s.residency.uploadBytesPerFrame = perProbe;
    const ProbeProjectionPass unbudgeted(cache, cloister().positions, cloister().indices, s);
    // (+ the staging ring a budgeted pass holds from the start, + the feedback ring's alignment slack)
    const std::size_t all = unbudgeted.gpuBytes() + unbudgeted.residency().stagingBytes();
    s.residency.gpuBudgetBytes = all - 3 * perProbe + 1024;
    auto pass = std::make_unique<ProbeProjectionPass>(cache, cloister().positions, cloister().indices, s);
    pass->setFallback(std::make_unique<GtaoFallback>(gtaoSettings()));
    return std::make_unique<FrameRenderer>(cloister().positions, cloister().indices, std::move(pass), BlurSettings{},
                                           test::compositeSettings());
}

ProbeProjectionPass& projection(FrameRenderer& r) { return dynamic_cast<ProbeProjectionPass&>(r.method()); }

// The RGBA32F diagnostics of the last frame, 4 floats per pixel, row 0 at the top.
std::vector<float> readDiagnostics(const ProbeProjectionPass& pass, int w, int h) {
    std::vector<float> d(std::size_t(w) * std::size_t(h) * 4);
    glGetTextureImage(pass.diagnosticsTexture(), 0, GL_RGBA, GL_FLOAT, GLsizei(d.size() * sizeof(float)), d.data());
    return d;
}

gl::Texture uploadR32f(const Image& image) {
    gl::Texture t = gl::Texture::create(GL_TEXTURE_2D);
    glTextureStorage2D(t.id(), 1, GL_R32F, image.width, image.height);
    glTextureSubImage2D(t.id(), 0, 0, 0, image.width, image.height, GL_RED, GL_FLOAT, image.pixels.data());
    return t;
}

// ---- GL errors ---------------------------------------------------------------------------------

// Counts messages at error level or above: gl/context.cpp logs GL debug errors (and anything the
// driver calls high severity) there.
class ErrorCountingSink : public spdlog::sinks::base_sink<std::mutex> {
public:
    int errors = 0;

protected:
    void sink_it_(const spdlog::details::log_msg& msg) override {
        if (msg.level >= spdlog::level::err) ++errors;
    }
    void flush_() override {}
};

// Attaches an ErrorCountingSink to the default logger for its lifetime.
class GlErrorWatch {
public:
    GlErrorWatch() : sink_(std::make_shared<ErrorCountingSink>()) {
        while (glGetError() != GL_NO_ERROR) {
        }
        spdlog::default_logger()->sinks().push_back(sink_);
    }
    ~GlErrorWatch() {
        auto& sinks = spdlog::default_logger()->sinks();
        sinks.erase(std::remove(sinks.begin(), sinks.end(), sink_), sinks.end());
    }
    int debugErrors() const { return sink_->errors; }

private:
    std::shared_ptr<ErrorCountingSink> sink_;
};

// ---- drawing into an FBO -----------------------------------------------------------------------

struct Target {
    int width, height;
    gl::Texture colour;
    gl::Framebuffer fbo;
    Target(int w, int h) : width(w), height(h) {
        colour = gl::Texture::create(GL_TEXTURE_2D);
        glTextureStorage2D(colour.id(), 1, GL_RGBA8, w, h);
        fbo = gl::Framebuffer::create();
        glNamedFramebufferTexture(fbo.id(), GL_COLOR_ATTACHMENT0, colour.id(), 0);
        glBindFramebuffer(GL_DRAW_FRAMEBUFFER, fbo.id());
        glBindFramebuffer(GL_READ_FRAMEBUFFER, fbo.id());
    }
    ~Target() { glBindFramebuffer(GL_FRAMEBUFFER, 0); }
    void clear(float r, float g, float b) {
        const float c[4] = {r, g, b, 1.0f};
        glClearNamedFramebufferfv(fbo.id(), GL_COLOR, 0, c);
    }
    // RGBA bytes, GL's order: row 0 at the bottom.
    std::vector<std::uint8_t> read() const {
        std::vector<std::uint8_t> p(std::size_t(width) * std::size_t(height) * 4);
        glReadPixels(0, 0, width, height, GL_RGBA, GL_UNSIGNED_BYTE, p.data());
        return p;
    }
    std::uint32_t pixel(const std::vector<std::uint8_t>& p, int x, int yFromBottom) const {
        const std::size_t i = (std::size_t(yFromBottom) * std::size_t(width) + std::size_t(x)) * 4;
        return std::uint32_t(p[i]) | std::uint32_t(p[i + 1]) << 8 | std::uint32_t(p[i + 2]) << 16;
    }
};

std::size_t distinctColours(const Target& t, const std::vector<std::uint8_t>& p) {
    std::set<std::uint32_t> colours;
    for (int y = 0; y < t.height; ++y)
        for (int x = 0; x < t.width; ++x) colours.insert(t.pixel(p, x, y));
    return colours.size();
}

// Every input of the modes for frame `frame` at w × h: the probe pass with diagnostics, a GTAO
// baseline and the Embree reference.
struct ModeFrame {
    std::unique_ptr<FrameRenderer> probes, baseline;
    gl::Texture reference;
    ViewInputs inputs;
    ModeFrame(const CacheReader& cache, std::size_t frame, int w, int h, int referenceSpp) {
        const CameraView view = frameView(frame, w, h);
        probes = probeRenderer(cache);
        projection(*probes).setDiagnostics(true);
        for (int f = 0; f < 4; ++f) probes->render(view, std::uint32_t(frame));  // let the budget's pool settle
        baseline = std::make_unique<FrameRenderer>(cloister().positions, cloister().indices,
                                                   std::make_unique<SsaoPass>(gtaoSettings()), BlurSettings{},
                                                   test::compositeSettings());
        baseline->render(view, std::uint32_t(frame));
        const EmbreeScene embree(cloister());
        AoSettings ao;
        ao.radius = cloister().defaultRadius();
        ao.spp = referenceSpp;
        const PinholeCamera camera(builtinCameraPath("builtin:cloister"), frame, w, h);
        reference = uploadR32f(renderReferenceFrame(embree, camera, ao, std::uint32_t(frame), nullptr).ao);
        inputs.shaded = probes->pipeline().shadedTexture();
        inputs.ao = probes->pipeline().aoTexture();
        inputs.diagnostics = projection(*probes).diagnosticsTexture();
        inputs.baselineAo = baseline->pipeline().aoTexture();
        inputs.reference = reference.id();
        inputs.footprintScale = cloister().defaultRadius() / 16.0f;
    }
};

// ---- names -------------------------------------------------------------------------------------

TEST(ViewModes, NamesRoundTripAndEveryModeHasALegend) {
    std::set<std::string> names;
    ASSERT_EQ(viewer::allViewModes().size(), 8u);
    for (ViewMode mode : viewer::allViewModes()) {
        names.insert(viewer::viewModeName(mode));
        EXPECT_EQ(viewer::parseViewMode(viewer::viewModeName(mode)), mode);
        EXPECT_GT(std::string(viewer::viewModeLegend(mode)).size(), 10u) << viewer::viewModeName(mode);
    }
    EXPECT_EQ(names, (std::set<std::string>{"shaded", "ao", "probe", "footprint", "confidence", "path", "baseline",
                                            "diff"}));
    EXPECT_FALSE(viewer::parseViewMode("Shaded").has_value());
    EXPECT_FALSE(viewer::parseViewMode("").has_value());
}

// ---- diagnostics -------------------------------------------------------------------------------

class DiagnosticsGl : public GlTest {};

// Two identical passes walking the first frames of the cloister, one with diagnostics: the same raw
// and blurred AO, the same pixel shares and fetch counts, frame by frame (the residency's feedback,
// and with it what streams in, is then the same too).
TEST_F(DiagnosticsGl, OnOrOffTheAoAndTheCountersAreBitIdentical) {
    const CacheReader cache(cloisterCache().path);
    auto plain = probeRenderer(cache), diagnosed = probeRenderer(cache);
    projection(*diagnosed).setDiagnostics(true);
    EXPECT_EQ(projection(*diagnosed).diagnosticsTexture(), 0u) << "no frame yet";
    const int w = 64, h = 48;
    for (std::uint32_t frame = 0; frame < 6; ++frame) {
        const CameraView view = frameView(frame, w, h);
        const RenderedFrame a = plain->render(view, frame), b = diagnosed->render(view, frame);
        EXPECT_EQ(a.ao.pixels, b.ao.pixels) << "frame " << frame;
        EXPECT_EQ(plain->readRawAo().pixels, diagnosed->readRawAo().pixels) << "frame " << frame;
        const auto sa = projection(*plain).pixelShares(), sb = projection(*diagnosed).pixelShares();
        EXPECT_EQ(sa.geometry, sb.geometry) << "frame " << frame;
        EXPECT_EQ(sa.uncovered, sb.uncovered) << "frame " << frame;
        EXPECT_EQ(sa.fallbackProbe, sb.fallbackProbe) << "frame " << frame;
        EXPECT_EQ(projection(*plain).fetchesPerPixel(), projection(*diagnosed).fetchesPerPixel()) << "frame " << frame;
    }
    EXPECT_NE(projection(*diagnosed).diagnosticsTexture(), 0u);
    EXPECT_EQ(projection(*diagnosed).allocatedGpuBytes(), projection(*diagnosed).gpuBytes());
    EXPECT_EQ(projection(*diagnosed).gpuBytes(), projection(*plain).gpuBytes() + std::size_t(w * h * 16))
        << "the diagnostics image is one RGBA32F texel per pixel";
    projection(*diagnosed).setDiagnostics(false);
    EXPECT_EQ(projection(*diagnosed).diagnosticsTexture(), 0u);
    EXPECT_EQ(projection(*diagnosed).gpuBytes(), projection(*plain).gpuBytes());
    const CameraView view = frameView(6, w, h);
    EXPECT_EQ(plain->render(view, 6).ao.pixels, diagnosed->render(view, 6).ao.pixels) << "switched off again";
}

// Frame by frame, the path codes count what the pass's counters count; probe ids are live probes
// exactly where a probe shaded the pixel and −1 elsewhere; footprints and confidences are in range.
TEST_F(DiagnosticsGl, PathCodesAreThePixelSharesAndProbeIdsAreLiveProbesWhereAProbeShaded) {
    const CacheReader cache(cloisterCache().path);
    auto r = probeRenderer(cache);
    ProbeProjectionPass& pass = projection(*r);
    pass.setDiagnostics(true);
    const int w = 64, h = 48;
    std::size_t seen[4] = {0, 0, 0, 0};  // pixels per path over all frames
    for (std::uint32_t frame = 0; frame < 6; ++frame) {
        r->render(frameView(frame, w, h), frame);
        const std::vector<float> d = readDiagnostics(pass, w, h);
        const CameraGBufferImage g = r->gbuffer().readBack();
        std::size_t count[4] = {0, 0, 0, 0};
        int bad = 0;
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                const float* t = &d[(std::size_t(y) * std::size_t(w) + std::size_t(x)) * 4];
                const int path = int(t[3]);
                ASSERT_TRUE(t[3] == float(path) && path >= 0 && path <= 3) << "path " << t[3];
                ++count[path];
                const bool probe = path == 1 || path == 2;
                bool ok = (path == 0) == g.empty(x, y);
                if (probe) {
                    const auto id = std::uint32_t(t[0]);
                    ok = ok && t[0] == float(id) && pass.source().isLive(ProbeId{id});
                    ok = ok && std::isfinite(t[1]) && t[1] > 0.0f && t[2] >= 0.0f && t[2] <= 1.0f;
                } else {
                    ok = ok && t[0] == -1.0f;
                }
                if (!ok && bad++ < 5)
                    ADD_FAILURE() << "frame " << frame << " pixel " << x << "," << y << ": id " << t[0] << " footprint "
                                  << t[1] << " confidence " << t[2] << " path " << t[3];
            }
        const auto shares = pass.pixelShares();
        const double pixels = double(w * h);
        EXPECT_EQ(double(w * h - count[0]) / pixels, shares.geometry) << "frame " << frame;
        EXPECT_EQ(double(count[3]) / pixels, shares.uncovered) << "frame " << frame;
        EXPECT_EQ(double(count[2]) / pixels, shares.fallbackProbe) << "frame " << frame;
        for (int p = 0; p < 4; ++p) seen[p] += count[p];
    }
    // The case must exercise every path, or the checks above prove little.
    EXPECT_GT(seen[0], 0u) << "sky";
    EXPECT_GT(seen[1], 0u) << "probe";
    EXPECT_GT(seen[2], 0u) << "fallback probe: the budget holds all probes but three";
    EXPECT_GT(seen[3], 0u) << "screen space: the far walks have no probe";
}

// ---- view modes --------------------------------------------------------------------------------

class ViewModesGl : public GlTest {};

// Every mode draws into a 64 × 48 FBO with no GL error, and with its inputs given shows an image
// (not one colour); with none given each draws the "not available" stripes and says so.
TEST_F(ViewModesGl, EveryModeDrawsWithoutGlErrorsAndShowsAnImage) {
    const CacheReader cache(cloisterCache().path);
    const int w = 64, h = 48;
    const ModeFrame frame(cache, 0, w, h, 16);
    const GlErrorWatch watch;
    viewer::ViewModes modes;
    Target target(w, h);
    for (ViewMode mode : viewer::allViewModes()) {
        const char* name = viewer::viewModeName(mode);
        target.clear(1.0f, 0.0f, 1.0f);
        EXPECT_TRUE(viewer::viewModeAvailable(mode, frame.inputs)) << name;
        EXPECT_TRUE(modes.draw(mode, frame.inputs, 0, 0, w, h)) << name;
        const std::vector<std::uint8_t> p = target.read();
        EXPECT_EQ(glGetError(), GLenum(GL_NO_ERROR)) << name;
        EXPECT_GE(distinctColours(target, p), 8u) << name << ": an image, not a constant colour";

        target.clear(1.0f, 0.0f, 1.0f);
        EXPECT_FALSE(modes.draw(mode, ViewInputs{}, 0, 0, w, h)) << name;
        const std::vector<std::uint8_t> stripes = target.read();
        EXPECT_EQ(glGetError(), GLenum(GL_NO_ERROR)) << name;
        EXPECT_EQ(distinctColours(target, stripes), 2u) << name << ": the two greys of the stripes";
    }
    EXPECT_EQ(watch.debugErrors(), 0) << "GL debug output reported errors (see the log above)";
}

// view.frag reads its parameters as viewer_layout.h's ViewBlock, at the C++ offsets.
TEST_F(ViewModesGl, TheShaderReadsTheSharedViewBlock) {
    const viewer::ViewModes modes;
    using B = kernel::ViewBlock;
    test::expectUniformBlock<B>(modes.program(), "ViewUniforms", "viewer", kernel::kViewBlock,
                                {CUBEAO_MEMBER(B, viewportRect), CUBEAO_MEMBER(B, mode),
                                 CUBEAO_MEMBER(B, footprintScale), CUBEAO_MEMBER(B, hasAo),
                                 CUBEAO_MEMBER(B, encodeSrgb)},
                                "view.frag");
}

// Texture row 0 is the image top: it must land in the top row of the framebuffer (GL's last row).
// And a draw into a sub-rectangle leaves the rest of the framebuffer alone and the viewport as it was.
TEST_F(ViewModesGl, TheImageIsUprightAndFillsOnlyItsViewport) {
    const int w = 8, h = 6;
    Image ao(w, h, 0.0f);
    for (int x = 0; x < w; ++x) ao.at(x, 0) = 1.0f;  // the top row open (white), the rest black
    const gl::Texture texture = uploadR32f(ao);
    const GlErrorWatch watch;
    viewer::ViewModes modes;
    ViewInputs in;
    in.ao = texture.id();
    Target target(32, 24);
    target.clear(1.0f, 0.0f, 0.0f);
    glViewport(1, 2, 3, 4);
    ASSERT_TRUE(modes.draw(ViewMode::Ao, in, 8, 6, 16, 12));  // each texel 2 × 2 pixels
    GLint viewport[4];
    glGetIntegerv(GL_VIEWPORT, viewport);
    EXPECT_EQ(std::vector<GLint>(viewport, viewport + 4), (std::vector<GLint>{1, 2, 3, 4}));
    const std::vector<std::uint8_t> p = target.read();
    const std::uint32_t white = 0xffffff, black = 0, red = 0xff;
    EXPECT_EQ(target.pixel(p, 8, 6 + 11), white) << "top row of the viewport";
    EXPECT_EQ(target.pixel(p, 23, 6 + 10), white);
    EXPECT_EQ(target.pixel(p, 8, 6 + 9), black);
    EXPECT_EQ(target.pixel(p, 23, 6), black) << "bottom row of the viewport";
    EXPECT_EQ(target.pixel(p, 7, 6), red) << "left of the viewport";
    EXPECT_EQ(target.pixel(p, 24, 17), red) << "right of the viewport";
    EXPECT_EQ(target.pixel(p, 8, 18), red) << "above the viewport";
    EXPECT_EQ(target.pixel(p, 8, 5), red) << "below the viewport";
    EXPECT_EQ(glGetError(), GLenum(GL_NO_ERROR));
    EXPECT_EQ(watch.debugErrors(), 0);
}

// The watch above is not vacuous: a GL error made on purpose reaches it (it logs one "GL error" line).
TEST_F(ViewModesGl, TheGlErrorWatchSeesAnError) {
    if (!context_->debugOutput()) GTEST_SKIP() << "no GL debug output in this context";
    const GlErrorWatch watch;
    glEnable(GLenum(0x1234));  // not a capability: GL_INVALID_ENUM
    EXPECT_EQ(glGetError(), GLenum(GL_INVALID_ENUM));
    glFinish();  // delivers an asynchronous message (a context without GL_DEBUG_OUTPUT_SYNCHRONOUS)
    EXPECT_GT(watch.debugErrors(), 0);
}

// Not a test: a PNG of every mode of a cloister frame, for people to look at (see the top of the file).
TEST_F(ViewModesGl, DISABLED_WriteEveryModeOfACloisterFrame) {
    const char* dir = std::getenv("CUBEAO_VIEW_MODES_PNGS");
    if (dir == nullptr || *dir == '\0') GTEST_SKIP() << "set CUBEAO_VIEW_MODES_PNGS=DIR";
    std::filesystem::create_directories(dir);
    const char* frameEnv = std::getenv("CUBEAO_VIEW_MODES_FRAME");
    const std::size_t frameIndex = frameEnv ? std::size_t(std::atoi(frameEnv)) : 0;
    const CacheReader cache(cloisterCache().path);
    const int w = 480, h = 270;
    const ModeFrame frame(cache, frameIndex, w, h, 64);
    const GlErrorWatch watch;
    viewer::ViewModes modes;
    Target target(w, h);
    for (ViewMode mode : viewer::allViewModes()) {
        ASSERT_TRUE(modes.draw(mode, frame.inputs, 0, 0, w, h));
        const std::vector<std::uint8_t> p = target.read();
        std::vector<float> rgb(std::size_t(w) * std::size_t(h) * 3);
        for (int y = 0; y < h; ++y)  // GL's rows bottom up, the PNG's top down
            for (int x = 0; x < w; ++x)
                for (int c = 0; c < 3; ++c)
                    rgb[(std::size_t(y) * std::size_t(w) + std::size_t(x)) * 3 + std::size_t(c)] =
                        float(p[(std::size_t(h - 1 - y) * std::size_t(w) + std::size_t(x)) * 4 + std::size_t(c)]) /
                        255.0f;
        writePngRgb(std::filesystem::path(dir) / (std::string(viewer::viewModeName(mode)) + ".png"), w, h, rgb);
    }
    const auto shares = projection(*frame.probes).pixelShares();
    std::printf("[ info ] cloister frame %zu %dx%d: geometry %.3f, uncovered %.3f, fallback probe %.3f\n", frameIndex,
                w, h, shares.geometry, shares.uncovered, shares.fallbackProbe);
    const std::vector<float> d = readDiagnostics(projection(*frame.probes), w, h);
    double confidence = 0.0, footprint = 0.0, probePixels = 0.0, doubtful = 0.0;
    for (std::size_t i = 0; i < d.size(); i += 4)
        if (d[i + 3] == 1.0f || d[i + 3] == 2.0f)
            probePixels += 1.0, footprint += d[i + 1], confidence += d[i + 2], doubtful += d[i + 2] < 0.9f ? 1.0 : 0.0;
    std::printf("[ info ] probe pixels: mean footprint %.4f (scale %.4f), mean confidence %.3f, below 0.9: %.3f\n",
                footprint / probePixels, frame.inputs.footprintScale, confidence / probePixels, doubtful / probePixels);
    EXPECT_EQ(glGetError(), GLenum(GL_NO_ERROR));
    EXPECT_EQ(watch.debugErrors(), 0);
}

}  // namespace
