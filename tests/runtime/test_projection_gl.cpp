// The projection pass on the GPU (shaders/runtime/project.comp) against its CPU twin (projectAo in
// src/cubeao/runtime/projection.cpp) on the same cache, camera G-buffer and candidate grid, and the
// whole frame pipeline (FrameRenderer) on a fixed surface point while the camera moves.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include "cubeao/bake/bake.h"
#include "cubeao/bake/bake_driver.h"
#include "cubeao/cache/cache_file.h"
#include "cubeao/reference/embree_scene.h"
#include "cubeao/runtime/camera_gbuffer.h"
#include "cubeao/runtime/camera_view.h"
#include "cubeao/runtime/composite.h"
#include "cubeao/runtime/probe_projection.h"
#include "cubeao/runtime/projection.h"
#include "cubeao/runtime/renderer.h"
#include "cubeao/scene/builtin.h"
#include "cubeao/scene/import.h"
#include "bake_test_settings.h"
#include "decoded_probe.h"
#include "gl_fixture.h"
#include "test_util.h"
#include "test_paths.h"

namespace {

using namespace cubeao;

// Three probes in the box room, traced on the CPU at 16² into DIR/c.cubeao (stored as BC4, the traced
// default).
std::string bakeThreeProbes(const test::TempDir& dir) {
    const std::string probes = dir.write("probes.json", R"({"version":1,"probes":[{"pos":[3,1.4,2.5]},{"pos":[6,1.5,1.5]},{"pos":[2,1.2,4.5]}]})");
    const std::string cacheFile = (dir.path() / "c.cubeao").string();
    const std::string cmd = std::string(cubeao::test::cubeaoBinary()) + " bake builtin:box-room --probes " + probes + " --out " +
                            cacheFile + " --res 16 --spp 16 --radius 1 --device cpu > /dev/null 2>&1";
    EXPECT_EQ(std::system(cmd.c_str()), 0) << cmd;
    return cacheFile;
}

// The probe pass's AO image (before the blur) of the box room's path frame 3 at 96 × 54.
std::vector<float> projectFrame(const Scene& scene, const CacheReader& cache, const ProbeProjectionSettings& settings,
                                std::size_t* gpuBytes = nullptr) {
    const CameraPath path = builtinCameraPath("builtin:box-room");
    const CameraView view = CameraView::fromPinhole(PinholeCamera(path, 3, 96, 54), path.nearPlane);
    CameraGBuffer gbuffer(scene.positions, scene.indices);
    gbuffer.render(view);
    ProbeProjectionPass pass(cache, scene.positions, scene.indices, settings);
    const gl::Texture aoImage = gl::Texture::create(GL_TEXTURE_2D);
    glTextureStorage2D(aoImage.id(), 1, GL_R32F, view.width, view.height);
    pass.run(gbuffer, view, 3, aoImage.id());
    std::vector<float> ao(std::size_t(view.width) * std::size_t(view.height));
    glGetTextureImage(aoImage.id(), 0, GL_RED, GL_FLOAT, GLsizei(ao.size() * sizeof(float)), ao.data());
    if (gpuBytes) *gpuBytes = pass.residency().allocatedGpuBytes();
    return ao;
}

TEST_F(GlTest, ProbeProjectionMatchesTheCpuTwin) {
    test::TempDir dir;
    const std::string cacheFile = bakeThreeProbes(dir);

    const Scene scene = loadScene("builtin:box-room");
    const CacheReader cache(cacheFile);
    const test::DecodedCache decoded(cache);
    ASSERT_TRUE(decoded.ok);
    const std::vector<DecodedProbe>& views = decoded.views;

    const CameraPath path = builtinCameraPath("builtin:box-room");
    const CameraView view = CameraView::fromPinhole(PinholeCamera(path, 3, 96, 54), path.nearPlane);
    CameraGBuffer gbuffer(scene.positions, scene.indices);
    gbuffer.render(view);
    ProbeProjectionPass pass(cache, scene.positions, scene.indices);
    const gl::Texture aoImage = gl::Texture::create(GL_TEXTURE_2D);
    glTextureStorage2D(aoImage.id(), 1, GL_R32F, view.width, view.height);
    pass.run(gbuffer, view, 3, aoImage.id());
    std::vector<float> gpu(std::size_t(view.width) * std::size_t(view.height));
    glGetTextureImage(aoImage.id(), 0, GL_RED, GL_FLOAT, GLsizei(gpu.size() * sizeof(float)), gpu.data());

    const CameraGBufferImage g = gbuffer.readBack();
    const glm::mat4 worldFromView = view.worldFromView();
    const ProjectSettings settings = resolveProjectSettings({});
    double sum = 0.0;
    std::size_t far = 0, covered = 0, surface = 0;
    for (int y = 0; y < view.height; ++y)
        for (int x = 0; x < view.width; ++x) {
            const std::size_t i = g.index(x, y);
            if (g.empty(x, y)) {
                EXPECT_EQ(gpu[i], 1.0f);
                continue;
            }
            const glm::vec3 p = glm::vec3(worldFromView * glm::vec4(view.viewPosition(x, y, g.depth[i]), 1.0f));
            const glm::vec3 n = glm::normalize(glm::mat3(worldFromView) * g.normal[i]);
            std::vector<DecodedProbe> candidates;
            for (std::uint32_t c : pass.grid().candidates(p)) candidates.push_back(views[c]);
            const Projected cpu = projectAo(candidates, p, n, settings);
            const float d = std::fabs(cpu.ao - gpu[i]);
            sum += d;
            far += d > 0.02f ? 1 : 0;
            covered += cpu.covered ? 1 : 0;
            ++surface;
        }
    ASSERT_GT(surface, 0u);
    // Same inputs and the same decisions; differences come from the BC5 decode (Mesa interpolates in
    // 8-bit fixed point, ≤ 1.6/255 from the spec) and from points within rounding of a texel border
    // or of the depth test's threshold, where GPU and CPU may pick neighbours.
    EXPECT_LT(sum / double(surface), 2e-3);
    EXPECT_LE(far, surface / 50) << "pixels differing by more than 0.02";
    EXPECT_GT(covered, surface * 9 / 10) << "three probes in an open room should see most of it";
    EXPECT_NEAR(pass.uncoveredFraction(), double(surface - covered) / double(gpu.size()), 0.01);
}

// A traced cache stored as BC4 (AO alone, green swizzled to one) renders exactly as the same probes
// stored as BC5 with confidence 1, and as the BC4 cache held as BC5 (the viewer's way, converted on
// upload), with half the AO atlas's bytes.
TEST_F(GlTest, ABc4CacheRendersAsItsBc5Twin) {
    test::TempDir dir;
    const std::string bc4File = bakeThreeProbes(dir);
    const std::string bc5File = (dir.path() / "c5.cubeao").string();
    mergeCaches(bc5File, {bc4File}, {}, AoFormat::Bc5);
    const CacheReader bc4(bc4File), bc5(bc5File);
    ASSERT_EQ(bc4.params().aoFormat, AoFormat::Bc4) << "a traced bake stores BC4";
    ASSERT_EQ(bc5.params().aoFormat, AoFormat::Bc5);

    const Scene scene = loadScene("builtin:box-room");
    ProbeProjectionSettings heldAsBc5;
    heldAsBc5.aoFormat = AoFormat::Bc5;
    std::size_t bytes4 = 0, bytes5 = 0, bytesHeld = 0;
    const std::vector<float> a = projectFrame(scene, bc4, {}, &bytes4), b = projectFrame(scene, bc5, {}, &bytes5),
                             c = projectFrame(scene, bc4, heldAsBc5, &bytesHeld);
    std::size_t open = 0;
    for (std::size_t i = 0; i < a.size(); ++i) {
        ASSERT_EQ(a[i], b[i]) << "pixel " << i;
        ASSERT_EQ(a[i], c[i]) << "pixel " << i;
        open += a[i] == 1.0f ? 1 : 0;
    }
    EXPECT_LT(open, a.size() / 2) << "the frame shows occlusion, not only open pixels";
    const std::size_t aoAtlas5 = 3 * 6 * 16 * 16;  // three probes' BC5 texels, a byte each (atlas tiles may pad)
    EXPECT_EQ(bytes5, bytesHeld);
    EXPECT_LE(bytes4 + aoAtlas5 / 2, bytes5) << "BC4 holds the AO in half the bytes";
}

// Levels of detail: a cache baked with --levels renders at level 0 exactly as the bake without levels
// does, and at level 1 exactly as a one-level cache holding its level-1 cubes (levelView) does, at
// that level's smaller atlas.
TEST_F(GlTest, EachLevelOfACacheRendersAsACacheOfThatLevelAlone) {
    test::TempDir dir;
    const std::string probes = dir.write("probes.json", R"({"version":1,"probes":[{"pos":[3,1.4,2.5]},{"pos":[6,1.5,1.5]}]})");
    const auto bake = [&](const std::string& name, const std::string& extra) {
        const std::string out = (dir.path() / name).string();
        const std::string cmd = std::string(cubeao::test::cubeaoBinary()) + " bake builtin:box-room --probes " + probes +
                                " --out " + out + " --res 32 --spp 16 --radius 1 --device cpu" + extra + " > /dev/null 2>&1";
        EXPECT_EQ(std::system(cmd.c_str()), 0) << cmd;
        return out;
    };
    const CacheReader levels(bake("levels.cubeao", " --levels max")), plain(bake("plain.cubeao", ""));
    ASSERT_EQ(levels.params().levels, 2u);  // 32², 16²
    const std::string level1File = (dir.path() / "level1.cubeao").string();
    std::vector<ProbeView> level1;
    for (std::size_t i = 0; i < levels.probeCount(); ++i) level1.push_back(levelView(levels.probe(i), levels.params(), 1));
    writeCache(level1File, levelParams(levels.params(), 1), level1);
    const CacheReader alone(level1File);

    const Scene scene = loadScene("builtin:box-room");
    ProbeProjectionSettings atLevel1;
    atLevel1.level = 1;
    std::size_t bytes0 = 0, bytes1 = 0;
    const std::vector<float> a = projectFrame(scene, levels, {}, &bytes0), b = projectFrame(scene, plain, {});
    const std::vector<float> c = projectFrame(scene, levels, atLevel1, &bytes1), d = projectFrame(scene, alone, {});
    std::size_t differ = 0;
    for (std::size_t i = 0; i < a.size(); ++i) {
        ASSERT_EQ(a[i], b[i]) << "pixel " << i;
        ASSERT_EQ(c[i], d[i]) << "pixel " << i;
        differ += a[i] != c[i] ? 1 : 0;
    }
    EXPECT_GT(differ, 0u) << "level 1 is another picture";
    EXPECT_LT(bytes1, bytes0) << "level 1's atlas is a quarter of level 0's";
    ProbeProjectionSettings atLevel2;
    atLevel2.level = 2;
    const std::string refused = test::errorMessage([&] { projectFrame(scene, levels, atLevel2); });
    EXPECT_TRUE(test::contains(refused, "level 2 of a cache of 2 levels")) << refused;
}

// ---- two probes, the camera walking from one to the other (issue 6) -----------------------------

// P: a floor point 0.4 m in front of the box room's cabinet (x = 7.4), where AO changes fast, seen
// from a far probe A (6.7 m away, 17° above the floor: at 32² one texel covers ~0.3 m × 1 m of floor
// around P, texelFootprint) and a near probe B (1.1 m, 62°: ~6 cm × 6 cm), so the two store
// noticeably different AO for P.
constexpr glm::vec3 kFarProbe{1.5f, 2.0f, 4.5f}, kNearProbe{6.6f, 1.0f, 1.6f}, kFixedPoint{7.0f, 0.0f, 1.25f};
constexpr glm::vec3 kFloorNormal{0.0f, 1.0f, 0.0f};

struct PointSample {
    float blurred = 0.0f;      // mean of the 3 × 3 window of the AO image (after the blur) around P's pixel
    float raw = 0.0f;          // the projection's AO at P's pixel, before the blur
    bool sameSurface = false;  // all nine pixels show the plane through P with P's normal
};

// AO at world point p (on a surface with normal n) in a frame: P's pixel is found by projecting p.
// The window tolerates the sub-pixel shifts of P between frames; it only counts when all of it lies
// on P's surface (an edge inside it would mix in another surface's AO).
PointSample sampleAt(const RenderedFrame& frame, const Image& raw, const CameraGBufferImage& g, const CameraView& view,
                     const glm::vec3& p, const glm::vec3& n) {
    const glm::vec2 at = view.projectToPixel(glm::vec3(view.viewFromWorld * glm::vec4(p, 1.0f)));
    const int cx = int(std::floor(at.x)), cy = int(std::floor(at.y));
    PointSample out;
    if (cx < 1 || cy < 1 || cx + 1 >= view.width || cy + 1 >= view.height) return out;
    const glm::mat4 worldFromView = view.worldFromView();
    out.sameSurface = true;
    for (int y = cy - 1; y <= cy + 1; ++y)
        for (int x = cx - 1; x <= cx + 1; ++x) {
            const std::size_t i = g.index(x, y);
            out.blurred += frame.ao.pixels[i] / 9.0f;
            if (g.empty(x, y)) {
                out.sameSurface = false;
                continue;
            }
            const glm::vec3 w = glm::vec3(worldFromView * glm::vec4(view.viewPosition(x, y, g.depth[i]), 1.0f));
            const glm::vec3 wn = glm::mat3(worldFromView) * g.normal[i];
            out.sameSurface = out.sameSurface && glm::dot(wn, n) > 0.999f && std::fabs(glm::dot(w - p, n)) < 1e-3f;
        }
    out.raw = raw.pixels[g.index(cx, cy)];
    return out;
}

// Issue 6: "two probes, camera moving from one to the other: AO of a fixed surface point changes
// continuously". The camera walks in a straight line from probe A's position to probe B's, always
// looking at P, through the whole frame pipeline (G-buffer, projection, blur, composite). The blur
// stays on (BlurSettings{}, what `render` ships): it is the one stage whose footprint on the surface
// changes with the camera, so it is what could make a fixed point's AO drift as the camera moves.
TEST_F(GlTest, FixedPointAoIsContinuousAsTheCameraWalksFromOneProbeToTheOther) {
    const Scene scene = loadScene("builtin:box-room");
    const BakeSettings s = test::bakeSettings(Estimator::Traced, 32, 1.0f, 64);
    test::TempDir dir("twoprobes");
    const std::string cacheFile = (dir / "two.cubeao").string();
    const glm::vec3 probes[] = {kFarProbe, kNearProbe};
    test::bakeCache(scene, probes, s, cacheFile);
    const CacheReader cache(cacheFile);
    const test::DecodedCache decoded(cache);
    ASSERT_TRUE(decoded.ok);
    const std::vector<DecodedProbe>& views = decoded.views;

    // The CPU twin at P: each probe alone, and both as the pass blends them.
    const ProjectSettings settings = resolveProjectSettings({});
    const Projected farAlone = projectAo({&views[0], 1}, kFixedPoint, kFloorNormal, settings);
    const Projected nearAlone = projectAo({&views[1], 1}, kFixedPoint, kFloorNormal, settings);
    const Projected blend = projectAo(views, kFixedPoint, kFloorNormal, settings);
    ASSERT_TRUE(farAlone.covered && nearAlone.covered) << "both probes must see P";
    ASSERT_EQ(blend.used, 2);

    CameraPath path;
    path.fovYDeg = 20.0f;  // narrow, so that the 3 × 3 window stays on the floor from 6.7 m away
    const int frames = 24, width = 65, height = 49;  // odd sizes: P, the target, is a pixel centre
    for (int f = 0; f < frames; ++f)
        path.frames.push_back({glm::mix(kFarProbe, kNearProbe, float(f) / float(frames - 1)), kFixedPoint});
    CompositeSettings composite;
    composite.lightDirection = defaultLightDirection(scene.up);
    FrameRenderer renderer(scene.positions, scene.indices,
                           std::make_unique<ProbeProjectionPass>(cache, scene.positions, scene.indices),
                           BlurSettings{}, composite);
    std::vector<PointSample> samples;
    for (int f = 0; f < frames; ++f) {
        const CameraView view = CameraView::fromPinhole(PinholeCamera(path, std::size_t(f), width, height), path.nearPlane);
        const RenderedFrame out = renderer.render(view, std::uint32_t(f));
        samples.push_back(sampleAt(out, renderer.readRawAo(), renderer.gbuffer().readBack(), view, kFixedPoint, kFloorNormal));
        ASSERT_TRUE(samples.back().sameSurface) << "frame " << f << ": P's 3 × 3 window leaves the floor";
    }

    // Bound on the change between consecutive frames. P's projected AO does not depend on the camera
    // (world-space candidates and quality); what moves is the 3 × 3 window and the blur's taps, whose
    // footprint on the floor shrinks from A to B (6× across, 17× along the view), sliding over the
    // near probe's ~6 cm texels. Measured on llvmpipe: largest step 0.0046, total drift 0.016 over
    // the walk. The bound is ~2× the largest step; a switch between the two probes would jump by their
    // whole disagreement, 0.17 (17× the bound), asserted below.
    constexpr float kStepBound = 0.01f;
    float largestStep = 0.0f, hardSwitchStep = 0.0f;
    for (int f = 1; f < frames; ++f) {
        largestStep = std::max(largestStep, std::fabs(samples[f].blurred - samples[f - 1].blurred));
        // What a camera-dependent choice would show: the probe nearest the camera, alone.
        const auto nearest = [&](int frame) {
            const glm::vec3 eye = path.frames[std::size_t(frame)].eye;
            return glm::distance(eye, kNearProbe) < glm::distance(eye, kFarProbe) ? nearAlone.ao : farAlone.ao;
        };
        hardSwitchStep = std::max(hardSwitchStep, std::fabs(nearest(f) - nearest(f - 1)));
    }
    std::printf("[ info ] AO at P: far probe alone %.4f, near probe alone %.4f, CPU blend %.4f; rendered (3x3, blurred) "
                "%.4f at A .. %.4f at B, largest step between frames %.4f (bound %.3f)\n",
                farAlone.ao, nearAlone.ao, blend.ao, samples.front().blurred, samples.back().blurred, largestStep,
                kStepBound);
    EXPECT_LE(largestStep, kStepBound);
    // The test can fail: the two probes disagree about P by far more than the bound, so a hard switch
    // between them anywhere on the walk would break it.
    EXPECT_GT(std::fabs(farAlone.ao - nearAlone.ao), 5.0f * kStepBound) << "the probes must disagree about P";
    EXPECT_GT(hardSwitchStep, kStepBound);

    // Every frame's projection at P is the CPU twin's blend of both probes, wherever the camera is
    // (the GPU decodes BC5 in 8-bit fixed point: ≤ 1.6/255 from the spec; measured 0.0012). At the
    // ends the blurred window also matches it: within 0.03 at A, where window and taps reach ±0.5 m
    // along the view, into the cabinet's shadow (measured 0.018 darker), and 0.005 at B (measured
    // 0.0014).
    for (int f = 0; f < frames; ++f) EXPECT_NEAR(samples[f].raw, blend.ao, 0.01f) << "frame " << f;
    EXPECT_NEAR(samples.front().blurred, blend.ao, 0.03f);
    EXPECT_NEAR(samples.back().blurred, blend.ao, 0.005f);
}
}  // namespace
