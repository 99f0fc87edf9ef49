// cubeao bench render: what a run-time frame costs per pass, for the probe projection and every
// screen-space baseline in one run (so the figures compare as ratios on a noisy machine), and how
// the projection's cost moves with the number of probes in the cache (issue 6: it must stay flat
// within 20 % from 10 to 10,000 probes, because the candidate grid caps the work at K probes per
// pixel).
//
// The sweep's caches are real caches read by the real upload path (the ProbeProjectionPass that
// `render --method probes --cache` builds), baked for the occasion at small faces so 10,000 probes
// take seconds: the CPU bake (Embree G-buffer, `traced` AO at few rays, the bake's own BC5 and
// distance-cube encoders) of probes scattered through the space the walk sees. Each count's cache
// holds the first N probes of one list, which is itself spread like the whole: density grows with
// N. The projection's timing depends on the cache's layout and the candidates, not on AO values,
// so few rays are enough.
//
// Timings are gl::timeGpu per pass (timer queries on a real GPU, wall clock around glFinish on
// llvmpipe), medians over --frames frames spread along the path × --rounds rounds, after one untimed
// warm-up frame (llvmpipe compiles shader variants on first use). The rounds interleave all methods
// and probe counts: on a shared machine a slow spell then hits all of them alike (sequential runs
// showed a 30 % "spread" over the sweep one time and 5 % the next).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>
#include <random>
#include <set>
#include <unistd.h>

#include <glm/geometric.hpp>
#include <spdlog/spdlog.h>

#include "cli_util.h"
#include "commands.h"
#include "render_setup.h"
#include "cubeao/bake/bake.h"
#include "cubeao/bake/bake_driver.h"
#include "cubeao/core/error.h"
#include "cubeao/core/progress.h"
#include "cubeao/gl/context.h"
#include "cubeao/gl/timer.h"
#include "cubeao/scene/builtin.h"
#include "cubeao/scene/import.h"

