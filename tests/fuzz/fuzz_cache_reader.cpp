// The .cubeao reader (src/cubeao/cache/cache_file.h) on arbitrary bytes: opening, verifying every
// checksum and reading every probe must end in cubeao::Error or success, never a crash, a read out of
// bounds or undefined behaviour (ASan + UBSan).
#include "cubeao/cache/cache_file.h"
#include "cubeao/core/error.h"
#include "fuzz_util.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const auto path = cubeao::fuzz::scratchFile("input.cubeao", data, size);
    try {
        cubeao::CacheReader reader(path);
        std::size_t bytes = 0;
        for (std::size_t i = 0; i < reader.probeCount(); ++i) {
            const cubeao::ProbeView p = reader.probe(i);
            for (std::uint8_t b : p.aoConfidence) bytes += b;
            for (std::uint8_t b : p.depth) bytes += b;
        }
        reader.verifyAll();
        (void)bytes;
    } catch (const cubeao::Error&) {
    }
    return 0;
}
