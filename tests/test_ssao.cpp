// The run-time camera side and the screen-space baselines (src/cubeao/runtime/, src/cubeao/ssao/):
// camera conventions against PinholeCamera, the camera G-buffer against Embree primary rays, each
// method on an open plane (no self-occlusion) and against the Embree reference, the edge-aware blur
// (edges kept, noise reduced, GPU == CPU twin) and `cubeao render` end to end.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <map>
#include <memory>
#include <random>
#include <sys/wait.h>

#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>
#include <nlohmann/json.hpp>

#include "cubeao/metrics/image_metrics.h"
#include "cubeao/reference/ao_reference.h"
#include "cubeao/reference/embree_scene.h"
#include "cubeao/runtime/blur.h"
#include "cubeao/runtime/camera_gbuffer.h"
#include "cubeao/runtime/composite.h"
#include "cubeao/runtime/renderer.h"
#include "cubeao/scene/builtin.h"
#include "cubeao/ssao/ssao_pass.h"
#include "gl_fixture.h"
#include "cli_run.h"
#include "cubeao/metrics/image_io.h"
#include "test_util.h"

namespace {

namespace fs = std::filesystem;
using namespace cubeao;
using cubeao::test::TempDir;

// ---- scenes -----------------------------------------------------------------------------------

struct Mesh {
    std::vector<glm::vec3> positions;
    std::vector<std::uint32_t> indices;
    void quad(glm::vec3 a, glm::vec3 b, glm::vec3 c, glm::vec3 d) {  // a b c d counter-clockwise
        const auto base = std::uint32_t(positions.size());
        positions.insert(positions.end(), {a, b, c, d});
        indices.insert(indices.end(), {base, base + 1, base + 2, base, base + 2, base + 3});
    }
};

const Scene& boxRoom() {
    static const Scene scene = makeBuiltinScene("builtin:box-room");
    return scene;
}
const CameraPath& boxRoomPath() {
    static const CameraPath path = builtinCameraPath("builtin:box-room");
    return path;
}

// A camera path of one frame.
CameraPath singleFrame(glm::vec3 eye, glm::vec3 target, float fovYDeg = 60.0f) {
    CameraPath p;
    p.fovYDeg = fovYDeg;
    p.frames.push_back({eye, target});
    return p;
}

CameraView viewOf(const CameraPath& path, std::size_t frame, int w, int h) {
    return CameraView::fromPinhole(PinholeCamera(path, frame, w, h), path.nearPlane);
}

SsaoSettings methodSettings(SsaoMethod m, float radius) {
    SsaoSettings s;
    s.method = m;
    s.radius = radius;
    return resolveSsaoSettings(s, radius);
}

CompositeSettings compositeSettings() {
    CompositeSettings c;
    c.lightDirection = defaultLightDirection({0.0f, 1.0f, 0.0f});
    return c;
}

constexpr std::array<SsaoMethod, 3> kMethods = {SsaoMethod::Alchemy, SsaoMethod::Hbao, SsaoMethod::Gtao};

double meanAbsoluteDifference(const Image& a, const Image& b) {
    double sum = 0.0;
    for (std::size_t i = 0; i < a.pixels.size(); ++i) sum += std::abs(double(a.pixels[i]) - double(b.pixels[i]));
    return sum / double(a.pixels.size());
}

// ---- camera conventions (no GL) -----------------------------------------------------------------

TEST(CameraView, PixelRaysArePinholeRays) {
    const CameraPath& path = boxRoomPath();
    for (std::size_t f : {std::size_t(0), std::size_t(17)}) {
        const PinholeCamera cam(path, f, 37, 21);
        const CameraView view = CameraView::fromPinhole(cam, path.nearPlane);
        const glm::mat3 worldFromView = glm::transpose(view.viewFromWorldRotation());
        for (int y : {0, 5, 20})
            for (int x : {0, 18, 36}) {
                const glm::vec3 world = glm::normalize(worldFromView * view.pixelRay(float(x), float(y)));
                const glm::vec3 expected = cam.rayDirection(x, y);
                EXPECT_NEAR(glm::length(world - expected), 0.0f, 1e-6f) << x << "," << y;
                // And back: a point on the ray projects to the pixel centre.
                const glm::vec2 px = view.projectToPixel(view.viewPosition(x, y, 3.7f));
                EXPECT_NEAR(px.x, x + 0.5f, 1e-4f);
                EXPECT_NEAR(px.y, y + 0.5f, 1e-4f);
            }
        // The eye maps to the view-space origin.
        EXPECT_NEAR(glm::length(glm::vec3(view.viewFromWorld * glm::vec4(cam.eye, 1.0f))), 0.0f, 1e-5f);
    }
}

TEST(CameraView, ReversedZPutsTheNearPlaneAtOne) {
    const CameraView view = viewOf(boxRoomPath(), 0, 64, 36);
    for (float d : {view.nearPlane, 1.0f, 100.0f}) {
        const glm::vec4 clip = view.clipFromView() * glm::vec4(0.0f, 0.0f, -d, 1.0f);
        EXPECT_NEAR(clip.z / clip.w, view.nearPlane / d, 1e-6f);
    }
    EXPECT_NEAR(view.projectedPixels(1.0f, 2.0f), 0.5f * view.focalPixels(), 1e-5f);
}

TEST(SsaoSettings, DefaultsAndEveryProblemAtOnce) {
    const SsaoSettings s = resolveSsaoSettings({}, 0.25f);
    EXPECT_EQ(s.radius, 0.25f);
    EXPECT_EQ(s.directions, 8);
    EXPECT_EQ(s.steps, 8);
    EXPECT_EQ(plannedFetchesPerPixel(s), 66);
    SsaoSettings bad;
    bad.directions = 3;
    bad.steps = 100;
    bad.radius = -1.0f;
    const std::string message = test::errorMessage([&] { resolveSsaoSettings(bad, 1.0f); });
    EXPECT_TRUE(test::contains(message, "directions 3")) << message;
    EXPECT_TRUE(test::contains(message, "steps 100")) << message;
    EXPECT_TRUE(test::contains(message, "--radius")) << message;
    EXPECT_EQ(parseSsaoMethod("hbao"), SsaoMethod::Hbao);
    EXPECT_TRUE(test::contains(test::errorMessage([] { parseSsaoMethod("ssao"); }), "alchemy, hbao or gtao"));
}

// ---- blur on the CPU (no GL) ---------------------------------------------------------------------

// Two planes facing the camera: the left half of the frame shows a near plane at depth 3, the right
// half a far one at depth 5 (a depth step down the middle column).
struct DepthStep {
    CameraView view;
    CameraGBufferImage g;
    int edge = 0;  // first column of the far plane
};

DepthStep depthStepImage(int w, int h) {
    DepthStep s;
    s.view.width = w, s.view.height = h;
    s.g.width = w, s.g.height = h;
    s.edge = w / 2;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            s.g.depth.push_back(x < s.edge ? 3.0f : 5.0f);
            s.g.normal.push_back({0.0f, 0.0f, 1.0f});
        }
    return s;
}