namespace cubeao::cli {
namespace {

namespace fs = std::filesystem;

struct RenderBenchArgs {
    std::string scene = "builtin:cloister", camera;
    int width = 1920, height = 1080, frames = 3, rounds = 3, res = 16, spp = 16;
    std::vector<std::size_t> probes{10, 100, 1000, 10000};
    std::vector<std::string> methods{"probes", "gtao", "hbao", "alchemy"};
    bool json = false;
};

constexpr double kFlatSpread = 0.2;  // issue 6: frame cost flat within 20 % over the sweep

// Every usage error at once, before anything is loaded.
void checkUsage(const RenderBenchArgs& a) {
    std::vector<std::string> problems;
    for (const std::string& m : a.methods)
        if (m != "probes" && m != "gtao" && m != "hbao" && m != "alchemy")
            problems.push_back("--methods \"" + m + "\": expected probes, gtao, hbao or alchemy");
    if (a.methods.empty()) problems.push_back("--methods: name at least one");
    if (a.width < 1 || a.height < 1) problems.push_back("--width and --height must be positive");
    if (a.frames < 1) problems.push_back("--frames must be at least 1");
    if (a.rounds < 1) problems.push_back("--rounds must be at least 1");
    if (a.res < 4 || a.res % 4 != 0) problems.push_back("--res must be a multiple of 4 (BC5 blocks)");
    if (a.spp < 1) problems.push_back("--spp must be at least 1");
    for (const std::size_t n : a.probes)
        if (n < 1) problems.push_back("--probes: every count must be at least 1");
    if (problems.empty()) return;
    std::string text = problems[0];
    for (std::size_t i = 1; i < problems.size(); ++i) text += "; " + problems[i];
    throw UsageError(text);
}

// `count` frames at the centres of equal parts of the path.
std::vector<std::size_t> benchFrames(const CameraPath& path, int count) {
    const std::size_t n = std::min(std::size_t(count), path.frames.size());
    std::vector<std::size_t> out;
    for (std::size_t k = 0; k < n; ++k) out.push_back((2 * k + 1) * path.frames.size() / (2 * n));
    return out;
}

// Probes scattered through the space the walk sees: a random point of the eye polyline, then a
// random direction and a random distance up to `maxOffset`, stopped `clearance` short of the first
// surface that way, so a probe is never inside geometry. Deterministic (fixed seed).
std::vector<glm::vec3> sweepPositions(const EmbreeScene& rt, const CameraPath& path, float maxOffset, float clearance,
                                      std::size_t count) {
    std::mt19937 rng(1);
    const auto uniform = [&] { return float(rng() >> 8) * (1.0f / 16777216.0f); };
    std::vector<glm::vec3> out;
    while (out.size() < count) {
        const float u = uniform() * float(path.frames.size() - 1);
        const std::size_t i = std::size_t(u);
        const std::size_t j = std::min(i + 1, path.frames.size() - 1);
        const glm::vec3 eye = glm::mix(path.frames[i].eye, path.frames[j].eye, u - float(i));
        const float z = 1.0f - 2.0f * uniform(), phi = 6.2831853f * uniform(), r = std::sqrt(std::max(0.0f, 1.0f - z * z));
        const glm::vec3 dir(r * std::cos(phi), z, r * std::sin(phi));
        const RayHit hit = rt.intersect(eye, dir, 0.0f, maxOffset + clearance);
        const float reach = (hit.hit ? hit.t : maxOffset + clearance) - clearance;
        out.push_back(eye + dir * (uniform() * std::max(0.0f, reach)));
    }
    return out;
}

struct SweepProbes {
    BakeSettings settings;
    std::vector<ProbeRecord> records;
    double bakeMs = 0.0;
};

SweepProbes bakeSweepProbes(const RenderBenchArgs& a, const Scene& scene, const CameraPath& path, std::size_t count) {
    SweepProbes s;
    s.settings.res = a.res;
    s.settings.estimator = Estimator::Traced;
    s.settings.ao.spp = a.spp;
    s.settings.device = BakeDevice::Cpu;
    s.settings = resolveBakeSettings(s.settings, scene.defaultRadius());
    ProbeBaker baker(scene, s.settings);
    baker.prepare();
    const float r = s.settings.ao.radius;
    std::vector<ProbeSpec> probes;
    for (const glm::vec3& p : sweepPositions(baker.embree(), path, 10.0f * r, 0.25f * r, count)) probes.push_back({p});
    spdlog::info("bench render: baking {} sweep probes at {}² (CPU, traced, {} rays per texel)", count, a.res, a.spp);
    const auto start = std::chrono::steady_clock::now();
    BakeJob job;
    job.probes = probes;
    MemoryProbeSink sink;
    bakeProbes(baker, job, sink);
    s.records = std::move(sink.records);
    s.bakeMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    return s;
}

// One method under test: its renderer (warmed up by one untimed frame: llvmpipe compiles shader
// variants on first use), what the report says of it, and its timings so far.
struct Timed {
    nlohmann::json row;
    std::unique_ptr<FrameRenderer> renderer;
    std::vector<PassTimings> timings;
    double fetches = 0.0, uncovered = 0.0;  // sums over the timed frames

    Timed(nlohmann::json r, std::unique_ptr<FrameRenderer> fr, const CameraPath& path, std::size_t frame, int w, int h)
        : row(std::move(r)), renderer(std::move(fr)) {
        renderer->render(frameView(path, frame, w, h), std::uint32_t(frame));
    }
    // One pass over the frames.
    void time(const CameraPath& path, const std::vector<std::size_t>& frames, int w, int h) {
        const auto* projection = dynamic_cast<const ProbeProjectionPass*>(&renderer->method());
        for (const std::size_t f : frames) {
            timings.push_back(renderer->render(frameView(path, f, w, h), std::uint32_t(f)).timings);
            fetches += renderer->method().fetchesPerPixel();
            if (projection) uncovered += projection->uncoveredFraction();
        }
    }
    // The row with the medians and per-pixel means.
    const nlohmann::json& finish() {
        const double n = double(std::max<std::size_t>(timings.size(), 1));
        row["timings_ms"] = timingsJson(timings);
        row["fetches_per_pixel"] = fetches / n;
        row["blur_fetches_per_pixel"] = renderer->blur().fetchesPerPixel();
        if (row.contains("probes")) row["uncovered_fraction"] = uncovered / n;
        return row;
    }
};

struct Bench {
    const RenderBenchArgs& args;
    const Scene& scene;
    const CameraPath& path;
    std::vector<std::size_t> frames;
    BlurSettings blur;
    CompositeSettings composite;

