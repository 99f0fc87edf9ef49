#include "cubeao-view/view_mode.h"

#include <array>

namespace cubeao::viewer {
namespace {

constexpr std::array<ViewMode, 8> kModes = {ViewMode::Shaded,     ViewMode::Ao,         ViewMode::ProbeId,
                                            ViewMode::Footprint,  ViewMode::Confidence, ViewMode::Path,
                                            ViewMode::Baseline,   ViewMode::ReferenceDiff};

}  // namespace

std::span<const ViewMode> allViewModes() { return kModes; }

const char* viewModeName(ViewMode mode) {
    switch (mode) {
        case ViewMode::Shaded: return "shaded";
        case ViewMode::Ao: return "ao";
        case ViewMode::ProbeId: return "probe";
        case ViewMode::Footprint: return "footprint";
        case ViewMode::Confidence: return "confidence";
        case ViewMode::Path: return "path";
        case ViewMode::Baseline: return "baseline";
        case ViewMode::ReferenceDiff: return "diff";
    }
    return "?";
}

std::optional<ViewMode> parseViewMode(std::string_view name) {
    for (ViewMode mode : kModes)
        if (name == viewModeName(mode)) return mode;
    return std::nullopt;
}

std::span<const char* const> viewerBaselines() {
    static constexpr const char* kBaselines[] = {"gtao", "hbao", "alchemy"};
    return kBaselines;
}

bool isViewerBaseline(std::string_view name) {
    for (const char* b : viewerBaselines())
        if (name == b) return true;
    return false;
}

const char* viewModeLegend(ViewMode mode) {
    switch (mode) {
        case ViewMode::Shaded: return "the composite: diffuse light times AO";
        case ViewMode::Ao: return "ambient occlusion: black = occluded, white = open";
        case ViewMode::ProbeId:
            return "one colour per probe (the one weighted most), shaded by AO; grey = no probe sees it";
        case ViewMode::Footprint:
            return "probe texel size: purple = fine (1/8 of scale), teal = at scale, yellow = coarse (8x); grey = none";
        case ViewMode::Confidence: return "probe confidence: blue = 0, pink = 0.5, yellow = 1; grey = no probe";
        case ViewMode::Path:
            return "grey = probe, amber = fallback probe (better one not loaded, or a nearby resident one), "
                   "magenta = screen space, blue = sky";
        case ViewMode::Baseline: return "screen-space baseline AO: black = occluded, white = open";
        case ViewMode::ReferenceDiff:
            return "AO - reference: blue = darker, white = equal, red = brighter (full at 0.25)";
    }
    return "";
}

}  // namespace cubeao::viewer