TEST(Blur, KeepsADepthStepAndSmoothsFlatNoise) {
    const DepthStep s = depthStepImage(48, 24);
    Image ao(48, 24);
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> noise(-0.1f, 0.1f);
    for (int y = 0; y < 24; ++y)
        for (int x = 0; x < 48; ++x) ao.at(x, y) = x < s.edge ? 0.0f : 0.5f + noise(rng);
    // AO 0 on the near side, noisy 0.5 on the far side. The depth term of blur.h is exactly 0 across a
    // step deeper than τ·z_c (0.1 · 3 < 2), so nothing crosses the edge at all: the stated bound
    // ("pixels more than 1 pixel from the edge change by < 0.02") holds with room to spare.
    const Image out = blurAoCpu(ao, s.g, s.view, BlurSettings{});
    double noiseBefore = 0.0, noiseAfter = 0.0;
    int farPixels = 0;
    for (int y = 0; y < 24; ++y)
        for (int x = 0; x < 48; ++x) {
            if (x < s.edge) {
                EXPECT_EQ(out.at(x, y), 0.0f) << x << "," << y;
            } else {
                noiseBefore += std::pow(ao.at(x, y) - 0.5, 2.0);
                noiseAfter += std::pow(out.at(x, y) - 0.5, 2.0);
                ++farPixels;
            }
        }
    // Noise on the flat side: the 5-tap Gaussian (r = 2) keeps Σw²/(Σw)² = 0.29 of the variance per
    // pass, so the standard deviation drops to ~0.29 of its value (a bit less far from the borders).
    EXPECT_LT(std::sqrt(noiseAfter / farPixels), 0.35 * std::sqrt(noiseBefore / farPixels));
    // Radius 0 is off.
    BlurSettings off;
    off.radius = 0;
    EXPECT_EQ(blurAoCpu(ao, s.g, s.view, off).pixels, ao.pixels);
}

