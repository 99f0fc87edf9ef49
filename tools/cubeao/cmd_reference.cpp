// cubeao reference SCENE --camera PATH.json --out DIR: Embree ground-truth AO of a camera path.
#include <chrono>
#include <cstdio>
#include <filesystem>

#include <spdlog/spdlog.h>

#include "cli_util.h"
#include "commands.h"
#include "cubeao/core/durable_file.h"
#include "cubeao/core/error.h"
#include "cubeao/core/progress.h"
#include "cubeao/metrics/image_io.h"
#include "cubeao/reference/ao_reference.h"
#include "cubeao/scene/builtin.h"
#include "cubeao/scene/import.h"

namespace cubeao::cli {
namespace {

namespace fs = std::filesystem;

struct ReferenceArgs {
    std::string scene, camera, out, frames, falloff = "none";
    int spp = 64, replicas = 2, aa = 1, width = 0, height = 0;
    float radius = 0.0f;
    std::uint32_t seed = 0;
    bool json = false;
};

void run(const ReferenceArgs& a) {
    // Ranges first, before the scene loads and --out is created (issue 15: absurd values cost nothing).
    checkRange("--spp", a.spp, 1, 65536);
    checkRange("--replicas", a.replicas, 1, 64);
    checkRange("--aa", a.aa, 1, 64);
    checkFiniteNonNegative("--radius", a.radius, " (0: 2% of the scene's diagonal)");
    checkImageSizeOptions(a.width, a.height);
    // Also checked by renderReferenceFrame.
    if (a.spp % a.replicas != 0)
        throw UsageError("--replicas " + std::to_string(a.replicas) + " must divide --spp " + std::to_string(a.spp));
    if (a.spp % (a.aa * a.aa * a.replicas) != 0)
        throw UsageError("--aa " + std::to_string(a.aa) + ": --spp " + std::to_string(a.spp) +
                         " must be a multiple of aa² × replicas = " + std::to_string(a.aa * a.aa * a.replicas) +
                         " (each of the aa² primary rays traces spp/aa² AO rays)");
    const Scene scene = loadScene(a.scene);
    const CameraPath path = resolveCameraPath(a.camera, scene);
    const FrameRange range = parseFrameRange(a.frames, path.frames.size());
    const AoSettings settings{a.radius > 0.0f ? a.radius : scene.defaultRadius(), a.spp, parseFalloff(a.falloff),
                              a.seed};
    int w = 0, h = 0;
    resolveImageSize(a.width, a.height, path, w, h);
    fs::create_directories(a.out);

    spdlog::info("reference: {} ({} triangles), frames {}:{} at {}x{}, {} spp in {} replicas, {}x{} primary rays per "
                 "pixel, R = {}", scene.source, scene.triangleCount(), range.begin, range.end, w, h, settings.spp,
                 a.replicas, a.aa, a.aa, settings.radius);
    const auto t0 = std::chrono::steady_clock::now();
    const EmbreeScene rt(scene);
    const double buildSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

    nlohmann::json frames = nlohmann::json::array();
    double traceSeconds = 0.0, noiseSum = 0.0;
    std::uint64_t rays = 0;
    Progress progress("reference", std::uint64_t(range.size()) * std::uint64_t(w) * std::uint64_t(h), "pixels");
    for (std::size_t f = range.begin; f < range.end; ++f) {
        const auto start = std::chrono::steady_clock::now();
        const ReferenceFrame frame =
            renderReferenceFrame(rt, PinholeCamera(path, f, w, h), settings, std::uint32_t(f), &progress, a.replicas, a.aa);
        const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        traceSeconds += secs;
        rays += frame.aoRays + std::uint64_t(w) * std::uint64_t(h) * std::uint64_t(a.aa * a.aa);
        noiseSum += frame.noise;
        const fs::path exr = fs::path(a.out) / frameName("ao", f, "exr");
        writeExr(exr, frame.ao);
        writePng(fs::path(a.out) / frameName("ao", f, "png"), frame.ao);
        frames.push_back({{"index", f}, {"file", exr.string()}, {"noise", frame.noise},
                          {"background_fraction", frame.backgroundFraction}, {"seconds", secs}});
    }
    const double raysPerSecond = traceSeconds > 0 ? double(rays) / traceSeconds : 0.0;
    nlohmann::json result = {{"scene", scene.source},
                             {"scene_hash", hashToString(scene.hash)},
                             {"triangles", scene.triangleCount()},
                             {"radius", settings.radius},
                             {"spp", settings.spp},
                             {"replicas", a.replicas},
                             {"aa", a.aa},
                             {"noise_estimate", a.replicas > 1 ? "replicas" : "independent_rays_bound"},
                             {"falloff", falloffName(settings.falloff)},
                             {"seed", settings.seed},
                             {"width", w},
                             {"height", h},
                             {"frames", frames},
                             {"noise", noiseSum / double(range.size())},
                             {"rays", rays},
                             {"rays_per_s", raysPerSecond},
                             {"bvh_build_s", buildSeconds},
                             {"trace_s", traceSeconds},
                             {"out", a.out}};
    writeFileDurably(fs::path(a.out) / "reference.json", result.dump(1) + "\n");
    std::printf("reference: %zu frames -> %s, %.2f Mrays/s, noise (std. error) %.4f\n", range.size(),
                a.out.c_str(), raysPerSecond * 1e-6, noiseSum / double(range.size()));
    if (a.json) printJson(result);
}

}  // namespace

void addReference(CLI::App& app) {
    auto* cmd = app.add_subcommand("reference", "Ray-traced (Embree) reference AO of a camera path");
    auto a = std::make_shared<ReferenceArgs>();
    cmd->add_option("scene", a->scene, "Model file or builtin:NAME")->required();
    cmd->add_option("--camera", a->camera, "Camera path JSON (default for built-in scenes: their own path)");
    cmd->add_option("--out", a->out, "Output directory for ao_NNNN.exr/.png and reference.json")->required();
    cmd->add_option("--spp", a->spp, "AO rays per pixel, 1..65536")->capture_default_str();
    cmd->add_option("--replicas", a->replicas,
                    "Split each pixel's rays into this many independently rotated sets; their spread measures "
                    "the noise (1: report the independent-ray bound instead). 1..64, must divide --spp")
        ->capture_default_str();
    cmd->add_option("--aa", a->aa,
                    "N: N×N jittered primary rays per pixel, box-filtered, as offline renderers do (1: the pixel "
                    "centre, as `render` samples; compare render against that). 1..64")
        ->capture_default_str();
    cmd->add_option("--radius", a->radius, "AO radius R in scene units (default: 2% of the bbox diagonal)");
    cmd->add_option("--falloff", a->falloff, "none | smooth")->capture_default_str();
    cmd->add_option("--frames", a->frames, "Half-open frame range A:B (default: all)");
    cmd->add_option("--width", a->width, "Image width (default: the camera file's)");
    cmd->add_option("--height", a->height, "Image height (default: the camera file's)");
    cmd->add_option("--seed", a->seed, "Rotates every pixel's sample set");
    cmd->add_flag("--json", a->json, "Print one JSON object as the last line");
    cmd->callback([a] { run(*a); });
}

}  // namespace cubeao::cli
