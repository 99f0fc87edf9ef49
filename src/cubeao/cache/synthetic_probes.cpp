#include "cubeao/cache/synthetic_probes.h"

#include <random>

#include "cubeao/core/error.h"

namespace cubeao {

std::vector<ProbeRecord> syntheticPayloads(const CacheParams& params, float maxDistance, std::size_t count,
                                           std::uint32_t seed) {
    if (params.depthFormat != DepthFormat::R16Unorm)
        throw Error("synthetic probes: writes r16unorm distances, the bake's default format");
    std::mt19937 rng(seed);
    std::vector<ProbeRecord> out;
    for (std::size_t k = 0; k < count; ++k) {
        ProbeRecord p;
        p.index = std::uint32_t(k);
        p.maxDistance = maxDistance;
        CacheParams bc5 = params;  // made as BC5, then stored in the cache's format (BC4: the AO half)
        bc5.aoFormat = AoFormat::Bc5;
        p.aoConfidence.resize(aoSectionSize(bc5));
        for (std::size_t b = 0; b < p.aoConfidence.size(); b += 16) {
            std::uint8_t* block = p.aoConfidence.data() + b;
            for (int i = 0; i < 8; ++i) block[i] = std::uint8_t(rng());  // AO: random endpoints and codes
            block[8] = 255, block[9] = 255;                              // confidence: 1, as a traced bake's
            for (int i = 10; i < 16; ++i) block[i] = 0;                  // every code 0: endpoint 0
        }
        p.depth.resize(depthSectionSize(params));
        for (std::size_t t = 0; t + 1 < p.depth.size(); t += 2) {  // little-endian r16unorm in [60000, 65535]
            const std::uint16_t v = std::uint16_t(60000 + rng() % 5536);
            p.depth[t] = std::uint8_t(v & 0xff), p.depth[t + 1] = std::uint8_t(v >> 8);
        }
        out.push_back(withAoFormat(std::move(p), params.aoFormat, params.res, params.levels));
    }
    return out;
}

std::vector<ProbeView> syntheticProbeViews(std::span<const glm::vec3> positions,
                                           std::span<const ProbeRecord> payloads) {
    if (payloads.empty() && !positions.empty()) throw Error("synthetic probes: no payloads to share");
    std::vector<ProbeView> out;
    out.reserve(positions.size());
    for (std::size_t i = 0; i < positions.size(); ++i) {
        const ProbeRecord& p = payloads[i % payloads.size()];
        out.push_back({std::uint32_t(i), positions[i], p.maxDistance, p.aoConfidence, p.depth, p.aoFormat});
    }
    return out;
}

}  // namespace cubeao
