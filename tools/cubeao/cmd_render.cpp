// cubeao render SCENE --camera PATH.json --out DIR [--method ...]: run-time AO of a camera path, one
// pass at a time (camera G-buffer → AO method → edge-aware blur → composite), with per-pass timings.
// Writes ao_NNNN.exr (+ .png) comparable with `cubeao reference` and a lit preview shaded_NNNN.png.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>
#include <vector>

#include <spdlog/spdlog.h>

#include "cli_util.h"
#include "commands.h"
#include "run_json.h"
#include "cubeao/cache/cache_file.h"
#include "cubeao/runtime/probe_projection.h"
#include "cubeao/core/durable_file.h"
#include "cubeao/core/error.h"
#include "cubeao/core/progress.h"
#include "cubeao/gl/context.h"
#include "cubeao/gl/timer.h"
#include "cubeao/metrics/image_io.h"
#include "cubeao/runtime/renderer.h"
#include "cubeao/scene/builtin.h"
#include "cubeao/scene/import.h"
#include "cubeao/ssao/ao_methods.h"

namespace cubeao::cli {
namespace {

namespace fs = std::filesystem;

struct RenderArgs {
    std::string scene, camera, out, cache, frames, method, falloff = "none";  // method "": withDefaults
    int width = 0, height = 0, directions = 0, steps = 0;
    std::optional<int> blur;  // unset: 2, for the probes probeBlurSettings
    float radius = 0.0f, alpha = 1.0f, alchemySigma = 0.0f;
    double gpuBudgetMb = 0.0, uploadMb = 0.0;  // probes: 0 = everything resident; 0 = the default bound
    std::string fallback = "gtao";
    std::uint32_t seed = 0, level = 0;  // level: probes, the level of detail every probe is held at
    float depthLift = 0.0f;             // probes: the depth test's lift (projection.h ProjectSettings::depthOffset)
    bool json = false;
};

// A cache is only of use to `probes`, so giving one picks it; without one, gtao (the best baseline
// against the reference: docs/BENCHMARKS.md). An explicit --method always wins.
RenderArgs withDefaults(RenderArgs a) {
    if (a.method.empty()) a.method = a.cache.empty() ? "gtao" : "probes";
    return a;
}

// Every problem with the method choice is a usage error, found before any file is read. `probes`
// keeps gtao's settings for the JSON fields it shares with the baselines.
SsaoMethod parseMethod(const RenderArgs& a) {
    if (a.method == "probes") {
        if (a.cache.empty()) throw UsageError("--method probes needs --cache CACHE.cubeao (from cubeao bake)");
        return SsaoMethod::Gtao;
    }
    if (a.method != "alchemy" && a.method != "hbao" && a.method != "gtao")
        throw UsageError("--method \"" + a.method + "\": expected probes, alchemy, hbao or gtao");
    return parseSsaoMethod(a.method);
}

struct PassSettings {
    SsaoSettings ssao;  // radius still 0 = scene default until the scene is loaded
    BlurSettings blur;
    ProbeProjectionSettings probes;
};

// Every usage error, before any file is read.
PassSettings usageChecked(const RenderArgs& a) {
    PassSettings p;
    p.ssao.method = parseMethod(a);
    p.ssao.falloff = parseFalloff(a.falloff);
    p.ssao.directions = a.directions, p.ssao.steps = a.steps, p.ssao.seed = a.seed;
    checkFiniteNonNegative("--alchemy-sigma", a.alchemySigma, " (0: the default, 0.8)");
    p.ssao.alchemyIntensity = a.alchemySigma;
    checkFiniteNonNegative("--radius", a.radius, " (0: 2% of the scene's diagonal)");
    p.ssao.radius = a.radius;
    checkImageSizeOptions(a.width, a.height);
    checkRange("--directions", a.directions, 0, 64, " (0: 8; even)");
    checkRange("--steps", a.steps, 0, 64, " (0: 8)");
    if (a.blur) p.blur.radius = *a.blur;
    validateBlurSettings(p.blur);
    if (!(a.alpha >= 0.0f && a.alpha <= 1.0f)) throw UsageError("--alpha must lie in [0, 1]");
    if (!a.cache.empty() && a.method != "probes")
        spdlog::warn("render: --cache is used only by --method probes; ignored for {}", a.method);
    checkResidencyOptions(a.gpuBudgetMb, a.uploadMb);
    if (a.fallback != "gtao" && a.fallback != "none")
        throw UsageError("--fallback \"" + a.fallback + "\": expected gtao or none");
    p.probes.residency = ResidencySettings::fromMib(a.gpuBudgetMb, a.uploadMb);
    p.probes.level = a.level;
    if (!(a.depthLift >= 0.0f && a.depthLift <= 4.0f)) throw UsageError("--depth-lift must lie in [0, 4]");
    p.probes.project.depthOffset = a.depthLift;
    return p;
}

// Writes ao_NNNN.exr/.png and shaded_NNNN.png of frame f; returns its entry of "frames".
nlohmann::json writeFrame(const fs::path& out, std::size_t f, const RenderedFrame& frame) {
    const fs::path exr = out / frameName("ao", f, "exr"), shaded = out / frameName("shaded", f, "png");
    writeExr(exr, frame.ao);
    writePng(out / frameName("ao", f, "png"), frame.ao);
    writePngRgb(shaded, frame.ao.width, frame.ao.height, frame.shadedRgb);
    const PassTimings& t = frame.timings;
    return {{"index", f},
            {"file", exr.string()},
            {"shaded", shaded.string()},
            {"timings_ms",
             {{"gbuffer", t.gbuffer}, {"ao", t.ao}, {"blur", t.blur}, {"composite", t.composite}, {"readback", t.readback}}}};
}

// Per frame: where the pixels' AO came from and what the residency did; sums for the run.
struct PixelShares {
    double probes = 0.0, fallbackProbe = 0.0, uncovered = 0.0, screenSpace = 0.0, blended = 0.0;

