// The screen-space baselines (src/cubeao/ssao/, shaders/ssao/): settings, each method on an open
// plane (no self-occlusion) and against the Embree reference.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <map>
#include <memory>

#include "cubeao/reference/ao_reference.h"
#include "cubeao/reference/embree_scene.h"
#include "cubeao/runtime/blur.h"
#include "cubeao/runtime/renderer.h"
#include "cubeao/ssao/ssao_pass.h"
#include "runtime_test_util.h"
#include "test_util.h"

namespace {

using namespace cubeao;
using namespace cubeao::test;

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

// ---- GL ------------------------------------------------------------------------------------------

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

// Issue 11: Falloff::Smooth through every screen-space pass, on box-room at R = 1 (frames 0 and 12,
// 160 × 90, Embree reference at 256 spp with each falloff). Three things a wrong falloff would break:
// (1) per pixel, the raw AO with smooth is at least the AO with none (the same jitter, the same
// horizons and samples; only the weight of each occluder, (1 − (r/R)²)² ≤ 1, changes); (2) on
// average it rises by what the reference says it should (measured on llvmpipe: reference +0.0595;
// alchemy +0.0590, hbao +0.0558, gtao +0.0639; bound ±25 %); (3) blurred, each method against the
// smooth reference: MAE measured alchemy 0.0353, hbao 0.0163, gtao 0.0349 (all-open image 0.0608),
// bounds ~30 % above and under 0.65 × the all-open MAE, as in MethodsAgainstTheEmbreeReference.
TEST_F(RuntimeGl, SmoothFalloffAgainstTheEmbreeReferenceAndOccludesLess) {
    const std::map<SsaoMethod, double> bound = {{SsaoMethod::Alchemy, 0.046}, {SsaoMethod::Hbao, 0.021}, {SsaoMethod::Gtao, 0.045}};
    const std::array<std::size_t, 2> frames = {0, 12};
    const int w = 160, h = 90;
    const Scene& scene = boxRoom();
    const EmbreeScene rt(scene);
    const float radius = 1.0f;  // the room's default R (0.21) leaves too little within R to tell smooth from none
    std::vector<Image> reference;
    double openMae = 0.0, referenceGain = 0.0;
    for (std::size_t f : frames) {
        const PinholeCamera camera(boxRoomPath(), f, w, h);
        reference.push_back(renderReferenceFrame(rt, camera, AoSettings{radius, 256, Falloff::Smooth, 0}, std::uint32_t(f), nullptr).ao);
        const Image none = renderReferenceFrame(rt, camera, AoSettings{radius, 256, Falloff::None, 0}, std::uint32_t(f), nullptr).ao;
        openMae += meanAbsoluteDifference(Image(w, h, 1.0f), reference.back()) / double(frames.size());
        for (std::size_t k = 0; k < none.pixels.size(); ++k)
            referenceGain += double(reference.back().pixels[k] - none.pixels[k]) / double(none.pixels.size() * frames.size());
    }
    std::printf("[ info ] box-room, smooth falloff, R = 1 (160x90, frames 0 and 12): all-open image MAE %.4f, reference "
                "AO gain over none %.4f\n", openMae, referenceGain);
    for (SsaoMethod m : kMethods) {
        SsaoSettings smooth = methodSettings(m, radius);
        smooth.falloff = Falloff::Smooth;
        FrameRenderer none(scene.positions, scene.indices, std::make_unique<SsaoPass>(methodSettings(m, radius)),
                           BlurSettings{}, compositeSettings());
        FrameRenderer r(scene.positions, scene.indices, std::make_unique<SsaoPass>(smooth), BlurSettings{},
                        compositeSettings());
        double mae = 0.0, gain = 0.0;
        for (std::size_t i = 0; i < frames.size(); ++i) {
            const CameraView view = viewOf(boxRoomPath(), frames[i], w, h);
            none.render(view, std::uint32_t(frames[i]));
            const RenderedFrame out = r.render(view, std::uint32_t(frames[i]));
            const Image rawNone = none.readRawAo(), raw = r.readRawAo();
            for (std::size_t k = 0; k < raw.pixels.size(); ++k) {
                ASSERT_GE(raw.pixels[k], rawNone.pixels[k] - 1e-5f) << ssaoMethodName(m) << " pixel " << k;
                gain += double(raw.pixels[k] - rawNone.pixels[k]) / double(raw.pixels.size() * frames.size());
            }
            mae += meanAbsoluteDifference(out.ao, reference[i]) / double(frames.size());
        }
        std::printf("[ info ]   %-8s MAE %.4f, raw AO gain over none %.4f\n", ssaoMethodName(m), mae, gain);
        EXPECT_NEAR(gain, referenceGain, 0.25 * referenceGain) << ssaoMethodName(m) << ": occluders within R weigh less with smooth";
        EXPECT_LT(mae, bound.at(m)) << ssaoMethodName(m);
        EXPECT_LT(mae, 0.65 * openMae) << ssaoMethodName(m);
    }
}

}  // namespace