TEST(Blur, ShallowStepBleedsAtMostItsWeight) {
    // A step of 2 % of the depth (under τ = 10 %) is a surface detail, not an edge: it blurs, with
    // tap weight 1 − 0.02/0.1 = 0.8. This pins the weight function down.
    DepthStep s = depthStepImage(16, 1);
    for (int x = s.edge; x < 16; ++x) s.g.depth[std::size_t(x)] = 3.06f;
    const glm::vec3 pc = s.view.viewPosition(7, 0, 3.0f), ps = s.view.viewPosition(8, 0, 3.06f);
    const float w = bilateralWeight({0, 0, 1}, pc, 3.0f, {0, 0, 1}, ps, BlurSettings{});
    EXPECT_NEAR(w, 0.8f, 1e-5f);
    // Perpendicular normals: ((0 + 1)/2)^10.
    EXPECT_NEAR(bilateralWeight({0, 0, 1}, pc, 3.0f, {1, 0, 0}, pc, BlurSettings{}), std::pow(0.5f, 10.0f), 1e-7f);
}

// ---- GL ------------------------------------------------------------------------------------------

class RuntimeGl : public GlTest {};

TEST_F(RuntimeGl, CameraGBufferMatchesEmbreePrimaryRays) {
    const Scene& scene = boxRoom();
    const EmbreeScene rt(scene);
    CameraGBuffer gbuffer(scene.positions, scene.indices);
    const int w = 160, h = 90;
    std::size_t pixels = 0, mismatched = 0;
    double worstDepth = 0.0;
    for (std::size_t f : {std::size_t(0), std::size_t(11), std::size_t(23)}) {
        const PinholeCamera cam(boxRoomPath(), f, w, h);
        const CameraView view = CameraView::fromPinhole(cam, boxRoomPath().nearPlane);
        gbuffer.render(view);  // the same object every frame: textures are reused
        const CameraGBufferImage g = gbuffer.readBack();
        const glm::mat3 worldFromView = glm::transpose(view.viewFromWorldRotation());
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                ++pixels;
                const glm::vec3 dir = cam.rayDirection(x, y);
                const RayHit hit = rt.intersect(cam.eye, dir, 0.0f, std::numeric_limits<float>::infinity());
                if (hit.hit != !g.empty(x, y)) {
                    ++mismatched;
                    continue;
                }
                if (!hit.hit) continue;
                const double t = double(g.depth[g.index(x, y)]) * glm::length(view.pixelRay(float(x), float(y)));
                const glm::vec3 n = worldFromView * g.normal[g.index(x, y)];
                const glm::vec3 expected = glm::dot(hit.normal, dir) > 0.0f ? -hit.normal : hit.normal;
                const double relative = std::abs(t - hit.t) / hit.t;
                // Pixel centres on a triangle edge may pick either triangle (rasteriser tie rules vs
                // Embree's): count, not fail, when the two hit different surfaces.
                if (relative > 1e-4 || glm::dot(n, expected) < 1.0f - 1e-5f) {
                    ++mismatched;
                    continue;
                }
                worstDepth = std::max(worstDepth, relative);
            }
    }
    // Stated bound: at most 0.5 % of pixels differ (silhouette and crease pixels); all others agree
    // in depth to 1e-4 relative and in normal to 1e-5 in the cosine.
    EXPECT_LE(double(mismatched), 0.005 * double(pixels)) << mismatched << " of " << pixels;
    std::printf("[ info ] G-buffer vs Embree: %zu of %zu pixels differ, worst relative depth %.2e elsewhere\n",
                mismatched, pixels, worstDepth);
}

