// The probes of a run by id: where each is and whether it is still part of the run. Ids come in the
// order the probes came (a cache's in cache order, then those added while walking); a removed probe
// keeps its id and is never live again. The one record of liveness: the source of the probes' bytes
// (probe_source.h ProbeSource) holds it, and the candidate grid, the ranking and the atlas read it.
// Pure (no GL).
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "cubeao/core/error.h"
#include "cubeao/runtime/probe_id.h"

namespace cubeao {

class ProbeSet {
public:
    ProbeSet() = default;
    // Probes 0 … n − 1 at `positions`, all live.
    explicit ProbeSet(std::span<const glm::vec3> positions) {
        probes_.reserve(positions.size());
        for (const glm::vec3& p : positions) add(p);
    }

    // A live probe with the next id, size() before the call.
    ProbeId add(const glm::vec3& position) {
        probes_.push_back({position, true});
        ++liveCount_;
        return ProbeId{std::uint32_t(probes_.size() - 1)};
    }
    // Error for an unknown or already removed id.
    void remove(ProbeId id) {
        if (!isLive(id)) throw Error("no live probe with id " + std::to_string(index(id)));
        probes_[index(id)].live = false;
        --liveCount_;
    }

    std::size_t size() const { return probes_.size(); }  // ids issued, removed ones included
    std::size_t liveCount() const { return liveCount_; }
    bool isLive(ProbeId id) const { return index(id) < probes_.size() && probes_[index(id)].live; }
    const glm::vec3& position(ProbeId id) const { return probes_[index(id)].position; }

private:
    struct Probe {
        glm::vec3 position{0.0f};
        bool live = true;
    };
    std::vector<Probe> probes_;
    std::size_t liveCount_ = 0;
};

}  // namespace cubeao
