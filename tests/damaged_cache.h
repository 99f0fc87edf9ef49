// A copy of a cache with one byte of some probes' AO sections flipped (their checksums then fail):
// the run-time's and the viewer's damaged-probe tests. The byte is found by the probe's stored bytes,
// not by the format's layout: the first 64-byte run of its AO that occurs once in the file (flat AO
// makes equal blocks, in other probes too).
#pragma once

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include "cubeao/cache/cache_file.h"

namespace cubeao::test {

inline void writeWithDamagedAo(const std::filesystem::path& from, std::span<const std::size_t> probes,
                               const std::filesystem::path& to) {
    const CacheReader cache(from);
    std::ifstream in(from, std::ios::binary);
    std::vector<char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const auto same = [](char a, std::uint8_t b) { return std::uint8_t(a) == b; };
    for (const std::size_t i : probes) {
        const std::vector<std::uint8_t> ao = cache.copyProbe(i).aoConfidence;
        std::size_t at = bytes.size();
        for (std::size_t o = 0; o + 64 <= ao.size() && at == bytes.size(); o += 16) {
            const auto first = std::search(bytes.begin(), bytes.end(), ao.begin() + o, ao.begin() + o + 64, same);
            if (std::search(first + 1, bytes.end(), ao.begin() + o, ao.begin() + o + 64, same) == bytes.end())
                at = std::size_t(first - bytes.begin());
        }
        if (at == bytes.size()) throw std::runtime_error("probe " + std::to_string(i) + ": no run of its AO bytes is unique");
        bytes[at] ^= 0x20;
    }
    std::ofstream(to, std::ios::binary).write(bytes.data(), std::streamsize(bytes.size()));
}

}  // namespace cubeao::test
