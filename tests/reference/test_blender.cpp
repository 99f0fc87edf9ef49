// `reference --aa N` against Blender Cycles' AO pass (issue 17): the same room, camera, radius and
// box filter rendered by both; they must agree within their noise. Skips with the reason when
// `blender` is not installed (Debian package blender; not in CI).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>

#include "cli_run.h"
#include "cubeao/core/camera.h"
#include "cubeao/metrics/image_io.h"
#include "cubeao/reference/ao_reference.h"
#include "cubeao/scene/builtin.h"
#include "cubeao/scene/camera_path.h"
#include "test_util.h"
#include "test_paths.h"

namespace cubeao {
namespace {

void writeObj(const Scene& scene, const std::string& path) {
    std::ofstream out(path);
    for (const glm::vec3& p : scene.positions) out << "v " << p.x << ' ' << p.y << ' ' << p.z << '\n';
    for (std::size_t t = 0; t + 2 < scene.indices.size(); t += 3)
        out << "f " << scene.indices[t] + 1 << ' ' << scene.indices[t + 1] + 1 << ' ' << scene.indices[t + 2] + 1
            << '\n';
}

// The box room from inside (every pixel sees a wall), 48×27, 256 samples per pixel in both: Blender
// (tools/blender_ao.py) traces one camera ray and one AO ray per sample, we 16×16 jittered primary rays
// with one AO ray each.
TEST(Blender, ReferenceWithAntiAliasingMatchesCyclesAoPass) {
    if (test::runCommand("command -v blender >/dev/null 2>&1").code != 0)
        GTEST_SKIP() << "blender is not installed (apt-get install blender): Cycles' AO pass cannot be compared";
    const Scene scene = makeBuiltinScene("builtin:box-room");
    const PinholeCamera cam(builtinCameraPath("builtin:box-room"), 0, 48, 27);
    const int aa = 16, spp = aa * aa;
    const float radius = scene.defaultRadius() * 4.0f;  // every pixel partly occluded: a wrong radius shows
    test::TempDir dir;
    const std::string obj = (dir.path() / "room.obj").string(), camera = (dir.path() / "walk.json").string();
    writeObj(scene, obj);
    writeCameraPath(camera, builtinCameraPath("builtin:box-room"));
    char options[160];
    std::snprintf(options, sizeof options, " --frames 0:1 --width %d --height %d --radius %.9g --samples %d", cam.width,
                  cam.height, radius, spp);
    // Blender is not ours: under the sanitizers (tools/test-sanitize.sh) it must not inherit the preloaded
    // ASan runtime, whose leak check would report Python's allocations and abort it.
    const test::CliRun r = test::runCommand("timeout 600 env -u LD_PRELOAD -u ASAN_OPTIONS -u LSAN_OPTIONS "
                                            "-u UBSAN_OPTIONS blender -b --factory-startup -noaudio "
                                            "--python-exit-code 1 --python " +
                                            std::string(test::sourceDir()) + "/tools/blender_ao.py -- " + obj + " " + camera + " " +
                                            dir.path().string() + options + " 2>&1");
    ASSERT_EQ(r.code, 0) << r.out;
    const std::string exr = (dir.path() / "ao_0000.exr").string();
    const Image cycles = readImage(exr);
    ASSERT_EQ(cycles.width, cam.width);
    ASSERT_EQ(cycles.height, cam.height);

    const EmbreeScene rt(scene);
    const AoSettings settings{radius, spp, Falloff::None, 0};
    const ReferenceFrame ours = renderReferenceFrame(rt, cam, settings, 0, nullptr, 1, aa);
    const ReferenceFrame centres = renderReferenceFrame(rt, cam, settings, 0, nullptr, 2);
    ASSERT_EQ(ours.backgroundFraction, 0.0);
    double mae = 0.0, maeCentres = 0.0, bias = 0.0, noise = 0.0;
    for (std::size_t i = 0; i < cycles.pixels.size(); ++i) {
        const double c = cycles.pixels[i];
        mae += std::abs(c - ours.ao.pixels[i]);
        maeCentres += std::abs(c - centres.ao.pixels[i]);
        bias += c - ours.ao.pixels[i];
        // Cycles' pixel: a mean of `spp` Bernoulli AO samples; ours has the same count of rays.
        noise += std::sqrt(std::max(c * (1.0 - c), 1e-4) / spp);
    }
    const double n = double(cycles.pixels.size());
    mae /= n, maeCentres /= n, bias /= n, noise /= n;
    std::printf("[ info ] Cycles vs reference --aa %d: MAE %.4f (bias %+.4f), pixel centres %.4f; noise %.4f\n", aa,
                mae, bias, maeCentres, noise);
    // Two independent estimates with per-pixel standard error s each: E|d| = sqrt(2) s sqrt(2/π) ≈ 1.13 s.
    EXPECT_LT(mae, 1.6 * noise);
    EXPECT_LT(std::abs(bias), 0.25 * noise);
    // Our own noise figure of the same 256 one-ray sub-samples (their spread over the pixel) is Cycles'.
    EXPECT_NEAR(ours.noise / noise, 1.0, 0.3) << "reference noise " << ours.noise;
}

}  // namespace
}  // namespace cubeao
