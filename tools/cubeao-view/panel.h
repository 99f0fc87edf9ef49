// cubeao-view's Dear ImGui panel: one function per section (view, frame, probes, live placement,
// camera), each drawing what the viewer measured and editing the ViewerState where a person changes
// a setting directly (mode, baseline, render scale). Actions that the viewer must carry out (live
// placement, playback, recording, saving, a path frame) come back as PanelRequests.
#pragma once

#include <cstddef>
#include <deque>
#include <optional>
#include <string>

#include "cubeao-view/viewer_state.h"
#include "cubeao/runtime/frame_pipeline.h"
#include "cubeao/runtime/probe_projection.h"

namespace cubeao::placement {
class LivePlacement;
}

namespace cubeao::viewer {

// What the panel shows and cannot change.
struct PanelFigures {
    std::string sceneName;
    std::size_t triangles = 0;
    int width = 0, height = 0;                 // the render's pixels
    bool fixedSize = false;                    // a script's `size`: no render-scale slider
    double frameMs = 0.0;                      // the last frame's wall time
    const std::deque<double>* recentFrameMs = nullptr;  // the last frames' wall times, oldest first
    std::optional<PassTimings> gpu;            // per-pass GPU ms of a recent frame
    bool gpuTimesAreExecution = true;          // false on software GL
    const ProbeProjectionPass* probes = nullptr;  // null: no probe pass
    ProbeProjectionPass::PixelShares shares;
    std::size_t damaged = 0;                   // damaged probes left out (the pass's and live placement's)
    const placement::LivePlacement* live = nullptr;  // null: not started
    bool coverageObjective = false;            // live placement aims at coverage (else the predicted error)
    double coverageTarget = 0.0, bakeMsBudget = 0.0;
    std::size_t pathFrames = 0;                // 0: no camera path
};

// What a press on the panel asks of the viewer this frame.
struct PanelRequests {
    std::optional<bool> live;                  // turn live placement on or off
    std::optional<std::size_t> pathFrame;      // jump to this path frame
    bool togglePlaying = false, toggleRecording = false, save = false;
};

PanelRequests drawPanel(ViewerState& state, const PanelFigures& figures);

}  // namespace cubeao::viewer
