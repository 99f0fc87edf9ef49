// The viewer's view modes and baselines by name (no GL): what --mode, the script's `mode` and
// `baseline`, the keys 1–8 and the panel choose from. Drawing them is view_modes.h's.
#pragma once

#include <optional>
#include <span>
#include <string_view>

namespace cubeao::viewer {

enum class ViewMode { Shaded, Ao, ProbeId, Footprint, Confidence, Path, Baseline, ReferenceDiff };

// Every mode, in the order of the enum (the panel's order and the keys 1–8).
std::span<const ViewMode> allViewModes();
// "shaded", "ao", "probe", "footprint", "confidence", "path", "baseline", "diff": the names of
// --mode and of the script's `mode` command.
const char* viewModeName(ViewMode mode);
std::optional<ViewMode> parseViewMode(std::string_view name);
// One line for the panel: what the colours mean.
const char* viewModeLegend(ViewMode mode);
// The screen-space baselines the baseline mode shows ("gtao", "hbao", "alchemy"; ssao_settings.h's
// names), and whether `name` is one of them.
std::span<const char* const> viewerBaselines();
bool isViewerBaseline(std::string_view name);

}  // namespace cubeao::viewer
