#include "cubeao/runtime/probe_source.h"

#include <cstring>
#include <span>
#include <string>
#include <utility>

#include "cubeao/cache/depth_cube.h"
#include "cubeao/core/error.h"

namespace cubeao {

ProbeSource::ProbeSource(const CacheReader* cache, const CacheParams& params, std::uint32_t level)
    : cache_(cache), stored_(params), params_(cubeao::levelParams(params, level)), level_(level) {
    if (!cache) return;
    cache->adviseRandomAccess();  // probes are read by priority, each section asked for (prefetch)
    probes_.resize(cache->probeCount());
    for (std::size_t i = 0; i < probes_.size(); ++i) {
        set_.add(cache->position(i));
        probes_[i].maxDistance = cache->maxDistance(i);
    }
}

float ProbeSource::distanceScale(ProbeId id) const {
    return params_.depthFormat == DepthFormat::R16Unorm ? probes_[index(id)].maxDistance : 1.0f;
}

ProbeId ProbeSource::add(ProbeRecord record) {
    if (const CacheParams own = withAoFormat(stored_, record.aoFormat);
        stored_.levels > 1 && record.aoConfidence.size() == aoSectionSize(own) &&
        record.depth.size() == depthSectionSize(own)) {  // every level, as a bake with the cache's settings makes
        const ProbeView level = levelView(viewOf(record), own, level_);
        record.aoConfidence.assign(level.aoConfidence.begin(), level.aoConfidence.end());
        record.depth.assign(level.depth.begin(), level.depth.end());
    }
    if (record.aoFormat != params_.aoFormat &&
        record.aoConfidence.size() == aoSectionSize(withAoFormat(params_, record.aoFormat)))
        record = withAoFormat(std::move(record), params_.aoFormat, params_.res);
    if (record.aoConfidence.size() != aoSectionSize(params_) || record.depth.size() != depthSectionSize(params_))
        throw Error("probe " + std::to_string(record.index) + ": " + std::to_string(record.aoConfidence.size()) +
                    " AO and " + std::to_string(record.depth.size()) + " distance bytes; this probe set needs " +
                    std::to_string(aoSectionSize(params_)) + " and " + std::to_string(depthSectionSize(params_)));
    Probe p;
    p.maxDistance = record.maxDistance;
    const ProbeId id = set_.add(record.position);
    p.added = std::make_unique<ProbeRecord>(std::move(record));
    probes_.push_back(std::move(p));
    return id;
}

void ProbeSource::remove(ProbeId id) {
    set_.remove(id);  // Error for an unknown or removed id
    probes_[index(id)].added.reset();
}

ProbeView ProbeSource::view(ProbeId id) const {
    const Probe& p = probes_[index(id)];
    if (p.added) return viewOf(*p.added);
    return view(id, level_);
}

CacheParams ProbeSource::levelParams(std::uint32_t level) const {
    return level == level_ ? params_ : cubeao::levelParams(stored_, level);
}

ProbeView ProbeSource::view(ProbeId id, std::uint32_t level) const {
    if (probes_[index(id)].added)
        throw Error("probe id " + std::to_string(index(id)) + " was added at run time: it holds level " +
                    std::to_string(level_) + " alone");
    ProbeView v = cache_->probe(index(id));
    if (stored_.levels > 1) v = levelView(v, stored_, level);
    if (v.aoFormat != params_.aoFormat) {
        convertedAo_ = convertAoSection(v.aoConfidence, stored_.res >> level, v.aoFormat, params_.aoFormat);
        v.aoConfidence = convertedAo_;
        v.aoFormat = params_.aoFormat;
    }
    return v;
}

void ProbeSource::prefetch(ProbeId id) const {
    if (!probes_[index(id)].added && cache_) cache_->prefetch(index(id));
}

void ProbeSource::prefetchDepth(ProbeId id) const {
    if (!probes_[index(id)].added && cache_) cache_->prefetchDepth(index(id));
}

void ProbeSource::releaseAll() const {
    if (cache_) cache_->releaseAll();
}

float ProbeSource::distance(ProbeId id, std::size_t texel) const {
    const Probe& p = probes_[index(id)];
    const std::span<const std::uint8_t> bytes =
        p.added ? std::span<const std::uint8_t>(p.added->depth)
                : cache_->unverifiedDepth(index(id)).subspan(depthLevelOffset(stored_, level_));
    const std::uint32_t size = depthBytesPerTexel(params_.depthFormat);
    std::uint32_t stored = 0;
    if (size == 2) {
        std::uint16_t v;
        std::memcpy(&v, bytes.data() + texel * 2, 2);
        stored = v;
    } else {
        std::memcpy(&stored, bytes.data() + texel * 4, 4);
    }
    return depth::decodeTexel(stored, params_.depthFormat, p.maxDistance);
}

}  // namespace cubeao
