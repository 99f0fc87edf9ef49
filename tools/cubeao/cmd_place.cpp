// cubeao place SCENE --method path --out probes.json: where probes go. Only the stand-in method
// `path` exists so far (probes spread evenly along the camera path, at the camera's eye height);
// coverage feedback and normal voting (DESIGN.md §4 "Placement") come with the placement issue.
#include <cstdio>

#include "commands.h"
#include "cubeao/bake/probe_set.h"
#include "cubeao/core/error.h"
#include "cubeao/scene/builtin.h"

namespace cubeao::cli {
namespace {

struct PlaceArgs {
    std::string scene, camera, out, method = "path";
    int budget = 8;
    bool json = false;
};

void run(const PlaceArgs& a) {
    if (a.method == "voting" || a.method == "coverage" || a.method == "grid")
        throw UsageError("--method " + a.method + ": not implemented yet (placement issue); use --method path");
    if (a.method != "path") throw UsageError("--method \"" + a.method + "\": expected path, grid, voting or coverage");
    if (a.budget < 1) throw UsageError("--budget must be at least 1");
    const CameraPath path = resolveCameraPath(a.camera, a.scene);
    const std::vector<ProbeSpec> probes = probesAlongPath(path, std::size_t(a.budget));
    writeProbeSet(a.out, probes);
    std::printf("place: %zu probes along the camera path -> %s\n", probes.size(), a.out.c_str());
    if (a.json) printJson({{"probes", probes.size()}, {"method", a.method}, {"out", a.out}});
}

}  // namespace

void addPlace(CLI::App& app) {
    auto* cmd = app.add_subcommand("place", "Place probes (probes.json)");
    auto a = std::make_shared<PlaceArgs>();
    cmd->add_option("scene", a->scene, "Model file or builtin:NAME")->required();
    cmd->add_option("--method", a->method, "path (for now: along the camera path)")->capture_default_str();
    cmd->add_option("--camera", a->camera, "Camera path JSON (default for built-in scenes: their own path)");
    cmd->add_option("--budget", a->budget, "Number of probes")->capture_default_str();
    cmd->add_option("--out", a->out, "probes.json to write")->required();
    cmd->add_flag("--json", a->json, "Print one JSON object as the last line");
    cmd->callback([a] { run(*a); });
}

}  // namespace cubeao::cli
