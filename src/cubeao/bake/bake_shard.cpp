// --shard I/N, apart from the bake loop in bake_driver.cpp so the parser can be fuzzed on its own
// (tests/fuzz/fuzz_ranges.cpp) without the bake's dependencies.
#include <exception>
#include <string>

#include "cubeao/bake/bake_driver.h"
#include "cubeao/core/error.h"

namespace cubeao {

BakeShard parseBakeShard(const std::string& text) {
    if (text.empty()) return {};
    const auto slash = text.find('/');
    try {
        if (slash != std::string::npos) {
            std::size_t used = 0;
            const long i = std::stol(text.substr(0, slash), &used);
            const bool wholeI = used == slash;
            const long n = std::stol(text.substr(slash + 1), &used);
            if (wholeI && used == text.size() - slash - 1 && n >= 1 && i >= 0 && i < n)
                return {std::size_t(i), std::size_t(n)};
        }
    } catch (const std::exception&) {
    }
    throw UsageError("--shard \"" + text + "\": expected I/N with 0 <= I < N");
}

}  // namespace cubeao
