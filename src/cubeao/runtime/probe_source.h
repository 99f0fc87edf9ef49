// Where the run's probes and their bytes are: a mapped cache (pages prefetched before an upload and
// released after it, so the RSS does not grow with the cache) and probes added at run time. No GL: the
// atlas (probe_atlas.h) uploads from it, the candidate grid reads its distances.
#pragma once

#include <cstddef>
#include <algorithm>
#include <cstdint>
#include <memory>
#include <vector>

#include <glm/vec3.hpp>

#include "cubeao/cache/cache_file.h"
#include "cubeao/runtime/probe_id.h"
#include "cubeao/runtime/probe_set.h"

namespace cubeao {

// Probes by id and their bytes: the cache's probes first (id = cache order), then those added at run
// time. Removed probes keep their id. Which are live, and where each is, is the ProbeSet it holds.
class ProbeSource {
public:
    // cache may be null: start empty. `params` are the cache's, except that the AO format may differ
    // (a viewer holds a BC4 cache as BC5 so live placement's probes, which carry confidence, can join):
    // then view() converts each cache probe's AO (convertAoSection). The source serves level `level`
    // of every probe (a cache with levels of detail; Error for a level it lacks): params() are that
    // level's (levelParams: one level), and added probes must have its sizes.
    ProbeSource(const CacheReader* cache, const CacheParams& params, std::uint32_t level = 0);

    const CacheParams& params() const { return params_; }  // of the level served: one level
    std::uint32_t level() const { return level_; }
    const ProbeSet& probes() const { return set_; }
    std::size_t size() const { return set_.size(); }
    bool isLive(ProbeId id) const { return set_.isLive(id); }
    glm::vec3 position(ProbeId id) const { return set_.position(id); }
    // Multiplies a stored distance texel into world units on the GPU (r16unorm: maxDistance; floats: 1).
    float distanceScale(ProbeId id) const;

    // A record with the sections of the level served or of every level of the cache (kept: the level
    // served) (Error otherwise, naming them), its AO converted to params().aoFormat when it is in the
    // other one; returns its id.
    ProbeId add(ProbeRecord record);
    void remove(ProbeId id);  // Error for an unknown or removed id

    // The stored bytes in params().aoFormat (a cache probe's checksum is checked on first use). A
    // cache probe converted to another AO format points into a buffer of this source, valid until the
    // next view().
    ProbeView view(ProbeId id) const;
    // Levels of detail the cache's probes have (1 without a cache or levels), and a cache probe at
    // another of them, in params().aoFormat (the same rules as view(); Error for an added probe, which
    // holds its one level).
    std::uint32_t storedLevels() const {
        return cache_ ? std::uint32_t(std::max<std::uint8_t>(stored_.levels, 1)) : 1u;
    }
    CacheParams levelParams(std::uint32_t level) const;
    ProbeView view(ProbeId id, std::uint32_t level) const;
    void prefetch(ProbeId id) const;       // page hint for a cache probe; nothing for added ones
    void prefetchDepth(ProbeId id) const;  // the same for its distance section alone
    void releaseAll() const;  // every cache page (CacheReader::releaseAll)
    // Distance-cube texel `texel` (cube::texelIndex order, depthRes faces) in world units, read from
    // the stored bytes: what the candidate grid's visibility test needs, without a decoded copy. A
    // cache probe's checksum is not checked here (CacheReader::unverifiedDepth): building the grid
    // then reads the distance sections alone, not the whole file; view() checks it before upload.
    float distance(ProbeId id, std::size_t texel) const;

private:
    struct Probe {
        float maxDistance = 0.0f;
        std::unique_ptr<ProbeRecord> added;  // null: cache probe `id`
    };
    const CacheReader* cache_ = nullptr;
    CacheParams stored_;  // the cache's (in params_'s AO format), every level
    CacheParams params_;
    std::uint32_t level_ = 0;
    ProbeSet set_;
    std::vector<Probe> probes_;  // by id, beside set_
    mutable std::vector<std::uint8_t> convertedAo_;  // view()'s AO of a cache probe in another format
};

}  // namespace cubeao