    std::unique_ptr<Timed> timed(nlohmann::json row, std::unique_ptr<AoPass> pass) const {
        auto renderer = std::make_unique<FrameRenderer>(scene.positions, scene.indices, std::move(pass), blur, composite);
        return std::make_unique<Timed>(std::move(row), std::move(renderer), path, frames[0], args.width, args.height);
    }

    std::unique_ptr<Timed> baseline(const std::string& method) const {
        SsaoSettings s;
        s.method = parseSsaoMethod(method);
        s = resolveSsaoSettings(s, scene.defaultRadius());
        return timed({{"method", method}, {"fetches_per_pixel_planned", plannedFetchesPerPixel(s)}},
                     makeAoPass(s, nullptr, scene));
    }

    // The first `count` sweep probes written as a cache and uploaded (the cache file is read while
    // the pass is built, then deleted).
    std::unique_ptr<Timed> probes(const SweepProbes& sweep, std::size_t count, const fs::path& dir) const {
        const fs::path file = dir / ("sweep_" + std::to_string(count) + ".cubeao");
        writeCache(file, cacheParamsFor(sweep.settings, scene.hash),
                   std::vector<ProbeRecord>(sweep.records.begin(), sweep.records.begin() + std::ptrdiff_t(count)));
        const CacheReader cache(file);
        std::unique_ptr<AoPass> pass;
        // Prep: read and checksum every probe, upload, build the candidate grid, compile.
        const double prepMs = gl::timeGpu([&] { pass = makeAoPass(SsaoSettings{}, &cache, scene); }).wallMs;
        const auto& projection = dynamic_cast<const ProbeProjectionPass&>(*pass);
        const ProbeAtlasLayout& atlas = projection.atlas();
        const ProbeGrid& grid = projection.grid();
        nlohmann::json row = {{"method", "probes"},
                              {"probes", count},
                              {"prep_ms", prepMs},
                              {"gpu_bytes", projection.gpuBytes()},
                              {"cache_bytes", cache.fileSize()},
                              {"atlas", {atlas.tilesX, atlas.tilesY, atlas.pages}},
                              {"grid", {{"dims", {grid.dims().x, grid.dims().y, grid.dims().z}},
                                        {"cell", grid.cellSize()}, {"candidates", grid.k()}}}};
        fs::remove(file);
        return timed(std::move(row), std::move(pass));
    }
};

void printHeader() {
    std::printf("%-8s %7s %9s %9s %8s %9s %9s %9s %10s %9s %9s %9s\n", "method", "probes", "G-buffer", "AO", "blur",
                "composite", "AO+blur", "frame", "fetches/px", "prep ms", "GPU MB", "uncovered");
}

void printRow(const nlohmann::json& r) {
    const nlohmann::json& t = r["timings_ms"];
    const bool probes = r.contains("probes");
    std::printf("%-8s %7s %9.1f %9.1f %8.1f %9.1f %9.1f %9.1f %10.1f", r["method"].get<std::string>().c_str(),
                probes ? std::to_string(r["probes"].get<std::size_t>()).c_str() : "-", t["gbuffer"].get<double>(),
                t["ao"].get<double>(), t["blur"].get<double>(), t["composite"].get<double>(), t["ao_blur"].get<double>(),
                t["gpu_total"].get<double>(), r["fetches_per_pixel"].get<double>());
    if (probes)
        std::printf(" %9.0f %9.2f %8.2f%%", r["prep_ms"].get<double>(), double(r["gpu_bytes"].get<std::size_t>()) / 1e6,
                    100.0 * r["uncovered_fraction"].get<double>());
    std::printf("\n");
    std::fflush(stdout);
}

// max/min − 1 of a timing over the sweep.
double spread(const nlohmann::json& sweep, const char* pass) {
    double lo = 0.0, hi = 0.0;
    for (const auto& r : sweep) {
        const double v = r["timings_ms"][pass].get<double>();
        lo = lo == 0.0 ? v : std::min(lo, v), hi = std::max(hi, v);
    }
    return lo > 0.0 ? hi / lo - 1.0 : 0.0;
}

// The two targets from the rows: probes (largest count) against gtao, and the sweep's spread.
nlohmann::json summary(const nlohmann::json& methods, const nlohmann::json& sweep) {
    nlohmann::json s = nlohmann::json::object();
    if (methods.contains("probes") && methods.contains("gtao")) {
        const double ratio = methods["probes"]["timings_ms"]["ao_blur"].get<double>() /
                             methods["gtao"]["timings_ms"]["ao_blur"].get<double>();
        s["probes_to_gtao_ao_blur"] = ratio;
        s["probes_within_gtao"] = ratio <= 1.0;
        std::printf("probes (%zu) / gtao, AO + blur: %.3f (target <= 1: %s)\n",
                    methods["probes"]["probes"].get<std::size_t>(), ratio, ratio <= 1.0 ? "met" : "missed");
    }
    if (sweep.size() > 1) {
        s["sweep_spread"] = spread(sweep, "gpu_total");
        s["sweep_spread_ao_blur"] = spread(sweep, "ao_blur");
        s["sweep_spread_ao"] = spread(sweep, "ao");
        s["sweep_flat"] = s["sweep_spread"].get<double>() <= kFlatSpread;
        std::printf("probe sweep, max/min - 1: frame %.1f %% (target <= %.0f %%: %s), AO + blur %.1f %%, AO pass %.1f %%\n",
                    100.0 * s["sweep_spread"].get<double>(), 100.0 * kFlatSpread,
                    s["sweep_flat"].get<bool>() ? "flat" : "not flat", 100.0 * s["sweep_spread_ao_blur"].get<double>(),
                    100.0 * s["sweep_spread_ao"].get<double>());
    }
    return s;
}

// Removes the sweep's cache directory however the bench ends.
struct TempDir {
    fs::path path = fs::temp_directory_path() / ("cubeao-bench-render-" + std::to_string(::getpid()));
    TempDir() { fs::create_directories(path); }
    ~TempDir() {
        std::error_code ignored;
        fs::remove_all(path, ignored);
    }
};

void run(const RenderBenchArgs& a) {
    checkUsage(a);
    const Scene scene = loadScene(a.scene);
    const CameraPath path = resolveCameraPath(a.camera, a.scene);
    std::string whyNot;
    const std::optional<gl::HeadlessContext> context = gl::HeadlessContext::tryCreate(&whyNot);
    if (!context) throw Error("bench render needs an OpenGL 4.5 context: " + whyNot);
    const Bench bench{a, scene, path, benchFrames(path, a.frames), BlurSettings{}, compositeFor(scene, 1.0f)};
    const std::set<std::size_t> counts(a.probes.begin(), a.probes.end());
    const bool wall = gl::trustedClock() == gl::GpuClock::WallClock;
    std::printf("bench render: %s, %dx%d, %zu frames x %d interleaved rounds (median), blur %d, on %s (%s); ms per pass:\n",
                scene.source.c_str(), a.width, a.height, bench.frames.size(), a.rounds, bench.blur.radius,
                context->renderer().c_str(),
                wall ? "wall clock around glFinish" : "GL timer queries");
    printHeader();

    // Every method is set up first and then timed in interleaved rounds, so that a slow spell of a
    // shared machine falls on all of them rather than on one.
    std::vector<std::unique_ptr<Timed>> timed;
    for (const std::string& m : a.methods)
        if (m != "probes") timed.push_back(bench.baseline(m));
    nlohmann::json sweepCaches;
    if (std::find(a.methods.begin(), a.methods.end(), "probes") != a.methods.end()) {
        const SweepProbes probes = bakeSweepProbes(a, scene, path, *counts.rbegin());
        sweepCaches = {{"how", "CPU bake (Embree; traced AO; the bake's BC5 and distance encoders) of probes scattered "
                               "within 10 R of the camera path, short of surfaces; each count = the first N of one list"},
                       {"res", probes.settings.res},
                       {"depth_res", probes.settings.depthRes},
                       {"spp", probes.settings.ao.spp},
                       {"bake_ms", probes.bakeMs},
                       {"bake_ms_per_probe", probes.bakeMs / double(*counts.rbegin())}};
        const TempDir dir;
        for (const std::size_t n : counts) timed.push_back(bench.probes(probes, n, dir.path));
    }
    for (int round = 0; round < a.rounds; ++round)
        for (const auto& t : timed) t->time(path, bench.frames, a.width, a.height);
    nlohmann::json methods = nlohmann::json::object(), sweep = nlohmann::json::array();
    for (const auto& t : timed) {
        const nlohmann::json& row = t->finish();
        printRow(row);
        if (row.contains("probes")) sweep.push_back(row);
        methods[row["method"].get<std::string>()] = row;  // probes: the largest count, the last
    }
    const nlohmann::json targets = summary(methods, sweep);
    if (a.json) {
        std::fflush(stdout);  // the table (stdio) before the JSON line (iostream)
        printJson({{"bench", "render"},
                   {"scene", scene.source},
                   {"width", a.width},
                   {"height", a.height},
                   {"frames", bench.frames},
                   {"rounds", a.rounds},
                   {"radius", scene.defaultRadius()},
                   {"blur", bench.blur.radius},
                   {"renderer", context->renderer()},
                   {"clock", wall ? "wall_clock_glfinish" : "gl_timer_query"},
                   {"methods", methods},
                   {"sweep", sweep},
                   {"sweep_caches", sweepCaches},
                   {"targets", targets}});
    }
}

}  // namespace

void addBenchRender(CLI::App& bench) {
    auto* cmd = bench.add_subcommand("render", "Run-time frame: ms per pass for probes and baselines; probe-count sweep");
    auto a = std::make_shared<RenderBenchArgs>();
    cmd->add_option("--scene", a->scene, "Scene")->capture_default_str();
    cmd->add_option("--camera", a->camera, "Camera path (default for built-in scenes: their own)");
    cmd->add_option("--width", a->width, "Frame width")->capture_default_str();
    cmd->add_option("--height", a->height, "Frame height")->capture_default_str();
    cmd->add_option("--frames", a->frames, "Path frames timed (spread along the path; median reported)")
        ->capture_default_str();
    cmd->add_option("--rounds", a->rounds, "Times every method is timed over the frames, interleaved with the others")
        ->capture_default_str();
    cmd->add_option("--probes", a->probes, "Probe counts of the sweep (comma-separated); the largest is \"probes\"")
        ->delimiter(',')
        ->capture_default_str();
    cmd->add_option("--res", a->res, "Face resolution of the sweep's probes (small: 10,000 must fit)")
        ->capture_default_str();
    cmd->add_option("--spp", a->spp, "Rays per texel of the sweep's bake (AO values do not change the timing)")
        ->capture_default_str();
    cmd->add_option("--methods", a->methods, "Any of probes, gtao, hbao, alchemy (comma-separated)")
        ->delimiter(',')
        ->capture_default_str();
    cmd->add_flag("--json", a->json, "Print one JSON object as the last line");
    cmd->callback([a] { run(*a); });
}

}  // namespace cubeao::cli
