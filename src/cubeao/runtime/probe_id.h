// The run time's two kinds of index as types of their own, so that one cannot be passed for the other:
// a probe's id (its place in the ProbeSource: the cache's probes in cache order, then those added at
// run time; a removed probe keeps its id) and an atlas slot (ResidencyPlanner). Both are the uint32 the
// kernels see; None is kernel::kNoProbe and kernel::kNoSlot. ProbeId{i} makes one, index() reads it.
#pragma once

#include <cstdint>

namespace cubeao {

enum class ProbeId : std::uint32_t { None = 0xffffffffu };
enum class SlotId : std::uint32_t { None = 0xffffffffu };

constexpr std::uint32_t index(ProbeId id) { return std::uint32_t(id); }
constexpr std::uint32_t index(SlotId slot) { return std::uint32_t(slot); }

}  // namespace cubeao
