#include "cubeao/ssao/ssao_settings.h"

#include <cmath>
#include <vector>

#include "cubeao/core/error.h"

namespace cubeao {

SsaoMethod parseSsaoMethod(const std::string& name) {
    if (name == "alchemy") return SsaoMethod::Alchemy;
    if (name == "hbao") return SsaoMethod::Hbao;
    if (name == "gtao") return SsaoMethod::Gtao;
    throw UsageError("--method \"" + name + "\": expected alchemy, hbao or gtao");
}

const char* ssaoMethodName(SsaoMethod m) {
    switch (m) {
        case SsaoMethod::Alchemy: return "alchemy";
        case SsaoMethod::Hbao: return "hbao";
        case SsaoMethod::Gtao: return "gtao";
    }
    return "?";
}

SsaoSettings resolveSsaoSettings(SsaoSettings s, float sceneDefaultRadius) {
    if (s.radius == 0.0f) s.radius = sceneDefaultRadius;
    if (s.directions == 0) s.directions = 8;
    if (s.steps == 0) s.steps = 8;
    if (s.alchemyIntensity == 0.0f) s.alchemyIntensity = 0.8f;
    if (s.alchemyContrast == 0.0f) s.alchemyContrast = 1.0f;
    if (s.alchemyBias == 0.0f) s.alchemyBias = 1e-4f;
    if (s.alchemyEpsilon == 0.0f) s.alchemyEpsilon = 0.01f;

    std::vector<std::string> problems;
    if (!(s.radius > 0.0f) || !std::isfinite(s.radius)) problems.push_back("--radius must be positive");
    if (s.directions < 2 || s.directions > 64 || s.directions % 2 != 0)
        problems.push_back("directions " + std::to_string(s.directions) + ": expected an even number in 2..64");
    if (s.steps < 1 || s.steps > 64) problems.push_back("steps " + std::to_string(s.steps) + ": expected 1..64");
    if (s.maxRadiusPixels < 0.0f) problems.push_back("max radius in pixels must be ≥ 0 (0 = no clamp)");
    if (!(s.alchemyIntensity > 0.0f)) problems.push_back("alchemy intensity σ must be positive");
    if (!(s.alchemyContrast > 0.0f)) problems.push_back("alchemy contrast k must be positive");
    if (!(s.alchemyBias >= 0.0f)) problems.push_back("alchemy bias β must be ≥ 0");
    if (!(s.alchemyEpsilon > 0.0f)) problems.push_back("alchemy ε must be positive");
    if (!problems.empty()) {
        std::string message = "bad screen-space AO settings:";
        for (const auto& p : problems) message += "\n  " + p;
        throw UsageError(message);
    }
    return s;
}

int plannedFetchesPerPixel(const SsaoSettings& s) { return 2 + s.directions * s.steps; }

}  // namespace cubeao
