// cubeao bench bake: where a probe bake spends its time, per estimator and device, in one run (so the
// figures compare as ratios on a noisy machine). On llvmpipe the "GPU" is this CPU: the GPU/Embree
// ratio there says how GPU-shaped code runs on a CPU, not what a GPU does (../shared/gpu/README.md).
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <memory>
#include <optional>
#include <thread>

#include <spdlog/spdlog.h>

#include "cli_util.h"
#include "commands.h"
#include "cubeao/bake/bake.h"
#include "cubeao/bake/bake_driver.h"
#include "cubeao/bake/gpu_bake.h"
#include "cubeao/core/error.h"
#include "cubeao/gl/context.h"
#include "cubeao/scene/builtin.h"
#include "cubeao/scene/import.h"

namespace cubeao::cli {
namespace {

struct BenchArgs {
    std::vector<std::string> scenes{"builtin:cloister"}, cameras, estimators{"hsplit", "gtao", "traced", "hybrid"},
        devices{"gpu", "cpu"};
    int res = 512, spp = 64, probes = 2;
    bool json = false;
};

// Probes where a person walks: camera positions spread evenly along the scene's path.
std::vector<glm::vec3> probePositions(const Scene& scene, const std::string& camera, int count) {
    const CameraPath path = resolveCameraPath(camera, scene);
    std::vector<glm::vec3> out;
    for (int i = 0; i < count; ++i)
        out.push_back({path.frames[std::size_t(i) * path.frames.size() / std::size_t(count)].eye});
    return out;
}

// One estimator on one device: stage medians under their bench names, then the rates `bake` prints too.
nlohmann::json runJson(const BakeStats& stats) {
    nlohmann::json run = {{"ms_per_probe", median(stats.total)},
                          {"gbuffer_ms", median(stats.gbuffer)},
                          {"ao_ms", median(stats.ao)},
                          {"encode_ms", median(stats.encode)},  // BC5 + distance cube: what the cache stores
                          {"encode_to_ao", median(stats.encodeToAo)},
                          {"error_ms", median(stats.error)},    // BC5 AO error measurement
                          {"readback_ms", median(stats.readback)}};
    run.update(stats.ratesJson());
    return run;
}

nlohmann::json benchScene(const BenchArgs& a, const std::string& spec, const std::string& camera,
                          const std::optional<gl::HeadlessContext>& context) {
    const Scene scene = loadScene(spec);
    const std::vector<glm::vec3> probes = probePositions(scene, camera, a.probes);
    nlohmann::json runs = nlohmann::json::array(), gbufferModes = nlohmann::json::object();
    for (const std::string& device : a.devices) {
        if (device == "gpu" && !context) continue;
        for (const std::string& estimator : a.estimators) {
            BakeSettings s;
            s.res = a.res;
            s.ao.spp = a.spp;
            s.estimator = parseEstimator(estimator);
            s.device = parseBakeDevice(device);
            s = resolveBakeSettings(s, scene.defaultRadius());
            ProbeBakerOptions options;
            options.timings = true;  // the point of the bench: every stage alone
            ProbeBaker baker(scene, s, options);
            BakeJob job;
            job.probes = probes;
            job.progressLabel.clear();
            MemoryProbeSink sink;
            const BakeStats stats = bakeProbes(baker, job, sink).stats;
            if (baker.onGpu() && gbufferModes.empty()) {  // G-buffer mode is independent of the estimator: once per scene
                for (const auto& [name, mode] : {std::pair{"layered", GBufferMode::Layered}, std::pair{"six_pass", GBufferMode::SixPass}}) {
                    baker.setGBufferMode(mode);
                    std::vector<double> ms;
                    for (const glm::vec3& p : probes) ms.push_back(baker.bake(p, 0).timings.gbufferMs);
                    gbufferModes[name] = median(ms);
                }
            }
            nlohmann::json run = runJson(stats);
            run["device"] = device;
            run["estimator"] = estimator;
            run["setup_ms"] = baker.setupMs();  // GPU: upload, BVH build, shader compilation; CPU: Embree BVH
            std::printf("  %-4s %-7s %9.1f ms/probe  (G-buffer %8.1f, AO %9.1f, encode %6.1f = %5.1f%% of AO, read-back %6.1f)  "
                        "%7.2f Mrays/s  %5.1f fetches/texel  traced %5.1f%%\n",
                        device.c_str(), estimator.c_str(), run["ms_per_probe"].get<double>(), run["gbuffer_ms"].get<double>(),
                        run["ao_ms"].get<double>(), run["encode_ms"].get<double>(), 100.0 * run["encode_to_ao"].get<double>(),
                        run["readback_ms"].get<double>(), run["rays_per_s"].get<double>() * 1e-6,
                        run["fetches_per_texel"].get<double>(), 100.0 * run["traced_fraction"].get<double>());
            std::fflush(stdout);
            runs.push_back(run);
        }
    }
    return {{"scene", scene.source}, {"triangles", scene.triangleCount()}, {"radius", scene.defaultRadius()},
            {"probes", probes.size()}, {"gbuffer_modes_ms", gbufferModes}, {"runs", runs}};
}

void runBake(const BenchArgs& a) {
    if (!a.cameras.empty() && a.cameras.size() != a.scenes.size())
        throw UsageError("--camera: give one per --scene (or none for built-in scenes)");
    checkRange("--res", a.res, 4, 4096);  // resolveBakeSettings also wants a multiple of 4
    checkRange("--spp", a.spp, 1, 65536);
    checkRange("--probes", a.probes, 1, 4096);
    std::string whyNot;
    std::optional<gl::HeadlessContext> context;
    if (std::find(a.devices.begin(), a.devices.end(), "gpu") != a.devices.end()) {
        context = gl::HeadlessContext::tryCreate(&whyNot);
        if (!context) spdlog::warn("bench: no GL context ({}); GPU runs skipped", whyNot);
    }
    nlohmann::json scenes = nlohmann::json::array();
    for (std::size_t i = 0; i < a.scenes.size(); ++i) {
        std::printf("%s at %d² per face, %d spp, %d probes:\n", a.scenes[i].c_str(), a.res, a.spp, a.probes);
        scenes.push_back(benchScene(a, a.scenes[i], a.cameras.empty() ? "" : a.cameras[i], context));
    }
    nlohmann::json result = {{"bench", "bake"},
                             {"res", a.res},
                             {"spp", a.spp},
                             {"renderer", context ? context->renderer() : "none"},
                             {"cpu_threads", std::thread::hardware_concurrency()},
                             {"scenes", scenes}};
    if (a.json) printJson(result);
}

}  // namespace

void addBench(CLI::App& app) {
    auto* bench = app.add_subcommand("bench", "Timings as JSON");
    bench->require_subcommand(1);
    auto* cmd = bench->add_subcommand("bake", "Probe bake: ms per probe by stage, estimator and device");
    auto a = std::make_shared<BenchArgs>();
    cmd->add_option("--scene", a->scenes, "Scenes (repeatable)")->capture_default_str();
    cmd->add_option("--camera", a->cameras, "Camera path per scene: probes go to its eye positions");
    cmd->add_option("--estimator", a->estimators, "Estimators to time (repeatable)")->capture_default_str();
    cmd->add_option("--device", a->devices, "gpu and/or cpu")->capture_default_str();
    cmd->add_option("--res", a->res, "Face resolution, 4..4096")->capture_default_str();
    cmd->add_option("--spp", a->spp, "Rays per traced texel, 1..65536")->capture_default_str();
    cmd->add_option("--probes", a->probes, "Probes per scene, 1..4096")->capture_default_str();
    cmd->add_flag("--json", a->json, "Print one JSON object as the last line");
    cmd->callback([a] { runBake(*a); });
    addBenchDepth(*bench);
    addBenchCache(*bench);
    addBenchRender(*bench);
}

}  // namespace cubeao::cli