    nlohmann::json add(const ProbeProjectionPass& p) {
        const ProbeProjectionPass::PixelShares s = p.pixelShares();
        const double u = s.uncovered, fb = s.fallbackProbe;
        const double geometry = std::max(s.geometry, u + fb);  // exact counts; no rounding below 0
        const double filled = p.fallback() ? p.fallback()->filledFraction() : 0.0;
        const double blend = p.fallback() ? p.fallback()->blendedFraction() : 0.0;
        probes += geometry - u - fb, fallbackProbe += fb, uncovered += u, screenSpace += filled, blended += blend;
        const ResidencyStats& r = p.residency().stats();
        return {{"pixels_probes", geometry - u - fb}, {"pixels_fallback_probe", fb},   {"pixels_uncovered", u},
                {"pixels_screen_space", filled},      {"pixels_blended", blend},       {"resident", r.resident},
                {"uploads", r.frameUploads},          {"upload_bytes", r.frameUploadBytes},
                {"upload_ms", r.frameUploadMs}};
    }
    // Means over the frames, as shares of all pixels.
    nlohmann::json json(std::size_t frames) const {
        const double n = double(std::max<std::size_t>(frames, 1));
        return {{"probes", probes / n},        {"fallback_probe", fallbackProbe / n}, {"uncovered", uncovered / n},
                {"screen_space", screenSpace / n}, {"blended", blended / n}};
    }
};

// The probes' cache for `scene`; the probes carry their own R, which `ssao` takes (a different --radius
// would compare them against the wrong AO).
std::unique_ptr<CacheReader> openProbeCache(const std::string& file, const Scene& scene, SsaoSettings& ssao) {
    auto cache = std::make_unique<CacheReader>(file);
    cache->expectScene(scene.hash);
    if (ssao.radius > 0.0f && ssao.radius != cache->params().radius)
        throw UsageError("--radius " + std::to_string(ssao.radius) + ": " + file + " was baked with R = " +
                         std::to_string(cache->params().radius));
    ssao.radius = cache->params().radius;
    return cache;
}

void run(const RenderArgs& a) {
    PassSettings settings = usageChecked(a);
    const Scene scene = loadScene(a.scene);
    const CameraPath path = resolveCameraPath(a.camera, scene);
    const FrameRange range = parseFrameRange(a.frames, path.frames.size());
    std::unique_ptr<CacheReader> cache = a.method == "probes" ? openProbeCache(a.cache, scene, settings.ssao) : nullptr;
    const SsaoSettings ssao = resolveSsaoSettings(settings.ssao, scene.defaultRadius());
    int w = 0, h = 0;
    resolveImageSize(a.width, a.height, path, w, h);
    if (cache && !a.blur)
        settings.blur =
            probeBlurSettings(int(cache->params().res), h, CameraView::fromPath(path, range.begin, w, h).tanHalfFovY);
    fs::create_directories(a.out);

    const gl::HeadlessContext context = gl::HeadlessContext::create();
    spdlog::info("render: {} ({} triangles), {} frames {}:{} at {}x{}, R = {}, on {}", scene.source,
                 scene.triangleCount(), a.method, range.begin, range.end, w, h, ssao.radius,
                 context.renderer());
    const CompositeSettings composite = previewComposite(scene.up, a.alpha);
    FrameRenderer renderer(
        scene.positions, scene.indices,
        makeAoPass(ssao, cache.get(), scene.positions, scene.indices, settings.probes, a.fallback == "gtao"),
        settings.blur, composite);
    auto* projection = dynamic_cast<ProbeProjectionPass*>(&renderer.method());
    PixelShares shares;

    nlohmann::json frames = nlohmann::json::array();
    std::vector<PassTimings> timings;
    double fetches = 0.0;
    Progress progress("render", range.size(), "frames");
    for (std::size_t f = range.begin; f < range.end; ++f) {
        const RenderedFrame frame = renderer.render(CameraView::fromPath(path, f, w, h), std::uint32_t(f));
        fetches += renderer.method().fetchesPerPixel();
        timings.push_back(frame.timings);
        frames.push_back(writeFrame(a.out, f, frame));
        if (projection) frames.back()["probes"] = shares.add(*projection);
        progress.advance();
    }
    const double fetchesPerPixel = fetches / double(range.size());
    const nlohmann::json medians = timingsJson(timings);
    const bool wall = gl::trustedClock() == gl::GpuClock::WallClock;
    nlohmann::json result = {{"scene", scene.source},
                                   {"scene_hash", hashToString(scene.hash)},
                                   {"method", renderer.method().name()},
                                   {"radius", ssao.radius},
                                   {"falloff", falloffName(ssao.falloff)},
                                   {"directions", ssao.directions},
                                   {"steps", ssao.steps},
                                   {"blur", settings.blur.radius},
                                   {"alpha", composite.alpha},
                                   {"seed", ssao.seed},
                                   {"width", w},
                                   {"height", h},
                                   {"frames", frames},
                                   {"timings_ms", medians},
                                   {"clock", wall ? "wall_clock_glfinish" : "gl_timer_query"},
                                   {"renderer", context.renderer()},
                                   {"fetches_per_pixel", fetchesPerPixel},
                                   {"fetches_per_pixel_planned", plannedFetchesPerPixel(ssao)},
                                   {"blur_fetches_per_pixel", renderer.blur().fetchesPerPixel()},
                                   {"out", a.out}};
    result["peak_rss_mb"] = peakRssMib();
    if (projection) {
        result["uncovered_fraction"] = shares.uncovered / double(range.size());
        result["pixels"] = shares.json(range.size());
        result["cache"] = a.cache;
        result["probes"] = cache->probeCount();
        result["level"] = a.level;
        result["depth_lift"] = a.depthLift;
        result["residency"] = residencyJson(*projection);
        result["residency"]["gpu_budget_mb"] = a.gpuBudgetMb, result["residency"]["fallback"] = a.fallback;
    }
    writeFileDurably(fs::path(a.out) / "render.json", result.dump(1) + "\n");
    std::printf("render: %s, %zu frames -> %s; median ms: G-buffer %.2f, AO %.2f, blur %.2f, composite %.2f, "
                "read-back %.2f (%s); %.1f fetches/pixel\n",
                renderer.method().name(), range.size(), a.out.c_str(), medians["gbuffer"].get<double>(),
                medians["ao"].get<double>(), medians["blur"].get<double>(), medians["composite"].get<double>(),
                medians["readback"].get<double>(), wall ? "wall clock" : "GL timer queries", fetchesPerPixel);
    if (const std::size_t damaged = projection ? projection->residency().stats().damaged : 0; damaged > 0)
        spdlog::warn("render: {} damaged probe{} of {} left out: their pixels took the other probes (`cubeao info {} "
                     "--verify` lists the damage)",
                     damaged, damaged == 1 ? "" : "s", cache->probeCount(), a.cache);
    if (a.json) {
        std::fflush(stdout);  // the summary (stdio) before the JSON line (iostream)
        printJson(result);
    }
}

}  // namespace

void addRender(CLI::App& app) {
    auto* cmd = app.add_subcommand("render", "Run-time AO of a camera path: probes from a cache, or a screen-space baseline");
    auto a = std::make_shared<RenderArgs>();
    cmd->add_option("scene", a->scene, "Model file or builtin:NAME")->required();
    cmd->add_option("--camera", a->camera, "Camera path JSON (default for built-in scenes: their own path)");
    cmd->add_option("--out", a->out, "Output directory for ao_NNNN.exr/.png, shaded_NNNN.png, render.json")->required();
    cmd->add_option("--method", a->method, "probes | alchemy | hbao | gtao (default: probes with --cache, else gtao)");
    cmd->add_option("--cache", a->cache, "Probe cache (.cubeao) from cubeao bake; makes probes the default method");
    cmd->add_option("--frames", a->frames, "Half-open frame range A:B (default: all)");
    cmd->add_option("--width", a->width, "Image width (default: the camera file's)");
    cmd->add_option("--height", a->height, "Image height (default: the camera file's)");
    cmd->add_option("--radius", a->radius, "AO radius R in scene units (default: 2% of the bbox diagonal)");
    cmd->add_option("--falloff", a->falloff, "none | smooth")->capture_default_str();
    cmd->add_option("--directions", a->directions, "Screen directions N_d, even (default 8)");
    cmd->add_option("--steps", a->steps, "March steps per direction N_s (default 8)");
    cmd->add_option("--alchemy-sigma", a->alchemySigma, "Alchemy intensity sigma (default 0.8)");
    cmd->add_option("--blur", a->blur,
                    "Blur taps on each side per pass, 0 = off (default 2; probes: 1 while a probe texel spans "
                    "at most 3 pixels)");
    cmd->add_option("--alpha", a->alpha, "AO strength in the preview: i = i_s((1-a) + a*ao)")->capture_default_str();
    cmd->add_option("--seed", a->seed, "Changes every pixel's jitter");
    cmd->add_option("--gpu-budget-mb", a->gpuBudgetMb,
                    "probes: GPU memory for probes, grid and staging, MiB; probes stream in by priority (default 0: all resident)");
    cmd->add_option("--upload-mb", a->uploadMb, "probes: bytes uploaded per frame at most, MiB (default 8)");
    cmd->add_option("--level", a->level,
                    "probes: hold every probe at this level of detail of a cache baked with --levels (0: the finest)");
    cmd->add_option("--depth-lift", a->depthLift,
                    "probes: the depth test also lifts each point this many distance texels off its surface (0: off; "
                    "0.71: no AO through thin walls, at some cost in coverage: docs/ALGORITHMS.md)")
        ->capture_default_str();
    cmd->add_option("--fallback", a->fallback, "probes: what pixels no resident probe sees get: gtao | none (open)")
        ->capture_default_str();
    cmd->add_flag("--json", a->json, "Print one JSON object as the last line");
    cmd->callback([a] { run(withDefaults(*a)); });
}

}  // namespace cubeao::cli