TEST_F(RuntimeGl, OpenPlaneHasNoSelfOcclusion) {
    // A 200 × 200 floor seen at ~15° above the horizon: grazing samples and long marches.
    Mesh plane;
    plane.quad({-100, 0, 100}, {100, 0, 100}, {100, 0, -100}, {-100, 0, -100});
    const CameraPath path = singleFrame({0.0f, 1.5f, 10.0f}, {0.3f, 0.0f, 4.4f});
    const CameraView view = viewOf(path, 0, 160, 90);
    for (SsaoMethod m : kMethods) {
        BlurSettings noBlur;
        noBlur.radius = 0;
        FrameRenderer r(plane.positions, plane.indices, std::make_unique<SsaoPass>(methodSettings(m, 0.5f)), noBlur,
                        compositeSettings());
        r.render(view, 0);
        const Image raw = r.readRawAo();
        float lowest = 1.0f;
        for (float v : raw.pixels) lowest = std::min(lowest, v);
        EXPECT_GE(lowest, 0.98f) << ssaoMethodName(m);
        EXPECT_GT(r.method().fetchesPerPixel(), 2.0) << ssaoMethodName(m);
    }
}

struct ReferenceCase {
    const char* scene;
    std::array<std::size_t, 2> frames;
    std::map<SsaoMethod, double> bound;  // MAE regression bounds
};

// Each method, blurred as `render` writes it, against the Embree reference at the same R (256 spp).
// Regression bounds, not targets: screen-space AO misses hidden and off-screen occluders and is
// known to be off by 0.05–0.2 in hard scenes. Measured on llvmpipe at 160 × 90 (printed by the test):
//   box-room frames 0, 12:  alchemy 0.0125  hbao 0.0099  gtao 0.0111  (all-open image 0.0221)
//   cloister frames 0, 4:   alchemy 0.0521  hbao 0.0441  gtao 0.0385  (all-open image 0.0981)
// The bounds sit ~30 % above. Each method must also stay under 0.65 × the all-open image's MAE: a
// method that found no occlusion at all would otherwise pass the absolute bound on the easy box-room.
TEST_F(RuntimeGl, MethodsAgainstTheEmbreeReference) {
    const std::array<ReferenceCase, 2> cases = {{
        {"builtin:box-room", {0, 12}, {{SsaoMethod::Alchemy, 0.016}, {SsaoMethod::Hbao, 0.013}, {SsaoMethod::Gtao, 0.0145}}},
        {"builtin:cloister", {0, 4}, {{SsaoMethod::Alchemy, 0.068}, {SsaoMethod::Hbao, 0.057}, {SsaoMethod::Gtao, 0.050}}},
    }};
    const int w = 160, h = 90;
    for (const ReferenceCase& c : cases) {
        const Scene scene = makeBuiltinScene(c.scene);
        const CameraPath path = builtinCameraPath(c.scene);
        const EmbreeScene rt(scene);
        const float radius = scene.defaultRadius();
        std::vector<Image> reference;
        double openMae = 0.0;
        for (std::size_t f : c.frames) {
            reference.push_back(renderReferenceFrame(rt, PinholeCamera(path, f, w, h),
                                                     AoSettings{radius, 256, Falloff::None, 0}, std::uint32_t(f), nullptr)
                                    .ao);
            openMae += meanAbsoluteDifference(Image(w, h, 1.0f), reference.back()) / double(c.frames.size());
        }
        std::printf("[ info ] %s (160x90, frames %zu and %zu): all-open image MAE %.4f\n", c.scene, c.frames[0],
                    c.frames[1], openMae);
        for (SsaoMethod m : kMethods) {
            FrameRenderer r(scene.positions, scene.indices, std::make_unique<SsaoPass>(methodSettings(m, radius)),
                            BlurSettings{}, compositeSettings());
            double mae = 0.0;
            for (std::size_t i = 0; i < c.frames.size(); ++i) {
                const RenderedFrame out = r.render(viewOf(path, c.frames[i], w, h), std::uint32_t(c.frames[i]));
                mae += meanAbsoluteDifference(out.ao, reference[i]) / double(c.frames.size());
                for (float v : out.ao.pixels) ASSERT_TRUE(v >= 0.0f && v <= 1.0f) << ssaoMethodName(m);
            }
            std::printf("[ info ]   %-8s MAE %.4f\n", ssaoMethodName(m), mae);
            EXPECT_LT(mae, c.bound.at(m)) << c.scene << " " << ssaoMethodName(m);
            EXPECT_LT(mae, 0.65 * openMae) << c.scene << " " << ssaoMethodName(m);
        }
    }
}

