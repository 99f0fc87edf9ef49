// GoogleTest output for the run time's typed ids (runtime/probe_id.h): "probe 3", "slot 1", "none".
#pragma once

#include <ostream>

#include "cubeao/runtime/probe_id.h"

namespace cubeao {

inline void PrintTo(ProbeId id, std::ostream* os) {
    if (id == ProbeId::None)
        *os << "no probe";
    else
        *os << "probe " << index(id);
}
inline void PrintTo(SlotId slot, std::ostream* os) {
    if (slot == SlotId::None)
        *os << "no slot";
    else
        *os << "slot " << index(slot);
}

}  // namespace cubeao
