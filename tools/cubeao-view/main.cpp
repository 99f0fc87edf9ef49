// cubeao-view SCENE [--cache CACHE.cubeao] [--camera PATH.json] [--reference DIR] [--script FILE] ...:
// the walkthrough viewer (viewer.h). Exit codes as the CLI's: 0 done, 1 an error, 2 a usage error.
#include <cstdio>

#include <CLI/CLI.hpp>
#include <spdlog/spdlog.h>

#include "cubeao-view/view_modes.h"
#include "cubeao-view/viewer.h"
#include "cubeao/core/error.h"
#include "cubeao/scenes/builtin_scenes.h"

int main(int argc, char** argv) {
    using namespace cubeao;
    scenes::registerBuiltinScenes();
    viewer::ViewerOptions o;
    CLI::App app{"cubeao-view: walk through a scene with its AO probes; place probes live"};
    app.add_option("scene", o.scene, "scene file or builtin:NAME")->required();
    app.add_option("--cache", o.cache, "probe cache (.cubeao) to walk with");
    app.add_option("--camera", o.camera, "camera path JSON to follow (P plays it)");
    app.add_option("--reference", o.reference, "`cubeao reference` directory for the difference mode");
    app.add_option("--script", o.script, "drive the viewer from a script (see tools/cubeao-view/script.h), then quit");
    app.add_option("--save", o.saveTo, "where Ctrl+S saves the probes (default live.cubeao)");
    std::string modes;
    for (viewer::ViewMode m : viewer::allViewModes()) modes += std::string(modes.empty() ? "" : "|") + viewer::viewModeName(m);
    app.add_option("--mode", o.mode, "view mode at start: " + modes);
    app.add_option("--width", o.width, "window width");
    app.add_option("--height", o.height, "window height");
    app.add_option("--scale", o.scale, "render resolution relative to the window (default 0.5)");
    app.add_option("--gpu-budget-mb", o.gpuBudgetMb, "probe residency budget, MiB (0 = every probe resident)");
    app.add_option("--upload-mb", o.uploadMb, "probe uploads per frame, MiB (0 = the default, 8)");
    app.add_flag("--live", o.live, "live placement from the start (without --cache: from no probes)");
    app.add_option("--bake-ms", o.bakeMsPerFrame, "live placement: bake time slice per frame, ms (default 8)");
    app.add_option("--live-res", o.liveRes, "live placement: face resolution of new probes (default 128)");
    app.add_option("--live-objective", o.liveObjective,
                   "live placement: error (probes where the predicted AO error of the walk so far asks, as `place` "
                   "does; default) or coverage (until --coverage-target of each frame is finely covered)");
    app.add_option("--coverage-target", o.coverageTarget,
                   "live placement with --live-objective coverage: coverage of the frames to reach (default 0.95)");
    app.add_option("--stats", o.statsJson, "write a JSON summary at exit");
    app.add_flag("!--no-vsync", o.vsync, "render as fast as possible");
    CLI11_PARSE(app, argc, argv);
    try {
        return viewer::runViewer(o);
    } catch (const UsageError& e) {
        std::fprintf(stderr, "cubeao-view: %s\n", e.what());
        return 2;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "cubeao-view: %s\n", e.what());
        return 1;
    }
}