TEST_F(RuntimeGl, BlurGpuMatchesTheCpuTwin) {
    // On box-room (creases, depth steps, background) with the raw GTAO image as input.
    const Scene& scene = boxRoom();
    FrameRenderer r(scene.positions, scene.indices,
                    std::make_unique<SsaoPass>(methodSettings(SsaoMethod::Gtao, scene.defaultRadius())),
                    BlurSettings{}, compositeSettings());
    const CameraView view = viewOf(boxRoomPath(), 5, 96, 54);
    const RenderedFrame out = r.render(view, 5);
    const Image cpu = blurAoCpu(r.readRawAo(), r.gbuffer().readBack(), view, BlurSettings{});
    float worst = 0.0f;
    for (std::size_t i = 0; i < cpu.pixels.size(); ++i) worst = std::max(worst, std::abs(cpu.pixels[i] - out.ao.pixels[i]));
    EXPECT_LT(worst, 1e-4f);
}

TEST_F(RuntimeGl, BlurKeepsARenderedDepthStep) {
    // The depth step rendered for real: a near quad over the left half, a far one behind everything.
    Mesh m;
    m.quad({-20, -20, -5}, {20, -20, -5}, {20, 20, -5}, {-20, 20, -5});
    m.quad({-10, -10, -3}, {0, -10, -3}, {0, 10, -3}, {-10, 10, -3});
    const CameraPath path = singleFrame({0, 0, 0}, {0, 0, -1});
    const CameraView view = viewOf(path, 0, 64, 36);
    CameraGBuffer g(m.positions, m.indices);
    g.render(view);
    const CameraGBufferImage img = g.readBack();
    Image ao(64, 36);
    for (int y = 0; y < 36; ++y)
        for (int x = 0; x < 64; ++x) ao.at(x, y) = img.depth[img.index(x, y)] < 4.0f ? 0.0f : 1.0f;
    EXPECT_EQ(ao.at(31, 18), 0.0f);  // the edge runs between columns 31 and 32
    EXPECT_EQ(ao.at(32, 18), 1.0f);
    // Upload, blur on the GPU, compare with the input and the CPU twin.
    gl::Texture in = gl::Texture::create(GL_TEXTURE_2D), out = gl::Texture::create(GL_TEXTURE_2D);
    glTextureStorage2D(in.id(), 1, GL_R32F, 64, 36);
    glTextureStorage2D(out.id(), 1, GL_R32F, 64, 36);
    glTextureSubImage2D(in.id(), 0, 0, 0, 64, 36, GL_RED, GL_FLOAT, ao.pixels.data());
    Blur blur(BlurSettings{});
    blur.run(g, view, in.id(), out.id());
    Image gpu(64, 36);
    glGetTextureImage(out.id(), 0, GL_RED, GL_FLOAT, GLsizei(gpu.pixels.size() * sizeof(float)), gpu.pixels.data());
    const Image cpu = blurAoCpu(ao, img, view, BlurSettings{});
    for (int y = 0; y < 36; ++y)
        for (int x = 0; x < 64; ++x) {
            // Stated bound: < 0.02 change more than one pixel from the edge (it is 0 here: see blur.h).
            if (x < 31 || x > 32) {
                EXPECT_LT(std::abs(gpu.at(x, y) - ao.at(x, y)), 0.02f) << x << "," << y;
            }
            EXPECT_NEAR(gpu.at(x, y), cpu.at(x, y), 1e-4f);
        }
}

