// probes.json (src/cubeao/placement/probe_set.h): cubeao::Error or finite probes, never a crash.
#include <cmath>

#include "cubeao/placement/probe_set.h"
#include "cubeao/core/error.h"
#include "fuzz_util.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const auto path = cubeao::fuzz::scratchFile("probes.json", data, size);
    try {
        for (const cubeao::ProbeSpec& p : cubeao::readProbeSet(path))
            if (!std::isfinite(p.position.x + p.position.y + p.position.z)) __builtin_trap();
    } catch (const cubeao::Error&) {
    }
    return 0;
}
