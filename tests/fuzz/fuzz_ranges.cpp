// The CLI's range arguments: --frames A:B (parseFrameRange, Python-slice rules) and --shard I/N
// (parseBakeShard). Input: a frame count in the first 4 bytes, the text after. cubeao::UsageError or a
// range inside [0, count), never a crash.
#include <cstring>
#include <string>

#include "cubeao/bake/bake_driver.h"
#include "cubeao/core/error.h"
#include "cubeao/scene/camera_path.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    std::uint32_t count = 0;
    if (size >= 4) std::memcpy(&count, data, 4);
    const std::string text(reinterpret_cast<const char*>(data) + (size >= 4 ? 4 : 0), size >= 4 ? size - 4 : 0);
    try {
        const cubeao::FrameRange r = cubeao::parseFrameRange(text, count);
        if (!(r.begin < r.end && r.end <= count)) __builtin_trap();
    } catch (const cubeao::Error&) {
    }
    try {
        const cubeao::BakeShard s = cubeao::parseBakeShard(text);
        if (!(s.index < s.count)) __builtin_trap();
    } catch (const cubeao::Error&) {
    }
    return 0;
}