TEST_F(RuntimeGl, CompositeFollowsTheFormula) {
    const Scene& scene = boxRoom();
    CompositeSettings c = compositeSettings();
    c.alpha = 0.75f;
    FrameRenderer r(scene.positions, scene.indices,
                    std::make_unique<SsaoPass>(methodSettings(SsaoMethod::Hbao, scene.defaultRadius())),
                    BlurSettings{}, c);
    const CameraView view = viewOf(boxRoomPath(), 3, 64, 36);
    const RenderedFrame out = r.render(view, 3);
    const CameraGBufferImage g = r.gbuffer().readBack();
    const glm::vec3 light = glm::normalize(view.viewFromWorldRotation() * c.lightDirection);
    for (int y = 0; y < 36; y += 5)
        for (int x = 0; x < 64; x += 7) {
            const std::size_t i = g.index(x, y);
            const glm::vec3 expected = g.empty(x, y) ? c.sky : compositePixel(g.normal[i], light, out.ao.pixels[i], c);
            for (int k = 0; k < 3; ++k) EXPECT_NEAR(out.shadedRgb[3 * i + std::size_t(k)], expected[k], 1.0f / 255.0f);
        }
}

// ---- the CLI -------------------------------------------------------------------------------------

using test::CliRun;
using test::lastLine;
using test::runCli;

TEST(RenderCli, UsageErrors) {
    TempDir dir;
    const std::string out = " --out " + dir.path().string();
    EXPECT_EQ(runCli("render builtin:box-room --method probes" + out).code, 2) << "probes need --cache";
    EXPECT_EQ(runCli("render builtin:box-room --method probes --cache " + (dir.path() / "none.cubeao").string() + out).code, 1);
    EXPECT_EQ(runCli("render builtin:box-room --method ssao" + out).code, 2);
    EXPECT_EQ(runCli("render builtin:box-room --falloff linear" + out).code, 2);
    EXPECT_EQ(runCli("render builtin:box-room --blur -1" + out).code, 2);
    EXPECT_EQ(runCli("render builtin:box-room --frames 5:5" + out).code, 2);
    EXPECT_EQ(runCli("render /no/such/scene.obj --camera x.json" + out).code, 1);
}

TEST_F(RuntimeGl, RenderProbesFromABakedCacheAndRefuseAnotherScenesCache) {
    TempDir dir;
    const std::string probes = dir.write("probes.json", R"({"version":1,"probes":[{"pos":[3,1.4,2.5]},{"pos":[6,1.5,1.5]}]})");
    const fs::path cache = dir.path() / "c.cubeao", render = dir.path() / "render";
    ASSERT_EQ(runCli("bake builtin:box-room --probes " + probes + " --out " + cache.string() + " --res 8 --spp 8 --device cpu").code, 0);
    const CliRun r = runCli("render builtin:box-room --method probes --cache " + cache.string() +
                            " --frames 0:2 --width 48 --height 27 --out " + render.string() + " --json");
    ASSERT_EQ(r.code, 0) << r.out;
    const auto j = lastLine(r.out);
    EXPECT_EQ(j["method"], "probes");
    EXPECT_EQ(j["probes"].get<int>(), 2);
    EXPECT_GE(j["uncovered_fraction"].get<double>(), 0.0);
    EXPECT_LT(j["uncovered_fraction"].get<double>(), 0.5);
    EXPECT_TRUE(fs::exists(render / "ao_0001.exr"));
    // The same cache against another scene: refused, naming both hashes.
    EXPECT_EQ(runCli("render builtin:cloister --method probes --cache " + cache.string() + " --frames 0:1 --out " +
                     (dir.path() / "wrong").string()).code, 1);
    EXPECT_EQ(runCli("render builtin:box-room --method probes --cache " + cache.string() + " --radius 0.3 --out " +
                     (dir.path() / "radius").string()).code, 2) << "the probes carry their own R";
}

