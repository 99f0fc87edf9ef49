// The bake parameters a cache records (cache/cache_file.h CacheParams), as JSON: `info CACHE --json`
// and `export`'s manifest.json print the same fields under the same names.
#pragma once

#include <nlohmann/json.hpp>

#include "cubeao/bake/bake_settings.h"
#include "cubeao/cache/cache_file.h"
#include "cubeao/core/falloff.h"

namespace cubeao::cli {

// Json: nlohmann::json (sorted keys) or nlohmann::ordered_json (this order).
template <typename Json = nlohmann::json>
Json bakeParamsJson(const CacheParams& p) {
    return Json{{"estimator", estimatorName(Estimator(p.estimator))},
                {"falloff", falloffName(Falloff(p.falloff))},
                {"radius", p.radius},
                {"spp", p.spp},
                {"seed", p.seed},
                {"directions", p.directions},
                {"steps", p.steps},
                {"hybrid_threshold", p.hybridThreshold},
                {"denoise", p.denoise},
                {"res", p.res},
                {"depth_res", p.depthRes},
                {"depth_format", depthFormatName(p.depthFormat)},
                {"ao_format", aoFormatName(p.aoFormat)},
                {"levels", p.levels}};
}

}  // namespace cubeao::cli
