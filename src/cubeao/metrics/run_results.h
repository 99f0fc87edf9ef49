// A render/compare run as tools/demo.sh and tools/walks.sh write it, read back for `cubeao report`:
//   DIR/info.json, probes.json, reference.json, reference/ao_NNNN.exr,
//   DIR/compare-METHOD.json with DIR/render-METHOD/ao_NNNN.exr (and render-METHOD.json when written),
//   DIR/bake-ESTIMATOR.json and bake-ESTIMATOR-info.json.
// loadRun checks the layout and reads the JSON (cheap, so every run of a report is checked before any
// work); measureFrames reads the EXRs for the per-frame figures and the frames shown as pictures.
#pragma once

#include <cstddef>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "cubeao/core/image.h"

namespace cubeao {

struct RunMethod {
    std::string name;                        // METHOD of compare-METHOD.json: probes, probes-hsplit, gtao, …
    nlohmann::json compare, render;          // render: null when render-NAME.json is absent
    std::filesystem::path dir;               // DIR/render-NAME
    std::vector<double> mae, flicker;        // per frame of RunResults::frames (measureFrames); flicker NaN first
};

struct RunFrame {
    std::string name;  // ao_NNNN.exr
    int number = 0;    // the camera path's frame
};

struct RunResults {
    std::filesystem::path dir;
    nlohmann::json info, probes, reference;
    std::vector<std::pair<std::string, nlohmann::json>> bakes, caches;  // estimator -> bake-E.json, bake-E-info.json
    std::vector<RunMethod> methods;          // probes methods first, then gtao, hbao, alchemy, then others by name
    std::vector<RunFrame> frames;
    std::vector<std::size_t> picked;         // positions in `frames` shown as pictures
    // The pictures (measureFrames): [picked frame][0 = reference, 1 + k = method k].
    std::vector<std::vector<Image>> pictures;
};

// "probes" and "probes-*": the cache's methods, not screen-space baselines.
bool isProbesMethod(const std::string& name);

// "N,M,..." (--frames): frame numbers; throws cubeao::UsageError for anything else.
std::vector<int> parseFrameList(const std::string& spec);

// The run in `dir` with the frames `wantFrames` picked (empty: first, middle, last). Throws
// cubeao::Error naming the missing or unreadable file, or a wanted frame the run does not have.
RunResults loadRun(const std::filesystem::path& dir, const std::vector<int>& wantFrames);

// Per-frame MAE (from compare-*.json when it has it, else from the EXRs) and flicker (never in
// compare-*.json: it keeps the sequence's mean only), and the picked frames' images, in one pass over
// the EXRs of each method. Throws cubeao::Error for a frame of another size than the reference's.
void measureFrames(RunResults& run);

// The lowest `metric` ("mae", "flicker", …) of compare-*.json among the screen-space baselines; null
// when there is none with that figure.
const RunMethod* bestBaseline(const RunResults& run, const char* metric);

// Reading the runs' JSON leniently: a number (NaN when absent, null or not a number: psnr of identical
// images is null), a string (`fallback` when absent), a member object (empty when absent).
double jsonNumber(const nlohmann::json& j, const char* key);
std::string jsonString(const nlohmann::json& j, const char* key, const std::string& fallback = "");
nlohmann::json jsonObject(const nlohmann::json& j, const char* key);

}  // namespace cubeao