// Issue 6: "box room, one probe: render vs reference within a stated MAE". One traced probe in the
// middle of the room at R = 1 (so that AO matters), 3 frames of the room's walk. Measured: MAE 0.043,
// 8 % of the pixels uncovered (hidden from the probe behind the furniture; they fall back to open,
// which is most of the error), against an all-open image's MAE that the test computes. Bounds: MAE
// ≤ 0.06, uncovered ≤ 0.15, and clearly better than claiming everything open (that MAE is 0.115).
TEST_F(RuntimeGl, RenderOneProbeInTheBoxRoomAgainstTheReference) {
    TempDir dir;
    const std::string probes = dir.write("probes.json", R"({"version":1,"probes":[{"pos":[4,1.5,3]}]})");
    const fs::path cache = dir.path() / "c.cubeao", render = dir.path() / "render", reference = dir.path() / "reference";
    ASSERT_EQ(runCli("bake builtin:box-room --probes " + probes + " --out " + cache.string() +
                     " --res 32 --spp 128 --radius 1 --device cpu").code, 0);
    const std::string frames = " --frames 0:3 --width 96 --height 54";
    const CliRun r = runCli("render builtin:box-room --method probes --cache " + cache.string() + frames + " --out " +
                            render.string() + " --json");
    ASSERT_EQ(r.code, 0) << r.out;
    EXPECT_LE(lastLine(r.out)["uncovered_fraction"].get<double>(), 0.15);
    ASSERT_EQ(runCli("reference builtin:box-room --spp 256 --radius 1" + frames + " --out " + reference.string()).code, 0);
    const CliRun c = runCli("compare " + render.string() + " " + reference.string() + " --json");
    ASSERT_EQ(c.code, 0) << c.out;
    const double mae = lastLine(c.out)["mae"].get<double>();
    double open = 0.0;
    for (int f = 0; f < 3; ++f) {
        const Image ref = readImage(reference / ("ao_000" + std::to_string(f) + ".exr"));
        for (float v : ref.pixels) open += (1.0 - v) / double(ref.pixels.size() * 3);
    }
    EXPECT_LE(mae, 0.06);
    EXPECT_LT(mae, 0.7 * open) << "all-open MAE " << open;
}

TEST_F(RuntimeGl, RenderCliWritesFramesThatCompareWithTheReference) {
    TempDir dir;
    const fs::path render = dir.path() / "render", reference = dir.path() / "reference";
    const CliRun r = runCli("render builtin:box-room --method gtao --frames 0:2 --width 64 --height 36 --out " +
                            render.string() + " --json");
    ASSERT_EQ(r.code, 0) << r.out;
    const auto j = lastLine(r.out);
    EXPECT_EQ(j["method"], "gtao");
    ASSERT_EQ(j["frames"].size(), 2u);
    EXPECT_EQ(j["frames"][1]["index"].get<int>(), 1);
    for (const char* pass : {"gbuffer", "ao", "blur", "composite", "readback"})
        EXPECT_GE(j["timings_ms"][pass].get<double>(), 0.0) << pass;
    EXPECT_GT(j["fetches_per_pixel"].get<double>(), 2.0);
    EXPECT_NEAR(j["radius"].get<double>(), boxRoom().defaultRadius(), 1e-6);
    for (const char* f : {"ao_0000.exr", "ao_0001.exr", "ao_0000.png", "shaded_0000.png", "shaded_0001.png"})
        EXPECT_TRUE(fs::exists(render / f)) << f;
    EXPECT_FALSE(fs::exists(render / "ao_0002.exr"));

    ASSERT_EQ(runCli("reference builtin:box-room --frames 0:2 --width 64 --height 36 --spp 32 --out " +
                     reference.string()).code, 0);
    const CliRun c = runCli("compare " + render.string() + " " + reference.string() + " --json");
    ASSERT_EQ(c.code, 0) << c.out;
    const auto m = lastLine(c.out);
    EXPECT_EQ(m["frames"].size(), 2u);
    EXPECT_LT(m["mae"].get<double>(), 0.2);
}

}  // namespace
