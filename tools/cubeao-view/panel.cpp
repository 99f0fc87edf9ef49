#include "cubeao-view/panel.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <vector>

#include <imgui.h>

#include "cubeao/placement/live_placement.h"

namespace cubeao::viewer {
namespace {

const ImVec4 kWarning(1.0f, 0.6f, 0.2f, 1.0f);

// A titled separator (ImGui 1.86 has no SeparatorText).
void section(const char* title) {
    ImGui::Spacing();
    ImGui::Separator();
    ImGui::TextColored(ImVec4(0.55f, 0.75f, 1.0f, 1.0f), "%s", title);
}

// The view mode with its legend; the baseline when the mode shows one.
void viewSection(ViewerState& s) {
    const std::span<const ViewMode> all = allViewModes();
    if (ImGui::BeginCombo("view", viewModeName(s.mode))) {
        for (std::size_t i = 0; i < all.size(); ++i) {
            char label[64];
            std::snprintf(label, sizeof label, "%zu  %s", i + 1, viewModeName(all[i]));
            if (ImGui::Selectable(label, all[i] == s.mode)) s.mode = all[i];
        }
        ImGui::EndCombo();
    }
    if (s.mode == ViewMode::Baseline && ImGui::BeginCombo("baseline", s.baseline.c_str())) {
        for (const char* b : viewerBaselines())
            if (ImGui::Selectable(b, s.baseline == b)) s.baseline = b;
        ImGui::EndCombo();
    }
    ImGui::PushTextWrapPos(340.0f);
    ImGui::TextDisabled("%s", viewModeLegend(s.mode));
    ImGui::PopTextWrapPos();
}

// Wall time with its recent history, size, render scale and the GPU's per-pass times.
void frameSection(ViewerState& s, const PanelFigures& f) {
    section("frame");
    ImGui::Text("%.1f ms (%.0f fps) · %d × %d px", f.frameMs, f.frameMs > 0.0 ? 1000.0 / f.frameMs : 0.0, f.width,
                f.height);
    if (f.recentFrameMs && !f.recentFrameMs->empty()) {
        const std::vector<float> t(f.recentFrameMs->begin(), f.recentFrameMs->end());
        ImGui::PlotLines("##frames", t.data(), int(t.size()), 0, "frame ms", 0.0f,
                         std::max(33.0f, *std::max_element(t.begin(), t.end())), ImVec2(250, 36));
    }
    if (!f.fixedSize) ImGui::SliderFloat("render scale", &s.scale, 0.1f, 1.0f, "%.2f");
    if (f.gpu) {
        ImGui::Text("GPU ms  gbuf %.1f · ao %.1f · blur %.1f · comp %.1f", f.gpu->gbuffer, f.gpu->ao, f.gpu->blur,
                    f.gpu->composite);
        if (!f.gpuTimesAreExecution) ImGui::TextDisabled("(software GL: these do not measure execution)");
    }
}

// Residency, uploads, who served the pixels, damaged probes.
void probesSection(const PanelFigures& f) {
    if (!f.probes) return;
    section("probes");
    const ResidencyStats& r = f.probes->residency().stats();
    ImGui::Text("%zu resident of %zu · %zu slots · %.1f MB", r.resident, f.probes->source().probes().liveCount(),
                r.slots, double(f.probes->gpuBytes()) / 1048576.0);
    ImGui::Text("uploads %zu this frame (%.1f KB, %.2f ms)", r.frameUploads, double(r.frameUploadBytes) / 1024.0,
                r.frameUploadMs);
    const double probesShare = std::max(0.0, f.shares.geometry - f.shares.uncovered - f.shares.fallbackProbe);
    ImGui::Text("pixels  probes %.1f %% · other probe %.1f %% · GTAO %.1f %%", 100.0 * probesShare,
                100.0 * f.shares.fallbackProbe, 100.0 * f.shares.uncovered);
    if (f.damaged > 0)
        ImGui::TextColored(kWarning, "%zu damaged probe%s left out (checksum; see the log)", f.damaged,
                           f.damaged == 1 ? "" : "s");
}

// On/off, the objective's figure, the bake's progress and budget, why it cannot place; save.
void liveSection(const ViewerState& s, const PanelFigures& f, PanelRequests& r) {
    section("live placement");
    bool on = s.liveOn;
    if (ImGui::Checkbox("place probes while walking (L)", &on)) r.live = on;
    if (f.live) {
        const placement::LivePlacement::Stats l = f.live->stats();
        if (f.coverageObjective) {
            ImGui::ProgressBar(float(l.coverage), ImVec2(170, 0));
            ImGui::SameLine();
            ImGui::Text("coverage (target %.0f %%)", 100.0 * f.coverageTarget);
        } else {
            ImGui::Text("predicted AO error of the walk so far: %.4f", l.predictedMae);
        }
        ImGui::Text("placed %zu · baked %zu · re-baked %zu · queued %zu", l.placed, l.baked, l.rebaked, l.queued);
        ImGui::Text("bake %.1f ms/frame (budget %.1f)", l.bakeMsMean, f.bakeMsBudget);
        if (l.stalled) ImGui::TextColored(kWarning, "cannot place: %s", l.stalled);
    }
    if (ImGui::Button("save (Ctrl+S)")) r.save = true;
}

// Where the camera is, the path slider and playback, recording, the keys, the last action's message.
void cameraSection(const ViewerState& s, const PanelFigures& f, PanelRequests& r) {
    section("camera");
    ImGui::Text("eye %.2f %.2f %.2f · %.2f/s", s.camera.eye.x, s.camera.eye.y, s.camera.eye.z, s.speed);
    if (f.pathFrames > 0) {
        int frame = s.pathFrame ? int(*s.pathFrame) : -1;
        if (ImGui::SliderInt("path frame", &frame, 0, int(f.pathFrames) - 1)) r.pathFrame = std::size_t(std::max(frame, 0));
        if (ImGui::Button(s.playing ? "pause (P)" : "play (P)")) r.togglePlaying = true;
        ImGui::SameLine();
    }
    if (ImGui::Button(s.recordFile ? "stop recording (R)" : "record (R)")) r.toggleRecording = true;
    if (s.recordFile) {
        ImGui::SameLine();
        ImGui::TextColored(ImVec4(1.0f, 0.35f, 0.3f, 1.0f), "REC %zu", s.recorded.size());
    }
    ImGui::TextDisabled("WASD QE move · right drag look · wheel speed");
    ImGui::TextDisabled("1-8 modes · F12 shot · Tab panel · Esc quit");
    if (!s.status.empty()) {
        ImGui::PushTextWrapPos(340.0f);
        ImGui::TextWrapped("%s", s.status.c_str());
        ImGui::PopTextWrapPos();
    }
}

}  // namespace

PanelRequests drawPanel(ViewerState& state, const PanelFigures& figures) {
    ImGui::SetNextWindowPos(ImVec2(10, 10), ImGuiCond_FirstUseEver);
    ImGui::SetNextWindowSize(ImVec2(330, 0), ImGuiCond_FirstUseEver);
    ImGui::SetNextWindowBgAlpha(0.82f);
    ImGui::Begin("cubeao", nullptr, ImGuiWindowFlags_AlwaysAutoResize);
    ImGui::PushItemWidth(170.0f);
    ImGui::TextDisabled("%s  (%zu triangles)", std::filesystem::path(figures.sceneName).filename().c_str(),
                        figures.triangles);
    PanelRequests requests;
    viewSection(state);
    frameSection(state, figures);
    probesSection(figures);
    liveSection(state, figures, requests);
    cameraSection(state, figures, requests);
    ImGui::PopItemWidth();
    ImGui::End();
    return requests;
}

}  // namespace cubeao::viewer
