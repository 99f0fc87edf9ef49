// cubeao bake SCENE --probes probes.json --out CACHE.cubeao: AO of every probe's cube map (DESIGN.md
// §4 "Bake"), compressed on the device that baked it (BC5 AO + confidence, a distance cube) and
// appended to the cache in batches (bake/bake_cache.h): an interrupted bake keeps what it appended,
// and running it again with the same parameters bakes only the probes still missing.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>

#include <spdlog/spdlog.h>

#include "bake_stats.h"
#include "cli_util.h"
#include "commands.h"
#include "cubeao/bake/bake.h"
#include "cubeao/bake/bake_cache.h"
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
                                          gbuffer = "layered", depthFormat = "r16unorm";
    int res = 0, spp = 0, directions = 0, steps = 0, verifySpp = 0, depthRes = 0;
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
    s.depthRes = a.depthRes;
    s.depthFormat = a.depthFormat == "r16unorm"   ? DepthFormat::R16Unorm
                    : a.depthFormat == "r16float" ? DepthFormat::R16Float
                    : a.depthFormat == "r32float"
                        ? DepthFormat::R32Float
                        : throw UsageError("--depth-format \"" + a.depthFormat + "\": expected r16unorm, r16float or r32float");
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
            {"hybrid_threshold", s.hybridThreshold},
            {"depth_res", s.depthRes},
            {"depth_format", depthFormatName(s.depthFormat)}};
}

// What a bake reports: the stats `bench bake` shares, plus the --verify sums and one entry per probe.
struct BakeTotals {
    BakeStats stats;
    double verifySum = 0.0, verifyNoise = 0.0;
    std::uint64_t verifyTexels = 0;
    nlohmann::json perProbe = nlohmann::json::array();
};

// The devices a bake needs. The GL context must outlive the baker (it owns GL objects): declared
// first, destroyed last.
struct Bakers {
    std::optional<gl::HeadlessContext> context;
    std::unique_ptr<GpuBaker> gpu;
    std::unique_ptr<EmbreeScene> embree;

    Bakers(const Scene& scene, const BakeSettings& settings, GBufferMode mode, BakeReadback readback, bool verify) {
        if (settings.device == BakeDevice::Gpu) {
            std::string whyNot;
            context = gl::HeadlessContext::tryCreate(&whyNot);
            if (!context) throw Error("--device gpu: no OpenGL 4.5 context (" + whyNot + "); use --device cpu");
            gpu = std::make_unique<GpuBaker>(scene, settings);
            gpu->setGBufferMode(mode);
            gpu->setReadback(readback);
        }
        if (settings.device == BakeDevice::Cpu || verify) embree = std::make_unique<EmbreeScene>(scene);
    }
    BakedProbe bake(const glm::vec3& position, std::uint32_t index, const BakeSettings& settings) const {
        return gpu ? gpu->bake(position, index) : bakeProbeCpu(*embree, position, index, settings);
    }
};

// Bakes probes `todo` into the cache; `verifySettings` is the Embree twin's (with --verify).
BakeTotals bakeProbes(const BakeArgs& a, const Bakers& bakers, const std::vector<ProbeSpec>& probes,
                      const std::vector<std::size_t>& todo, const BakeSettings& settings,
                      const BakeSettings& verifySettings, BakeCacheWriter& cache) {
    BakeTotals t;
    Progress progress("bake", todo.size());
    for (const std::size_t i : todo) {
        const auto index = std::uint32_t(i);
        const auto start = std::chrono::steady_clock::now();
        BakedProbe probe = bakers.bake(probes[i].position, index, settings);
        const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
        if (!a.dump.empty()) dumpProbe(a.dump, index, probe);
        nlohmann::json entry = {{"index", i},
                                {"pos", {probes[i].position.x, probes[i].position.y, probes[i].position.z}},
                                {"ms", ms},
                                {"gbuffer_ms", probe.timings.gbufferMs},
                                {"ao_ms", probe.timings.aoMs},
                                {"encode_ms", probe.timings.encodeMs},
                                {"error_ms", probe.timings.errorMs},
                                {"readback_ms", probe.timings.readbackMs},
                                {"surface_texels", probe.encoded.surfaceTexels},
                                {"traced_texels", probe.tracedTexels},
                                {"rays", probe.rays},
                                {"ao_psnr", aoPsnr(probe.encoded.aoSquaredError, probe.encoded.surfaceTexels)}};
        if (a.verify) {
            const VerifyResult v = verifyProbe(*bakers.embree, probe, index, verifySettings);
            entry["verify_mae"] = v.mae;
            entry["verify_noise"] = v.noise;
            t.verifySum += v.mae * double(v.texels);
            t.verifyNoise += v.noise * double(v.texels);
            t.verifyTexels += v.texels;
        }
        t.stats.add(probe, ms);
        t.perProbe.push_back(std::move(entry));
        EncodedProbe& e = probe.encoded;
        cache.add({index, probes[i].position, e.maxDistance, std::move(e.aoConfidence), std::move(e.depth)});
        progress.advance();
    }
    return t;
}

