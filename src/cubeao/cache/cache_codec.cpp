// The cache's header codec and probe checksum (cache_codec.h), and the public parameter and size
// functions of cache_file.h.
#include <algorithm>
#include <cmath>
#include <string>

#include "cubeao/cache/cache_codec.h"
#include "cubeao/core/error.h"

namespace cubeao {
namespace cache_codec {

std::uint64_t hashProbe(std::span<const std::uint8_t> ao, std::span<const std::uint8_t> depth) {
    HashState s = newHashState();
    XXH3_64bits_update(s.get(), ao.data(), ao.size());
    XXH3_64bits_update(s.get(), depth.data(), depth.size());
    return XXH3_64bits_digest(s.get());
}

std::array<std::uint8_t, kHeaderSize> encodeHeader(const CacheParams& p, std::uint32_t probeCount,
                                                   std::uint64_t payloadSize, std::uint64_t tableChecksum) {
    std::array<std::uint8_t, kHeaderSize> h{};
    const std::uint64_t payloadOffset = kHeaderSize + kEntrySize * probeCount;
    std::memcpy(h.data() + hdr::magic, kMagic.data(), kMagic.size());
    const bool recentred = p.origin != glm::vec3(0.0f);
    // The oldest format that holds the file (cache_file.h).
    put32(&h[hdr::version], p.levels > 1                   ? 5u
                            : p.aoFormat != AoFormat::Bc5 ? 4u
                            : p.denoise != 0              ? 3u
                            : recentred                   ? 2u
                                                          : 1u);
    put32(&h[hdr::headerSize], kHeaderSize);
    put64(&h[hdr::sceneHash], p.sceneHash);
    put32(&h[hdr::res], p.res);
    put32(&h[hdr::depthRes], p.depthRes);
    h[hdr::depthFormat] = std::uint8_t(p.depthFormat);
    h[hdr::estimator] = p.estimator;
    h[hdr::falloff] = p.falloff;
    h[hdr::denoise] = p.denoise;  // reserved (0) before format 3
    put32(&h[hdr::spp], p.spp);
    putF32(&h[hdr::radius], p.radius);
    put32(&h[hdr::seed], p.seed);
    put32(&h[hdr::directions], p.directions);
    put32(&h[hdr::steps], p.steps);
    putF32(&h[hdr::hybridThreshold], p.hybridThreshold);
    put32(&h[hdr::probeCount], probeCount);
    put64(&h[hdr::tableOffset], kHeaderSize);
    put64(&h[hdr::payloadOffset], payloadOffset);
    put64(&h[hdr::payloadSize], payloadSize);
    put64(&h[hdr::fileSize], payloadOffset + payloadSize + kTrailerSize);
    put64(&h[hdr::tableChecksum], tableChecksum);
    if (recentred)
        for (int k = 0; k < 3; ++k) putF32(&h[hdr::origin + 4 * std::size_t(k)], p.origin[k]);
    h[hdr::aoFormat] = std::uint8_t(p.aoFormat);  // reserved (0 = BC5) before format 4
    if (p.levels > 1) h[hdr::levels] = p.levels;  // reserved (0) before format 5
    put64(&h[hdr::headerChecksum], XXH3_64bits(h.data(), hdr::headerChecksum));
    return h;
}

CacheParams decodeParams(const std::uint8_t* h, std::uint32_t version) {
    CacheParams p;
    if (version >= 2)
        for (int k = 0; k < 3; ++k) p.origin[k] = getF32(h + hdr::origin + 4 * std::size_t(k));
    p.sceneHash = get64(h + hdr::sceneHash);
    p.res = get32(h + hdr::res);
    p.depthRes = get32(h + hdr::depthRes);
    p.depthFormat = DepthFormat(h[hdr::depthFormat]);
    p.estimator = h[hdr::estimator];
    p.falloff = h[hdr::falloff];
    if (version >= 3) p.denoise = h[hdr::denoise];
    if (version >= 4) p.aoFormat = AoFormat(h[hdr::aoFormat]);
    if (version >= 5) p.levels = h[hdr::levels];
    p.spp = get32(h + hdr::spp);
    p.radius = getF32(h + hdr::radius);
    p.seed = get32(h + hdr::seed);
    p.directions = get32(h + hdr::directions);
    p.steps = get32(h + hdr::steps);
    p.hybridThreshold = getF32(h + hdr::hybridThreshold);
    return p;
}

}  // namespace cache_codec

using namespace cache_codec;

// ---- parameters and sizes -----------------------------------------------------------------------------

std::uint32_t depthBytesPerTexel(DepthFormat f) {
    switch (f) {
        case DepthFormat::R16Unorm: return 2;
        case DepthFormat::R16Float: return 2;
        case DepthFormat::R32Float: return 4;
    }
    return 0;
}

const char* depthFormatName(DepthFormat f) {
    switch (f) {
        case DepthFormat::R16Unorm: return "r16unorm";
        case DepthFormat::R16Float: return "r16float";
        case DepthFormat::R32Float: return "r32float";
    }
    return "?";
}

std::uint32_t aoBlockBytes(AoFormat f) {
    switch (f) {
        case AoFormat::Bc5: return 16;
        case AoFormat::Bc4: return 8;
    }
    return 0;
}

const char* aoFormatName(AoFormat f) {
    switch (f) {
        case AoFormat::Bc5: return "bc5";
        case AoFormat::Bc4: return "bc4";
    }
    return "?";
}

AoFormat parseAoFormat(const std::string& name, const std::string& option) {
    if (name == "bc5") return AoFormat::Bc5;
    if (name == "bc4") return AoFormat::Bc4;
    throw UsageError(option + " \"" + name + "\": expected bc5 (AO + confidence) or bc4 (AO alone, traced caches)");
}

constexpr std::uint8_t kTracedEstimator = 2;  // Estimator::Traced (bake_settings.h), which the cache numbers alike

AoFormat defaultAoFormat(std::uint8_t estimator) {
    return estimator == kTracedEstimator ? AoFormat::Bc4 : AoFormat::Bc5;
}

std::vector<std::uint8_t> convertAoSection(std::span<const std::uint8_t> section, std::uint32_t res, AoFormat from,
                                           AoFormat to, std::uint32_t levels) {
    CacheParams p;  // the chain's block count: every level is whole blocks of either format
    p.res = res, p.levels = std::uint8_t(std::min(levels, 255u)), p.aoFormat = from;
    const bool valid = aoBlockBytes(from) != 0 && aoBlockBytes(to) != 0 && levels >= 1 &&
                       levels <= kMaxCacheLevels && res % (4u << (levels - 1)) == 0;
    if (!valid || section.size() != aoSectionSize(p))
        throw Error("AO section of " + std::to_string(section.size()) + " bytes is not " + aoFormatName(from) +
                    " at res " + std::to_string(res) +
                    (levels == 1 ? "" : " with " + std::to_string(levels) + " levels"));
    if (from == to) return {section.begin(), section.end()};
    const std::uint64_t blocks = section.size() / aoBlockBytes(from);
    // Confidence 1 in every texel: red_0 = 255 > red_1 = 254, every 3-bit code 0 (= red_0), the block
    // the encoder makes of sixteen ones (cache/bc4.h), so a traced bake's BC5 blocks come back exactly.
    constexpr std::array<std::uint8_t, 8> kGreenOne{255, 254, 0, 0, 0, 0, 0, 0};
    std::vector<std::uint8_t> out(blocks * aoBlockBytes(to));
    for (std::uint64_t b = 0; b < blocks; ++b) {
        if (to == AoFormat::Bc4) {
            std::memcpy(&out[8 * b], &section[16 * b], 8);  // the red half
        } else {
            std::memcpy(&out[16 * b], &section[8 * b], 8);
            std::memcpy(&out[16 * b + 8], kGreenOne.data(), 8);
        }
    }
    return out;
}

ProbeRecord withAoFormat(ProbeRecord r, AoFormat to, std::uint32_t res, std::uint32_t levels) {
    if (r.aoFormat == to) return r;
    r.aoConfidence = convertAoSection(r.aoConfidence, res, r.aoFormat, to, levels);
    r.aoFormat = to;
    return r;
}

CacheParams withAoFormat(CacheParams p, AoFormat to) {
    p.aoFormat = to;
    return p;
}

std::vector<std::string> cacheParamProblems(const CacheParams& p) {
    std::vector<std::string> problems;
    if (p.res < 4 || p.res > kMaxRes || p.res % 4 != 0)
        problems.push_back("res " + std::to_string(p.res) + " is not a multiple of 4 in 4..16384");
    if (p.depthRes < 1 || p.depthRes > kMaxRes)
        problems.push_back("depthRes " + std::to_string(p.depthRes) + " is not in 1..16384");
    if (depthBytesPerTexel(p.depthFormat) == 0)
        problems.push_back("depth format " + std::to_string(unsigned(p.depthFormat)) +
                           " is not r16unorm (1), r16float (2) or r32float (3)");
    if (p.estimator > 3)
        problems.push_back("estimator " + std::to_string(p.estimator) +
                           " is not hsplit (0), gtao (1), traced (2) or hybrid (3)");
    if (p.falloff > 1) problems.push_back("falloff " + std::to_string(p.falloff) + " is not none (0) or smooth (1)");
    if (p.denoise > kMaxCacheDenoise)
        problems.push_back("denoise " + std::to_string(p.denoise) + " is not in 0.." + std::to_string(kMaxCacheDenoise));
    if (!(std::isfinite(p.radius) && p.radius > 0.0f))
        problems.push_back("radius " + fmtFloat(p.radius) + " is not finite and > 0");
    if (!std::isfinite(p.hybridThreshold))
        problems.push_back("hybrid threshold " + fmtFloat(p.hybridThreshold) + " is not finite");
    if (!std::isfinite(p.origin.x) || !std::isfinite(p.origin.y) || !std::isfinite(p.origin.z))
        problems.push_back("origin " + fmtVec(p.origin) + " is not finite");
    if (aoBlockBytes(p.aoFormat) == 0)
        problems.push_back("ao format " + std::to_string(unsigned(p.aoFormat)) + " is not bc5 (0) or bc4 (1)");
    else if (p.aoFormat == AoFormat::Bc4 && p.estimator != kTracedEstimator)
        problems.push_back("ao format bc4 holds no confidence: only traced caches (estimator 2) use it, not estimator " +
                           std::to_string(p.estimator));
    if (p.levels < 1 || p.levels > kMaxCacheLevels)
        problems.push_back("levels " + std::to_string(p.levels) + " is not in 1.." + std::to_string(kMaxCacheLevels));
    else if (p.levels > 1 && (p.res % (4u << (p.levels - 1)) != 0 || p.depthRes % (1u << (p.levels - 1)) != 0))
        problems.push_back(std::to_string(p.levels) + " levels need res a multiple of " +
                           std::to_string(4u << (p.levels - 1)) + " and depthRes of " +
                           std::to_string(1u << (p.levels - 1)) + " (res " + std::to_string(p.res) + ", depthRes " +
                           std::to_string(p.depthRes) + ")");
    return problems;
}

std::vector<std::string> cacheParamDifferences(const CacheParams& a, const CacheParams& b) {
    std::vector<std::string> d;
    auto num = [&d](const char* name, auto x, auto y) {
        if (x != y) d.push_back(std::string(name) + " " + std::to_string(x) + " vs " + std::to_string(y));
    };
    if (a.sceneHash != b.sceneHash) d.push_back("scene hash " + hex64(a.sceneHash) + " vs " + hex64(b.sceneHash));
    num("res", a.res, b.res);
    num("depthRes", a.depthRes, b.depthRes);
    if (a.depthFormat != b.depthFormat)
        d.push_back(std::string("depth format ") + depthFormatName(a.depthFormat) + " vs " +
                    depthFormatName(b.depthFormat));
    num("estimator", unsigned(a.estimator), unsigned(b.estimator));
    num("falloff", unsigned(a.falloff), unsigned(b.falloff));
    num("denoise", unsigned(a.denoise), unsigned(b.denoise));
    num("spp", a.spp, b.spp);
    if (a.radius != b.radius) d.push_back("radius " + fmtFloat(a.radius) + " vs " + fmtFloat(b.radius));
    num("seed", a.seed, b.seed);
    num("directions", a.directions, b.directions);
    num("steps", a.steps, b.steps);
    if (a.hybridThreshold != b.hybridThreshold)
        d.push_back("hybrid threshold " + fmtFloat(a.hybridThreshold) + " vs " + fmtFloat(b.hybridThreshold));
    if (a.origin != b.origin) d.push_back("origin " + fmtVec(a.origin) + " vs " + fmtVec(b.origin));
    if (a.aoFormat != b.aoFormat)
        d.push_back(std::string("ao format ") + aoFormatName(a.aoFormat) + " vs " + aoFormatName(b.aoFormat));
    num("levels", unsigned(a.levels), unsigned(b.levels));
    return d;
}

namespace {

// Level k's own section sizes (levelParams without its checks).
std::uint64_t aoLevelSize(const CacheParams& p, std::uint32_t k) {
    const std::uint64_t side = (p.res >> k) / 4;
    return kFaces * side * side * aoBlockBytes(p.aoFormat);  // one block per 4×4 texels
}
std::uint64_t depthLevelSize(const CacheParams& p, std::uint32_t k) {
    const std::uint64_t side = p.depthRes >> k;
    return kFaces * side * side * depthBytesPerTexel(p.depthFormat);
}
std::uint32_t levelCount(const CacheParams& p) { return std::clamp<std::uint32_t>(p.levels, 1, kMaxCacheLevels); }

}  // namespace

std::uint64_t aoSectionSize(const CacheParams& p) {
    std::uint64_t bytes = 0;
    for (std::uint32_t k = 0; k < levelCount(p); ++k) bytes += aoLevelSize(p, k);
    return bytes;
}

std::uint64_t depthSectionSize(const CacheParams& p) {
    std::uint64_t bytes = 0;
    for (std::uint32_t k = 0; k < levelCount(p); ++k) bytes += depthLevelSize(p, k);
    return bytes;
}

std::uint32_t maxLevels(std::uint32_t res, std::uint32_t depthRes) {
    std::uint32_t levels = 1;
    while (levels < kMaxCacheLevels && (res >> levels) >= kMinLevelRes && res % (4u << levels) == 0 &&
           depthRes % (1u << levels) == 0)
        ++levels;
    return levels;
}

CacheParams levelParams(const CacheParams& p, std::uint32_t level) {
    if (level >= levelCount(p))
        throw Error("level " + std::to_string(level) + " of a cache of " + std::to_string(levelCount(p)) +
                    (levelCount(p) == 1 ? " level" : " levels") + " (levels are 0.." +
                    std::to_string(levelCount(p) - 1) + ")");
    CacheParams l = p;
    l.res = p.res >> level, l.depthRes = p.depthRes >> level, l.levels = 1;
    return l;
}

std::uint64_t cacheFileSize(const CacheParams& p, std::uint64_t probes) {
    return kHeaderSize + probes * (kEntrySize + alignUp(aoSectionSize(p) + depthSectionSize(p))) + kTrailerSize;
}

ProbeView viewOf(const ProbeRecord& r) {
    return {r.index, r.position, r.maxDistance, r.aoConfidence, r.depth, r.aoFormat};
}

std::uint64_t depthLevelOffset(const CacheParams& p, std::uint32_t level) {
    std::uint64_t offset = 0;
    for (std::uint32_t k = 0; k < level; ++k) offset += depthLevelSize(p, k);
    return offset;
}

ProbeView levelView(const ProbeView& v, const CacheParams& p, std::uint32_t level) {
    levelParams(p, level);  // checks the level
    const CacheParams own = withAoFormat(p, v.aoFormat);
    std::uint64_t ao = 0;
    for (std::uint32_t k = 0; k < level; ++k) ao += aoLevelSize(own, k);
    const std::uint64_t depth = depthLevelOffset(p, level);
    const std::uint64_t aoSize = aoLevelSize(own, level), depthSize = depthLevelSize(own, level);
    if (ao + aoSize > v.aoConfidence.size() || depth + depthSize > v.depth.size())
        throw Error("probe " + std::to_string(v.index) + ": sections of " + std::to_string(v.aoConfidence.size()) +
                    " and " + std::to_string(v.depth.size()) + " bytes hold no level " + std::to_string(level));
    ProbeView l = v;
    l.aoConfidence = v.aoConfidence.subspan(ao, aoSize);
    l.depth = v.depth.subspan(depth, depthSize);
    return l;
}

}  // namespace cubeao
