// cubeao bake SCENE --probes probes.json --out CACHE.cubeao: AO of every probe's cube map (DESIGN.md
// §4 "Bake"), compressed on the device that baked it (BC5 AO + confidence, kept as BC4 AO alone for
// traced caches, whose confidence is 1; a distance cube) and
// written to the cache in batches (bake/bake_cache.h): an interrupted bake keeps what it wrote, and
// running it again with the same parameters bakes only the probes still missing. The loop itself is
// the library's (bake/bake_driver.h); this file parses flags and prints the report.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>

#include <spdlog/spdlog.h>

#include "cli_util.h"
#include "commands.h"
#include "cubeao/bake/bake.h"
#include "cubeao/bake/bake_cache.h"
#include "cubeao/bake/bake_driver.h"
#include "cubeao/bake/bake_images.h"
#include "cubeao/bake/gpu_bake.h"
#include "cubeao/placement/probe_set.h"
#include "cubeao/core/error.h"
#include "cubeao/gl/context.h"
#include "cubeao/scene/import.h"

namespace cubeao::cli {
namespace {

namespace fs = std::filesystem;

struct BakeArgs {
    std::string scene, probes, out, dump, estimator = "traced", device = "gpu", falloff = "none", shard,
                                          gbuffer = "layered", depthFormat = "r16unorm", ao, levels;
    int res = 0, spp = 0, directions = 0, steps = 0, verifySpp = 0, depthRes = 0, denoise = -1;
    float radius = 0.0f, hybridThreshold = 0.0f;
    std::uint32_t seed = 0;
    bool verify = false, timings = false, json = false;
};

// --levels: a count or "max"; empty: the default (0).
int parseLevels(const std::string& levels) {
    if (levels.empty()) return 0;
    if (levels == "max") return kAllLevels;
    if (levels.find_first_not_of("0123456789") == std::string::npos && levels.size() <= 2) return std::stoi(levels);
    throw UsageError("--levels \"" + levels + "\": expected a count of levels of detail (1 = none) or max");
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
    s.denoise = a.denoise;
    if (!a.ao.empty()) s.aoFormat = parseAoFormat(a.ao);
    s.levels = parseLevels(a.levels);
    s.depthFormat = a.depthFormat == "r16unorm"   ? DepthFormat::R16Unorm
                    : a.depthFormat == "r16float" ? DepthFormat::R16Float
                    : a.depthFormat == "r32float"
                        ? DepthFormat::R32Float
                        : throw UsageError("--depth-format \"" + a.depthFormat + "\": expected r16unorm, r16float or r32float");
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
            {"depth_format", depthFormatName(s.depthFormat)},
            {"denoise", s.denoise},
            {"ao_format", aoFormatName(*s.aoFormat)},
            {"levels", s.levels}};
}

nlohmann::json timingsJson(const BakeTimings& t) {
    return {{"gbuffer_ms", t.gbufferMs}, {"ao_ms", t.aoMs}, {"encode_ms", t.encodeMs}, {"error_ms", t.errorMs},
            {"readback_ms", t.readbackMs}};
}

nlohmann::json verifyJson(const VerifyResult& v, const char* prefix) {
    const std::string p = prefix;
    return {{p + "_mae", v.mae}, {p + "_noise", v.noise}};
}

nlohmann::json probeJson(const ProbeBakeResult& p, bool timings) {
    nlohmann::json entry = {{"index", p.index},
                            {"pos", {p.position.x, p.position.y, p.position.z}},
                            {"ms", p.ms},
                            {"surface_texels", p.surfaceTexels},
                            {"traced_texels", p.tracedTexels},
                            {"rays", p.rays},
                            {"ao_psnr", p.aoPsnr}};
    if (timings) entry.update(timingsJson(p.timings));
    if (p.verify) entry.update(verifyJson(*p.verify, "verify"));
    if (p.twin) entry.update(verifyJson(*p.twin, "twin"));
    return entry;
}

// The JSON a bake prints (and its one-line summary), from what it baked and what the cache now holds.
nlohmann::json report(const BakeArgs& a, const Scene& scene, const BakeSettings& settings, const BakeShard& shard,
                      const BakeResult& r, const BakeCacheWriter& cache, std::size_t probesTotal,
                      const std::string& renderer) {
    const CacheReader written(a.out);
    const BakeStats& s = r.stats;
    nlohmann::json perProbe = nlohmann::json::array();
    for (const ProbeBakeResult& p : r.probes) perProbe.push_back(probeJson(p, a.timings));
    nlohmann::json result = {{"scene", scene.source},
                             {"scene_hash", hashToString(scene.hash)},
                             {"probes", s.probes()},
                             {"probes_skipped", r.skipped},  // already in the cache
                             {"probes_total", probesTotal},
                             {"probes_in_cache", written.probeCount()},
                             {"shard", {shard.index, shard.count}},
                             {"settings", settingsJson(settings)},
                             {"ms_per_probe", median(s.total)},
                             {"bytes_per_texel", written.bytesPerTexel()},
                             {"file_bytes", written.fileSize()},
                             {"appends", cache.appends()},  // batches written (part files, docs/FORMAT.md)
                             {"rays", s.rays},
                             {"per_probe", perProbe},
                             {"out", a.out}};
    result.update(s.ratesJson());  // ao_psnr, traced_fraction, rays_per_s, rays_per_texel, fetches_per_texel
    // Stage medians only when asked: on the GPU path timing a stage stalls the pipeline around it.
    if (a.timings)
        result["timings_ms"] = {{"gbuffer", median(s.gbuffer)}, {"ao", median(s.ao)},       {"encode", median(s.encode)},
                                {"error", median(s.error)},     {"readback", median(s.readback)},
                                {"write_total", cache.writeMs()}, {"merge", cache.mergeMs()}};
    if (!renderer.empty()) result["renderer"] = renderer;
    if (a.verify) {
        result.update(verifyJson(r.verify, "verify"));
        result["verify_spp"] = r.verifySpp;
        result["verify_seed"] = verifyReferenceSettings(settings, a.verifySpp).ao.seed;
        if (r.twin.texels) result.update(verifyJson(r.twin, "twin"));
    }
    if (!a.dump.empty()) result["dump"] = a.dump;
    std::string verifyText;
    if (a.verify) {
        char buf[160];
        std::snprintf(buf, sizeof buf, ", verify_mae %.5f (noise %.5f, %d rays)", r.verify.mae, r.verify.noise, r.verifySpp);
        verifyText = buf;
        if (r.twin.texels) {
            std::snprintf(buf, sizeof buf, ", twin_mae %.5f", r.twin.mae);
            verifyText += buf;
        }
    }
    std::printf("bake: %zu probes -> %s (%zu skipped: already there; %zu in the cache), %.1f ms per probe (%s, %s), "
                "AO PSNR %.1f dB, %.4f bytes/texel%s\n",
                s.probes(), a.out.c_str(), r.skipped, written.probeCount(), median(s.total),
                estimatorName(settings.estimator), bakeDeviceName(settings.device), result["ao_psnr"].get<double>(),
                written.bytesPerTexel(), verifyText.c_str());
    return result;
}

// The numeric options' ranges, before the scene or the probe set is read (issue 15); 0 is each one's
// default. resolveBakeSettings checks what depends on other values (multiples of 4, depth-res ≤ res).
void checkRanges(const BakeArgs& a) {
    checkRange("--res", a.res, 0, 4096, " (0: 512; a multiple of 4)");
    checkRange("--spp", a.spp, 0, 65536, " (0: 64)");
    checkFiniteNonNegative("--radius", a.radius, " (0: 2% of the scene's diagonal)");
    checkRange("--directions", a.directions, 0, 64, " (0: 16; even)");
    checkRange("--steps", a.steps, 0, 64, " (0: 16)");
    checkRange("--hybrid-threshold", a.hybridThreshold, 0.0f, 1.0f, " (0: 0.95)");
    checkRange("--depth-res", a.depthRes, 0, 4096, " (0: res/4)");
    checkRange("--denoise", a.denoise, -1, kMaxDenoiseRadius, " (-1: 1 for traced and hybrid, else 0)");
    checkRange("--verify-spp", a.verifySpp, 0, 4 * 65536, " (0: 4x --spp)");
}

void run(const BakeArgs& a) {
    checkRanges(a);
    const Scene scene = loadScene(a.scene);
    const std::vector<glm::vec3> probes = positionsOf(readProbeSet(a.probes, scene.origin));
    const BakeSettings settings = settingsFrom(a, scene);
    const BakeShard shard = parseBakeShard(a.shard);
    ProbeBakerOptions options;
    options.gbuffer = a.gbuffer == "layered"    ? GBufferMode::Layered
                      : a.gbuffer == "six-pass" ? GBufferMode::SixPass
                                                : throw UsageError("--gbuffer \"" + a.gbuffer + "\": expected layered or six-pass");
    options.timings = a.timings;

    BakeCacheWriter cache(a.out, cacheParamsFor(settings, scene), probes);  // checks --out first
    const std::size_t todo = probesToBake(probes.size(), shard, cache).size();
    if (!a.dump.empty()) fs::create_directories(a.dump);
    spdlog::info("bake: {} ({} triangles), {} probes{}, {} to bake into {}, {} on the {}, {}² texels per face, R = {}",
                 scene.source, scene.triangleCount(), probes.size(),
                 shard.count > 1 ? " (shard " + std::to_string(shard.index) + "/" + std::to_string(shard.count) + ")" : "",
                 todo, a.out, estimatorName(settings.estimator), bakeDeviceName(settings.device), settings.res,
                 settings.ao.radius);

    BakeJob job;
    job.probes = probes;
    job.shard = shard;
    if (a.verify) job.verify = VerifySpec{a.verifySpp};
    if (!a.dump.empty()) job.onProbe = [&](std::uint32_t index, const BakedProbe& p) { dumpProbe(a.dump, index, p); };
    // The GL context must outlive the baker (it owns GL objects): declared first, destroyed last.
    std::optional<gl::HeadlessContext> context;
    if (todo > 0 && settings.device == BakeDevice::Gpu) {
        std::string whyNot;
        context = gl::HeadlessContext::tryCreate(&whyNot);
        if (!context) throw Error("--device gpu: no OpenGL 4.5 context (" + whyNot + "); use --device cpu");
    }
    ProbeBaker baker(scene, settings, options);  // sets up on the first probe: nothing when all are there
    const BakeResult result = bakeProbes(baker, job, cache);
    cache.finish();

    const nlohmann::json json = report(a, scene, settings, shard, result, cache, probes.size(),
                                       context ? context->renderer() : "");
    if (a.json) printJson(json);
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
    cmd->add_flag("--verify", a->verify,
                  "Also trace an independent Embree reference at every texel and report the bake's error as verify_mae "
                  "(GPU traced: also twin_mae, against the Embree twin tracing the same rays)");
    cmd->add_option("--verify-spp", a->verifySpp, "Rays per texel of the --verify reference (default: 4x --spp)");
    cmd->add_flag("--timings", a->timings, "Time every stage (timings_ms); on the GPU this stalls between stages");
    cmd->add_option("--dump", a->dump, "Directory for per-face EXRs and a cross-layout PNG per probe (uncompressed)");
    cmd->add_option("--denoise", a->denoise,
                    "Edge-aware filter of traced AO, texels a side (default 1 for traced and hybrid, 0 = off)");
    cmd->add_option("--depth-res", a->depthRes, "Distance cube texels per side (default res/4)");
    cmd->add_option("--depth-format", a->depthFormat, "r16unorm | r16float | r32float")->capture_default_str();
    cmd->add_option("--ao", a->ao, "Cached AO: bc4 (AO alone; traced's default) | bc5 (AO + confidence; the others')");
    cmd->add_option("--levels", a->levels,
                    "Levels of detail stored per probe, each half the last's resolution: a count (default 1: none) or "
                    "max (down to 16² faces)");
    cmd->add_flag("--json", a->json, "Print one JSON object as the last line");
    cmd->callback([a] { run(*a); });
}

}  // namespace cubeao::cli