// The JSON a bake prints (and its one-line summary), from what it baked and what the cache now holds.
nlohmann::json report(const BakeArgs& a, const Scene& scene, const BakeSettings& settings,
                      const BakeSettings& verifySettings, const Shard& shard, const BakeTotals& t,
                      const BakeCacheWriter& cache, std::size_t probesTotal, std::size_t skipped,
                      const std::string& renderer) {
    const CacheReader written(a.out);
    const BakeStats& s = t.stats;
    const std::size_t baked = s.probes();
    nlohmann::json result = {{"scene", scene.source},
                             {"scene_hash", hashToString(scene.hash)},
                             {"probes", baked},
                             {"probes_skipped", skipped},  // already in the cache
                             {"probes_total", probesTotal},
                             {"probes_in_cache", written.probeCount()},
                             {"shard", {shard.index, shard.count}},
                             {"settings", settingsJson(settings)},
                             {"ms_per_probe", median(s.total)},
                             {"timings_ms", {{"gbuffer", median(s.gbuffer)}, {"ao", median(s.ao)}, {"encode", median(s.encode)},
                                             {"error", median(s.error)}, {"readback", median(s.readback)},
                                             {"write_total", cache.writeMs()}}},
                             {"bytes_per_texel", written.bytesPerTexel()},
                             {"file_bytes", written.fileSize()},
                             {"appends", cache.appends()},
                             {"rays", s.rays},
                             {"per_probe", t.perProbe},
                             {"out", a.out}};
    result.update(s.ratesJson());  // ao_psnr, traced_fraction, rays_per_s, rays_per_texel, fetches_per_texel
    if (!renderer.empty()) result["renderer"] = renderer;
    if (a.verify) {
        result["verify_mae"] = t.verifyTexels ? t.verifySum / double(t.verifyTexels) : 0.0;
        result["verify_noise"] = t.verifyTexels ? t.verifyNoise / double(t.verifyTexels) : 0.0;
        result["verify_spp"] = verifySettings.ao.spp;
    }
    if (!a.dump.empty()) result["dump"] = a.dump;
    std::printf("bake: %zu probes -> %s (%zu skipped: already there; %zu in the cache), %.1f ms per probe (%s, %s), "
                "AO PSNR %.1f dB, %.4f bytes/texel%s\n",
                baked, a.out.c_str(), skipped, written.probeCount(), median(s.total),
                estimatorName(settings.estimator), bakeDeviceName(settings.device), result["ao_psnr"].get<double>(),
                written.bytesPerTexel(),
                a.verify ? (", verify_mae " + std::to_string(result["verify_mae"].get<double>())).c_str() : "");
    return result;
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
    if (a.verifySpp < 0) throw UsageError("--verify-spp must be positive");
    BakeSettings verifySettings = settings;  // default: the bake's own rays (traced: the same rays)
    if (a.verifySpp > 0) verifySettings.ao.spp = a.verifySpp;

    BakeCacheWriter cache(a.out, cacheParamsFor(settings, scene.hash), probes);  // checks --out first
    std::vector<std::size_t> todo;
    std::size_t inShard = 0;
    for (std::size_t i = shard.index; i < probes.size(); i += shard.count, ++inShard)
        if (!cache.has(std::uint32_t(i))) todo.push_back(i);
    if (!a.dump.empty()) fs::create_directories(a.dump);
    spdlog::info("bake: {} ({} triangles), {} probes{}, {} already in {}, {} on the {}, {}² texels per face, R = {}",
                 scene.source, scene.triangleCount(), probes.size(),
                 shard.count > 1 ? " (shard " + std::to_string(shard.index) + "/" + std::to_string(shard.count) + ")" : "",
                 inShard - todo.size(), a.out, estimatorName(settings.estimator), bakeDeviceName(settings.device),
                 settings.res, settings.ao.radius);

    const BakeReadback readback = a.verify || !a.dump.empty() ? BakeReadback::All : BakeReadback::Encoded;
    std::optional<Bakers> bakers;
    if (!todo.empty()) bakers.emplace(scene, settings, gbufferMode, readback, a.verify);
    const BakeTotals t = todo.empty() ? BakeTotals{}
                                      : bakeProbes(a, *bakers, probes, todo, settings, verifySettings, cache);
    cache.finish();

    const nlohmann::json result = report(a, scene, settings, verifySettings, shard, t, cache, probes.size(),
                                         inShard - todo.size(), bakers && bakers->context ? bakers->context->renderer() : "");
    if (a.json) printJson(result);
}

}  // namespace

void addBake(CLI::App& app) {
    auto* cmd = app.add_subcommand("bake", "Bake AO into cube-map probes");
    auto a = std::make_shared<BakeArgs>();
    cmd->add_option("scene", a->scene, "Model file or builtin:NAME")->required();
    cmd->add_option("--probes", a->probes, "probes.json ({\"version\":1,\"probes\":[{\"pos\":[x,y,z]}]})")->required();
    cmd->add_option("--out", a->out, "Probe cache (.cubeao) to write; an existing one baked alike is resumed")
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
    cmd->add_option("--dump", a->dump, "Directory for per-face EXRs and a cross-layout PNG per probe (uncompressed)");
    cmd->add_option("--depth-res", a->depthRes, "Distance cube texels per side (default res/4)");
    cmd->add_option("--depth-format", a->depthFormat, "r16unorm | r16float | r32float")->capture_default_str();
    cmd->add_flag("--json", a->json, "Print one JSON object as the last line");
    cmd->callback([a] { run(*a); });
}

}  // namespace cubeao::cli
