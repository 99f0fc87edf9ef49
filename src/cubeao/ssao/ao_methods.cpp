#include "cubeao/ssao/ao_methods.h"

#include "cubeao/ssao/gtao_fallback.h"
#include "cubeao/ssao/ssao_pass.h"

namespace cubeao {
namespace {

std::unique_ptr<GtaoFallback> gtaoFallback(SsaoSettings ssao) {
    ssao.method = SsaoMethod::Gtao;
    return std::make_unique<GtaoFallback>(ssao);
}

}  // namespace

std::unique_ptr<AoPass> makeAoPass(const SsaoSettings& ssao, const CacheReader* cache,
                                   std::span<const glm::vec3> positions, std::span<const std::uint32_t> indices,
                                   const ProbeProjectionSettings& probes, bool fallback) {
    if (!cache) return std::make_unique<SsaoPass>(ssao);
    auto pass = std::make_unique<ProbeProjectionPass>(*cache, positions, indices, probes);
    if (fallback) pass->setFallback(gtaoFallback(ssao));
    return pass;
}

std::unique_ptr<ProbeProjectionPass> makeEmptyProbePass(const CacheParams& params, const SsaoSettings& ssao,
                                                        std::span<const glm::vec3> positions,
                                                        std::span<const std::uint32_t> indices,
                                                        const ProbeProjectionSettings& probes) {
    auto pass = std::make_unique<ProbeProjectionPass>(params, positions, indices, probes);
    pass->setFallback(gtaoFallback(ssao));
    return pass;
}

}  // namespace cubeao
