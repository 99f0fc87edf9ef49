// cubeao-view: the walkthrough viewer (issue 14, DESIGN.md §7). A GLFW window with a 4.5 core context,
// the run-time frame pipeline (runtime/frame_pipeline.h) over the opened cache or an empty probe set,
// the diagnostic view modes (view_modes.h), a Dear ImGui panel, and live placement: with it on, the
// placement's coverage class watches the frames, places probes where coverage falls, bakes them
// with the fast GPU estimator in time slices and re-bakes them with `traced` when the viewer is idle
// (placement/live_placement.h). Driven by keyboard and mouse, or by a script (script.h) for tests.
#pragma once

#include <string>

namespace cubeao::viewer {

struct ViewerOptions {
    std::string scene;          // file or builtin:NAME
    std::string cache;          // .cubeao to walk with ("" = none: gtao, or live placement from no probes)
    std::string camera;         // camera path JSON ("" = the builtin scene's own path, if any)
    std::string reference;      // `cubeao reference` output directory for the difference mode
    std::string script;         // drive the viewer from this file, then quit
    std::string saveTo;         // where Ctrl+S and the panel's Save write ("" = live.cubeao or the cache's name)
    std::string mode = "shaded";
    std::string statsJson;      // at exit, write a JSON summary (frames, coverage, probes, timings) here
    int width = 1280, height = 720;  // window size
    float scale = 0.5f;         // render resolution relative to the window (llvmpipe is slow)
    double gpuBudgetMb = 0.0;   // probe residency budget (0 = every probe resident)
    double uploadMb = 0.0;      // per-frame upload bound (0 = the default)
    bool live = false;          // live placement from the start
    double bakeMsPerFrame = 8.0;   // live placement's time slice per frame
    int liveRes = 128;          // face resolution of live-placed probes (placed for a 512² bake's density)
    std::string liveObjective = "error";  // live placement's objective: error (predicted AO error) or coverage
    double coverageTarget = 0.95;  // live placement with the coverage objective: coverage of the frames to reach
    bool vsync = true;
};

// Runs the viewer until the window closes, Esc, or the script's end. Returns the process exit code;
// cubeao::Error (bad input, no display) propagates with its message.
int runViewer(const ViewerOptions& options);

}  // namespace cubeao::viewer
