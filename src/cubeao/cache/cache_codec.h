// The .cubeao file's layout and the helpers its writer, reader and merge share: offsets, little-endian
// encoding, checksums, the header codec. Private to cubeao_cache (not installed); docs/FORMAT.md is the
// byte-level contract and the tables below are its tables.
#pragma once

#include <xxhash.h>

#include <array>
#include <bit>
#include <cerrno>
#include <cinttypes>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <functional>
#include <memory>
#include <new>
#include <span>
#include <string>
#include <vector>

#include "cubeao/cache/cache_file.h"

namespace cubeao::cache_codec {

// ---- layout (docs/FORMAT.md) ----------------------------------------------------------------------
constexpr std::array<std::uint8_t, 8> kMagic{0x89, 'C', 'U', 'B', 'E', 'A', 'O', '\n'};
constexpr std::uint64_t kHeaderSize = 128;
constexpr std::uint64_t kEntrySize = 64;
constexpr std::uint64_t kTrailerSize = 8;
constexpr std::uint32_t kMaxRes = 16384;
constexpr int kFaces = 6;

namespace hdr {  // byte offsets in the header
constexpr std::size_t magic = 0, version = 8, headerSize = 12, sceneHash = 16, res = 24, depthRes = 28,
                      depthFormat = 32, estimator = 33, falloff = 34, reserved0 = 35, denoise = 35, spp = 36, radius = 40,
                      seed = 44, directions = 48, steps = 52, hybridThreshold = 56, probeCount = 60,
                      tableOffset = 64, payloadOffset = 72, payloadSize = 80, fileSize = 88, tableChecksum = 96,
                      reserved1 = 104, origin = 104, reserved2 = 116, aoFormat = 116, reserved3 = 117, levels = 117,
                      reserved4 = 118, headerChecksum = 120;  // origin: format 2; aoFormat: 4; levels: 5
}  // namespace hdr
namespace ent {  // byte offsets in a probe table entry
constexpr std::size_t position = 0, maxDistance = 12, aoOffset = 16, aoSize = 24, depthOffset = 32, depthSize = 40,
                      checksum = 48, index = 56, reserved = 60;
}  // namespace ent

// ---- little-endian encoding, independent of the host's byte order -----------------------------------
inline void put32(std::uint8_t* p, std::uint32_t v) {
    for (int i = 0; i < 4; ++i) p[i] = std::uint8_t(v >> (8 * i));
}
inline void put64(std::uint8_t* p, std::uint64_t v) {
    for (int i = 0; i < 8; ++i) p[i] = std::uint8_t(v >> (8 * i));
}
inline void putF32(std::uint8_t* p, float v) { put32(p, std::bit_cast<std::uint32_t>(v)); }
inline std::uint32_t get32(const std::uint8_t* p) {
    std::uint32_t v = 0;
    for (int i = 0; i < 4; ++i) v |= std::uint32_t(p[i]) << (8 * i);
    return v;
}
inline std::uint64_t get64(const std::uint8_t* p) {
    std::uint64_t v = 0;
    for (int i = 0; i < 8; ++i) v |= std::uint64_t(p[i]) << (8 * i);
    return v;
}
inline float getF32(const std::uint8_t* p) { return std::bit_cast<float>(get32(p)); }

inline std::uint64_t alignUp(std::uint64_t v) {
    return (v + kCacheSectionAlignment - 1) / kCacheSectionAlignment * kCacheSectionAlignment;
}

// Same spelling as hashToString (scene.h), which lives in cubeao_offline.
inline std::string hex64(std::uint64_t v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "0x%016" PRIx64, v);
    return buf;
}
inline std::string hexBytes(const std::uint8_t* p, std::size_t n) {
    std::string s;
    char buf[4];
    for (std::size_t i = 0; i < n; ++i) {
        std::snprintf(buf, sizeof buf, i ? " %02X" : "%02X", unsigned(p[i]));
        s += buf;
    }
    return s;
}
inline std::string fmtFloat(float v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.9g", double(v));
    return buf;
}
inline std::string fmtVec(const glm::vec3& v) {
    char buf[96];
    std::snprintf(buf, sizeof buf, "(%.9g, %.9g, %.9g)", double(v.x), double(v.y), double(v.z));
    return buf;
}
inline std::string join(const std::vector<std::string>& parts, const char* sep) {
    std::string s;
    for (const auto& p : parts) s += (s.empty() ? "" : sep) + p;
    return s;
}
inline std::string probeName(std::size_t i) { return "probe " + std::to_string(i); }
inline std::string systemError() { return std::strerror(errno); }

using HashState = std::unique_ptr<XXH3_state_t, decltype(&XXH3_freeState)>;
inline HashState newHashState() {
    HashState s(XXH3_createState(), &XXH3_freeState);
    if (!s || XXH3_64bits_reset(s.get()) != XXH_OK) throw std::bad_alloc();
    return s;
}

// Calls `release` after every WriteOptions::kReleaseBytes of mapped bytes read: copying or checking a
// cache of any size then keeps about that much of it resident (CacheReader::releaseAll drops the pages).
class ReleasePacer {
public:
    explicit ReleasePacer(std::function<void()> release) : release_(std::move(release)) {}
    void read(std::uint64_t bytes) {
        unreleased_ += bytes;
        if (unreleased_ < WriteOptions::kReleaseBytes || !release_) return;
        release_();
        unreleased_ = 0;
    }

private:
    std::function<void()> release_;
    std::uint64_t unreleased_ = 0;
};

// Probe checksum: XXH3-64 of the AO section's bytes followed by the depth section's bytes.
std::uint64_t hashProbe(std::span<const std::uint8_t> ao, std::span<const std::uint8_t> depth);

// The header of a file of `probeCount` probes with `payloadSize` payload bytes and the probe table's
// checksum; its own checksum last.
std::array<std::uint8_t, kHeaderSize> encodeHeader(const CacheParams& p, std::uint32_t probeCount,
                                                   std::uint64_t payloadSize, std::uint64_t tableChecksum);
// The parameters of a header of format `version` (fields a version lacks keep their defaults).
CacheParams decodeParams(const std::uint8_t* h, std::uint32_t version);

using PositionKey = std::array<std::uint32_t, 3>;
inline PositionKey positionKey(const glm::vec3& p) {
    return {std::bit_cast<std::uint32_t>(p.x), std::bit_cast<std::uint32_t>(p.y), std::bit_cast<std::uint32_t>(p.z)};
}

}  // namespace cubeao::cache_codec
