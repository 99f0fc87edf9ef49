// cubeao place SCENE --method voting|coverage|grid|path --out probes.json: where probes go (DESIGN.md
// §4 "Placement", placement/include/cubeao/placement/placement.h). Every method reports coverage the
// same way; probes.json records the method, its parameters, the report and each probe's gain.
#include <sys/resource.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <memory>

#include "commands.h"
#include "cubeao/core/error.h"
#include "cubeao/gl/context.h"
#include "cubeao/placement/gpu_coverage.h"
#include "cubeao/placement/place.h"
#include "cubeao/placement/probe_set.h"
#include "cubeao/scene/builtin.h"
#include "cubeao/scene/import.h"
#include "cubeao/scene/repair.h"

namespace cubeao::cli {
namespace {

struct PlaceArgs {
    std::string scene, camera, out, method = "voting", device = "gpu";
    placement::PlaceSettings settings;
    bool json = false;
};

// Why voting stopped, in words for the summary line ("" for the other methods).
std::string stopReason(const placement::Placement& result) {
    const std::string& stop = result.stop;
    if (stop == "budget") return "; the budget";
    if (stop == "target_error") return "; --target-error reached";
    if (stop == "automatic") {
        char share[32];
        std::snprintf(share, sizeof share, "%g", 100.0 * placement::kAutomaticStop);
        std::string why = "; the next probe would remove under " + std::string(share) + " % of the predicted error";
        for (const auto& [name, value] : result.figures)
            if (name == "pruned" && value > 0.0)
                why += ", and " + std::to_string(int(value)) + (value == 1.0 ? " probe that" : " probes that") +
                       " removed under " + share + " % given the others dropped";
        return why;
    }
    if (stop == "no_gain") return "; no further probe lowers the predicted error (fewer than --budget)";
    return "";
}

double peakMemoryMb() {
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    return double(usage.ru_maxrss) / 1024.0;  // Linux reports kilobytes
}

// No probe placed: say which of the usual causes applies: no free space at all (a closed solid, or faces
// whose winding flips, which the back-face inside test reads as inside), or free space farther from every
// surface than a probe of this face size covers.
[[noreturn]] void throwNoProbes(const std::string& m, const Scene& scene, const placement::PlacementScene& ps,
                                const placement::PlaceSettings& settings) {
    const std::size_t free = ps.freeSpace().candidates().size();
    std::string why = "is the scene open on every side, or --voxel/--clearance too large?";
    const WindingCheck winding = checkWinding(scene);
    if (free == 0 && winding.flippedShare() > 0.01) {
        char share[32];
        std::snprintf(share, sizeof share, "%.1f %%", 100.0 * winding.flippedShare());
        why = "the faces' winding is inconsistent (" + std::string(share) + " of shared edges are run the same way "
              "by both faces), so free space reads as inside geometry; orient the faces consistently";
    } else if (free > 0) {
        why = "a probe covers a surface only within " + std::to_string(ps.criterion().maxDistance()) +
              " of it at --res " + std::to_string(settings.res) + " (a texel at most R/" +
              std::to_string(int(settings.texelsPerRadius)) + "): raise --res or lower --texels-per-radius";
    }
    throw Error("place --method " + m + ": no probe placed (" + std::to_string(free) + " free voxels; " +
                std::to_string(std::count(ps.relevant().begin(), ps.relevant().end(), 1)) +
                " relevant samples): " + why);
}

// probes.json's fields beside the probes (probe_set.h): the method, its settings, the walk, the figures
// the placement predicts, free space's counts, each probe's coverage gain, the stages' times.
nlohmann::json placementReport(const std::string& m, const placement::PlacementScene& ps,
                               const placement::Placement& result, const nlohmann::json& camera,
                               const nlohmann::json& coverageGains) {
    nlohmann::json timings = nlohmann::json::object(), figures = nlohmann::json::object();
    for (const auto& [stage, seconds] : result.timings) timings[stage] = seconds;
    for (const auto& [name, value] : result.figures) figures[name] = value;
    const placement::FreeSpace::Stats& fs = ps.freeSpace().stats();
    return {
        {"method", m},
        {"params", ps.settings().toJson()},
        {"camera", camera},  // null: none
        // Named for what they are (issue 31): the error model's walk MAE, the relevant area some probe
        // sees (what the projection serves), and the fine coverage (a texel at most R / texels-per-radius).
        {"predicted_mae", result.predictedMae},
        {"served", result.served},
        {"coverage", result.coverage},
        {"coverage2", result.coverage2},
        {"relevant_area", result.relevantArea},
        {"stop", result.stop.empty() ? nlohmann::json() : nlohmann::json(result.stop)},
        {"free_space",
         {{"voxels", fs.voxels}, {"candidates", fs.candidates}, {"reached", fs.reached}, {"too_close", fs.tooClose},
          {"inside_by_rays", fs.insideByRays}, {"inside_closed", fs.insideClosed}, {"outside_seeds", fs.outsideSeeds},
          {"eye_seeds", fs.seeds}, {"eyes_not_free", fs.seedsNotFree}, {"reversed_faces", fs.reversedFaces},
          {"closed_solids", fs.closedSolids}, {"closed_rooms", fs.closedRooms}, {"open_components", fs.openComponents}}},
        {"coverage_gains", coverageGains},
        {"figures", figures},
        {"timings_s", timings}};
}

void run(PlaceArgs a) {
    if (a.device != "gpu" && a.device != "cpu") throw UsageError("--device \"" + a.device + "\": expected gpu or cpu");
    const placement::Method method = placement::parseMethod(a.method);
    placement::checkMethodSettings(method, a.settings);
    const std::string m = placement::methodName(method);
    a.settings.validate();
    // Before the work, not after it: a probes.json that cannot be written should cost nothing.
    const std::filesystem::path outDir = std::filesystem::path(a.out).parent_path();
    std::error_code ec;
    if (!outDir.empty()) std::filesystem::create_directories(outDir, ec);
    if (ec) throw Error(a.out + ": cannot create its directory (" + ec.message() + ")");
    const Scene scene = loadScene(a.scene);
    // The path and coverage methods walk a camera path; voting and grid use one when given (it decides
    // what is relevant) and free space otherwise. Built-in scenes bring their own path.
    std::unique_ptr<CameraPath> path;
    if (placement::needsWalk(method) || !a.camera.empty())
        path = std::make_unique<CameraPath>(resolveCameraPath(a.camera, scene));
    // `live` weighs the walk one frame at a time, as the viewer does (given the walk, the viewer builds
    // the same scene: the walk bounds what is relevant and seeds free space).
    const placement::PlacementScene ps(scene, a.settings, path.get());

    // Coverage counts its frames on the GPU when a GL 4.5 context can be made (asynchronously: frames
    // are handled as their counts come back); otherwise, or with --device cpu, every frame is traced
    // with Embree. Same probes either way up to pixels at silhouettes.
    std::optional<gl::HeadlessContext> context;
    std::unique_ptr<placement::GpuCoverageCount> gpu;
    if (method == placement::Method::Coverage && a.device == "gpu") {
        std::string whyNot;
        context = gl::HeadlessContext::tryCreate(&whyNot);
        if (context) {
            context->makeCurrent();
            gpu = std::make_unique<placement::GpuCoverageCount>(scene, path->nearPlane);
        } else {
            std::printf("place: no OpenGL 4.5 context (%s): counting frames on the CPU\n", whyNot.c_str());
        }
    }
    const placement::Placement result = placement::place(method, ps, path.get(), gpu.get());
    if (result.probes.empty() && result.stop == "target_error")
        throw Error("place --method voting: --target-error " + std::to_string(a.settings.targetError) +
                    " is met without any probe (screen space alone is predicted at " +
                    std::to_string(result.predictedMae) + "): nothing to place; lower it");
    if (result.probes.empty()) throwNoProbes(m, scene, ps, a.settings);

    std::vector<ProbeSpec> probes;
    // Each probe's "gain" is the predicted walk MAE it removed after the ones before it (issue 31); the
    // fine coverage it added goes beside it.
    nlohmann::json coverageGains = nlohmann::json::array();
    for (const placement::PlacedProbe& p : result.probes) {
        probes.push_back({p.position, p.errorRemoved});
        coverageGains.push_back(p.gain);
    }
    const nlohmann::json report = placementReport(
        m, ps, result, path ? nlohmann::json(a.camera.empty() ? a.scene : a.camera) : nlohmann::json(), coverageGains);
    writeProbeSet(a.out, probes, report, scene.origin);
    std::printf("place %s: %zu probes, predicted MAE %.4f, served %.1f %% of %.4g relevant area, fine coverage %.1f %% "
                "(twice: %.1f %%)%s -> %s\n",
                m.c_str(), probes.size(), result.predictedMae, 100.0 * result.served, result.relevantArea,
                100.0 * result.coverage, 100.0 * result.coverage2, stopReason(result).c_str(), a.out.c_str());
    if (a.json) {
        nlohmann::json j = report;
        j["probes"] = probes.size();
        j["out"] = a.out;
        j["peak_memory_mb"] = peakMemoryMb();
        printJson(j);
    }
}

}  // namespace

void addPlace(CLI::App& app) {
    auto* cmd = app.add_subcommand("place", "Place probes (probes.json)");
    auto a = std::make_shared<PlaceArgs>();
    placement::PlaceSettings& s = a->settings;
    cmd->add_option("scene", a->scene, "Model file or builtin:NAME")->required();
    cmd->add_option("--method", a->method,
                    "voting (normal voting + greedy on predicted error), live (the viewer's live placement run "
                    "along --camera), coverage (coverage feedback along --camera), grid (uniform, spacing searched), "
                    "path (along --camera)")
        ->capture_default_str();
    cmd->add_option("--out", a->out, "probes.json to write")->required();
    cmd->add_option("--camera", a->camera,
                    "Camera path JSON: what it sees is what must be covered (default for built-in scenes with "
                    "path/coverage: their own path; voting/grid without it cover what free space sees)");
    cmd->add_option("--budget", s.budget,
                    "voting: exactly this many probes (fewer only when no probe lowers the predicted error); "
                    "grid: at most; path: how many (0: no limit)")
        ->capture_default_str();
    cmd->add_option("--coverage-target", s.target, "grid, coverage: fine coverage to reach, in (0, 1]")
        ->capture_default_str();
    cmd->add_option("--target-error", s.targetError,
                    "voting: stop once the predicted walk MAE is at most this (0: stop where the next probe "
                    "removes under 1 % of it, keeping only probes that each remove 1 % given the others)")
        ->capture_default_str();
    cmd->add_option("--voxel", s.voxel, "Candidate voxel edge (0: ~150k voxels in the box)")->capture_default_str();
    cmd->add_option("--clearance", s.clearance, "Least distance from a probe to geometry (0: half a voxel)")
        ->capture_default_str();
    cmd->add_option("--radius", s.radius, "AO radius (0: 2 % of the scene diagonal)")->capture_default_str();
    cmd->add_option("--res", s.res, "Probe face size the quality threshold assumes (the bake's --res)")
        ->capture_default_str();
    cmd->add_option("--texels-per-radius", s.texelsPerRadius,
                    "Covered: one probe texel spans at most radius / this on the surface")
        ->capture_default_str();
    cmd->add_option("--samples", s.samples, "Surface points (two sides each)")->capture_default_str();
    cmd->add_option("--rays", s.votingRays, "Voting rays per surface sample")->capture_default_str();
    cmd->add_option("--seed", s.seed, "Seed of the samples and rays")->capture_default_str();
    cmd->add_option("--device", a->device,
                    "coverage: count each frame's uncovered pixels on the gpu (falls back to cpu without GL) or cpu")
        ->capture_default_str();
    cmd->add_flag("--json", a->json, "Print one JSON object as the last line");
    cmd->callback([a] { run(*a); });
}

}  // namespace cubeao::cli
