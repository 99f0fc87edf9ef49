// cubeao bake SCENE --probes probes.json --out DIR: AO of every probe's cube map (DESIGN.md §4 "Bake").
// Until the .cubeao cache lands, --out is a directory: bake.json plus probe_NNNN_{ao,confidence,
// distance}.exr per probe (bake/bake_images.h), each written atomically as soon as the probe is done.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <optional>

#include <spdlog/spdlog.h>

#include "commands.h"
#include "cubeao/bake/bake.h"
#include "cubeao/bake/bake_images.h"
#include "cubeao/bake/gpu_bake.h"
#include "cubeao/bake/probe_set.h"
#include "cubeao/core/error.h"
#include "cubeao/core/progress.h"
#include "cubeao/gl/context.h"
#include "cubeao/scene/import.h"

namespace cubeao::cli {
namespace {

namespace fs = std::filesystem;

struct BakeArgs {
    std::string scene, probes, out, dump, estimator = "traced", device = "gpu", falloff = "none", shard,
                                          gbuffer = "layered";
    int res = 0, spp = 0, directions = 0, steps = 0, verifySpp = 0;
    float radius = 0.0f, hybridThreshold = 0.0f;
    std::uint32_t seed = 0;
    bool verify = false, json = false;
};

struct Shard {
    std::size_t index = 0, count = 1;
};

// "I/N": this run bakes the probes whose index ≡ I (mod N).
Shard parseShard(const std::string& text) {
    if (text.empty()) return {};
    const auto slash = text.find('/');
    try {
        if (slash != std::string::npos) {
            std::size_t used = 0;
            const long i = std::stol(text.substr(0, slash), &used);
            const bool wholeI = used == slash;
            const long n = std::stol(text.substr(slash + 1), &used);
            if (wholeI && used == text.size() - slash - 1 && n >= 1 && i >= 0 && i < n) return {std::size_t(i), std::size_t(n)};
        }
    } catch (const std::exception&) {
    }
    throw UsageError("--shard \"" + text + "\": expected I/N with 0 <= I < N");
}

BakeSettings settingsFrom(const BakeArgs& a, const Scene& scene) {
    BakeSettings s;
    s.res = a.res;
    s.estimator = parseEstimator(a.estimator);
    s.device = parseBakeDevice(a.device);
    s.ao = AoSettings{a.radius, a.spp, parseFalloff(a.falloff), a.seed};
    s.directions = a.directions;
    s.steps = a.steps;
    s.hybridThreshold = a.hybridThreshold;
    if (a.radius < 0.0f) throw UsageError("--radius must be positive");
    return resolveBakeSettings(s, scene.defaultRadius());
}

nlohmann::json settingsJson(const BakeSettings& s) {
    return {{"res", s.res},
            {"estimator", estimatorName(s.estimator)},
            {"device", bakeDeviceName(s.device)},
            {"radius", s.ao.radius},
            {"spp", s.ao.spp},
            {"falloff", falloffName(s.ao.falloff)},
            {"seed", s.ao.seed},
            {"directions", s.directions},
            {"steps", s.steps},
            {"hybrid_threshold", s.hybridThreshold}};
}

double median(std::vector<double> v) {
    if (v.empty()) return 0.0;
    std::sort(v.begin(), v.end());
    return v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
}

void run(const BakeArgs& a) {
    const Scene scene = loadScene(a.scene);
    const std::vector<ProbeSpec> probes = readProbeSet(a.probes);
    const BakeSettings settings = settingsFrom(a, scene);
    const Shard shard = parseShard(a.shard);
    const GBufferMode gbufferMode = a.gbuffer == "layered" ? GBufferMode::Layered
                                    : a.gbuffer == "six-pass"
                                        ? GBufferMode::SixPass
                                        : throw UsageError("--gbuffer \"" + a.gbuffer + "\": expected layered or six-pass");
    fs::create_directories(a.out);
    if (!a.dump.empty()) fs::create_directories(a.dump);

    // The GL context must outlive the baker (it owns GL objects): declared first, destroyed last.
    std::optional<gl::HeadlessContext> context;
    std::unique_ptr<GpuBaker> gpu;
    std::unique_ptr<EmbreeScene> embree;
    if (settings.device == BakeDevice::Gpu) {
        std::string whyNot;
        context = gl::HeadlessContext::tryCreate(&whyNot);
        if (!context) throw Error("--device gpu: no OpenGL 4.5 context (" + whyNot + "); use --device cpu");
        gpu = std::make_unique<GpuBaker>(scene, settings);
        gpu->setGBufferMode(gbufferMode);
    }
    if (settings.device == BakeDevice::Cpu || a.verify) embree = std::make_unique<EmbreeScene>(scene);
    if (a.verifySpp < 0) throw UsageError("--verify-spp must be positive");
    BakeSettings verifySettings = settings;  // default: the bake's own rays (traced: the same rays)
    if (a.verifySpp > 0) verifySettings.ao.spp = a.verifySpp;

    spdlog::info("bake: {} ({} triangles), {} probes{}, {} on the {}, {}² texels per face, R = {}", scene.source,
                 scene.triangleCount(), probes.size(),
                 shard.count > 1 ? " (shard " + std::to_string(shard.index) + "/" + std::to_string(shard.count) + ")" : "",
                 estimatorName(settings.estimator), bakeDeviceName(settings.device), settings.res, settings.ao.radius);

    nlohmann::json perProbe = nlohmann::json::array();
    std::vector<double> msTotal, msGBuffer, msAo, msReadback;
    double verifySum = 0.0, verifyNoise = 0.0, rayMs = 0.0;
    std::uint64_t verifyTexels = 0, traced = 0, surface = 0, rays = 0, fetches = 0;
    std::size_t baked = 0;
    Progress progress("bake", (probes.size() - shard.index + shard.count - 1) / shard.count);
    for (std::size_t i = shard.index; i < probes.size(); i += shard.count) {
        const auto index = std::uint32_t(i);
        const auto start = std::chrono::steady_clock::now();
        const BakedProbe probe = gpu ? gpu->bake(probes[i].position, index)
                                     : bakeProbeCpu(*embree, probes[i].position, index, settings);
        const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
        writeProbeImages(a.out, index, probe);
        if (!a.dump.empty()) dumpProbe(a.dump, index, probe);

        std::uint64_t surfaceTexels = 0;
        for (const auto& t : probe.gbuffer.texels) surfaceTexels += CubeGBuffer::empty(t) ? 0 : 1;
        nlohmann::json entry = {{"index", i},
                                {"pos", {probes[i].position.x, probes[i].position.y, probes[i].position.z}},
                                {"ms", ms},
                                {"gbuffer_ms", probe.timings.gbufferMs},
                                {"ao_ms", probe.timings.aoMs},
                                {"readback_ms", probe.timings.readbackMs},
                                {"surface_texels", surfaceTexels},
                                {"traced_texels", probe.tracedTexels},
                                {"rays", probe.rays}};
        if (a.verify) {
            const VerifyResult v = verifyProbe(*embree, probe, index, verifySettings);
            entry["verify_mae"] = v.mae;
            entry["verify_noise"] = v.noise;
            verifySum += v.mae * double(v.texels);
            verifyNoise += v.noise * double(v.texels);
            verifyTexels += v.texels;
        }
        perProbe.push_back(entry);
        msTotal.push_back(ms);
        msGBuffer.push_back(probe.timings.gbufferMs);
        msAo.push_back(probe.timings.aoMs);
        msReadback.push_back(probe.timings.readbackMs);
        if (probe.rays) rayMs += probe.timings.aoMs;
        traced += probe.tracedTexels;
        surface += surfaceTexels;
        rays += probe.rays;
        fetches += probe.fetches;
        ++baked;
        progress.advance();
    }

    nlohmann::json result = {{"scene", scene.source},
                             {"scene_hash", hashToString(scene.hash)},
                             {"probes", baked},
                             {"probes_total", probes.size()},
                             {"shard", {shard.index, shard.count}},
                             {"settings", settingsJson(settings)},
                             {"ms_per_probe", median(msTotal)},
                             {"timings_ms", {{"gbuffer", median(msGBuffer)}, {"ao", median(msAo)}, {"readback", median(msReadback)}}},
                             {"traced_fraction", surface ? double(traced) / double(surface) : 0.0},
                             {"rays", rays},
                             {"rays_per_s", rayMs > 0.0 ? double(rays) / (rayMs * 1e-3) : 0.0},
                             {"fetches_per_texel", surface ? double(fetches) / double(surface) : 0.0},
                             {"rays_per_texel", surface ? double(rays) / double(surface) : 0.0},
                             {"per_probe", perProbe},
                             {"out", a.out}};
    if (settings.device == BakeDevice::Gpu) result["renderer"] = context->renderer();
    if (a.verify) {
        result["verify_mae"] = verifyTexels ? verifySum / double(verifyTexels) : 0.0;
        result["verify_noise"] = verifyTexels ? verifyNoise / double(verifyTexels) : 0.0;
        result["verify_spp"] = verifySettings.ao.spp;
    }
    if (!a.dump.empty()) result["dump"] = a.dump;
    const fs::path manifest = fs::path(a.out) / "bake.json";
    {
        std::ofstream out(manifest.string() + ".tmp");
        out << result.dump(1) << '\n';
        if (!out) throw Error(manifest.string() + ": cannot write");
    }
    fs::rename(manifest.string() + ".tmp", manifest);
    std::printf("bake: %zu probes -> %s, %.1f ms per probe (%s, %s)%s\n", baked, a.out.c_str(), median(msTotal),
                estimatorName(settings.estimator), bakeDeviceName(settings.device),
                a.verify ? (", verify_mae " + std::to_string(result["verify_mae"].get<double>())).c_str() : "");
    if (a.json) printJson(result);
}

}  // namespace

void addBake(CLI::App& app) {
    auto* cmd = app.add_subcommand("bake", "Bake AO into cube-map probes");
    auto a = std::make_shared<BakeArgs>();
    cmd->add_option("scene", a->scene, "Model file or builtin:NAME")->required();
    cmd->add_option("--probes", a->probes, "probes.json ({\"version\":1,\"probes\":[{\"pos\":[x,y,z]}]})")->required();
    cmd->add_option("--out", a->out, "Output directory (bake.json + per-probe EXR faces until the .cubeao cache lands)")
        ->required();
    cmd->add_option("--res", a->res, "Face resolution in texels (default 512)");
    cmd->add_option("--estimator", a->estimator, "hsplit | gtao | traced | hybrid")->capture_default_str();
    cmd->add_option("--spp", a->spp, "Rays per traced texel (default 64)");
    cmd->add_option("--radius", a->radius, "AO radius R in scene units (default: 2% of the bbox diagonal)");
    cmd->add_option("--falloff", a->falloff, "none | smooth")->capture_default_str();
    cmd->add_option("--seed", a->seed, "Rotates every texel's sample set");
    cmd->add_option("--directions", a->directions, "Horizon directions N_d (default 16, even)");
    cmd->add_option("--steps", a->steps, "March steps N_s per direction (default 16)");
    cmd->add_option("--hybrid-threshold", a->hybridThreshold, "hybrid: trace texels with confidence below (default 0.95)");
    cmd->add_option("--device", a->device, "gpu (OpenGL 4.5) | cpu (Embree)")->capture_default_str();
    cmd->add_option("--gbuffer", a->gbuffer, "GPU G-buffer: layered | six-pass")->capture_default_str();
    cmd->add_option("--shard", a->shard, "I/N: bake only the probes with index = I mod N");
    cmd->add_flag("--verify", a->verify, "Also trace the Embree twin at every texel and report verify_mae");
    cmd->add_option("--verify-spp", a->verifySpp, "Rays per texel of the --verify reference (default: --spp, the same rays)");
    cmd->add_option("--dump", a->dump, "Directory for per-face EXRs and a cross-layout PNG per probe");
    cmd->add_flag("--json", a->json, "Print one JSON object as the last line");
    cmd->callback([a] { run(*a); });
}

}  // namespace cubeao::cli
