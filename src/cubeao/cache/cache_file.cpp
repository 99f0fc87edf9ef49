// The .cubeao cache file: encoding, the atomic writer, the mmap reader and its checks, append and
// merge. docs/FORMAT.md is the byte-level contract; the offsets below are its tables.
#include "cubeao/cache/cache_file.h"

#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>
#include <xxhash.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cerrno>
#include <cinttypes>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <map>
#include <utility>

#include "cubeao/core/durable_file.h"
#include "cubeao/core/error.h"
#include "cubeao/core/progress.h"

namespace cubeao {
namespace {

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
                      reserved1 = 104, origin = 104, reserved2 = 116, headerChecksum = 120;  // origin: format 2
}  // namespace hdr
namespace ent {  // byte offsets in a probe table entry
constexpr std::size_t position = 0, maxDistance = 12, aoOffset = 16, aoSize = 24, depthOffset = 32, depthSize = 40,
                      checksum = 48, index = 56, reserved = 60;
}  // namespace ent

// ---- little-endian encoding, independent of the host's byte order -----------------------------------
void put32(std::uint8_t* p, std::uint32_t v) {
    for (int i = 0; i < 4; ++i) p[i] = std::uint8_t(v >> (8 * i));
}
void put64(std::uint8_t* p, std::uint64_t v) {
    for (int i = 0; i < 8; ++i) p[i] = std::uint8_t(v >> (8 * i));
}
void putF32(std::uint8_t* p, float v) { put32(p, std::bit_cast<std::uint32_t>(v)); }
std::uint32_t get32(const std::uint8_t* p) {
    std::uint32_t v = 0;
    for (int i = 0; i < 4; ++i) v |= std::uint32_t(p[i]) << (8 * i);
    return v;
}
std::uint64_t get64(const std::uint8_t* p) {
    std::uint64_t v = 0;
    for (int i = 0; i < 8; ++i) v |= std::uint64_t(p[i]) << (8 * i);
    return v;
}
float getF32(const std::uint8_t* p) { return std::bit_cast<float>(get32(p)); }

std::uint64_t alignUp(std::uint64_t v) {
    return (v + kCacheSectionAlignment - 1) / kCacheSectionAlignment * kCacheSectionAlignment;
}

// Same spelling as hashToString (scene.h), which lives in cubeao_offline.
std::string hex64(std::uint64_t v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "0x%016" PRIx64, v);
    return buf;
}
std::string hexBytes(const std::uint8_t* p, std::size_t n) {
    std::string s;
    char buf[4];
    for (std::size_t i = 0; i < n; ++i) {
        std::snprintf(buf, sizeof buf, i ? " %02X" : "%02X", unsigned(p[i]));
        s += buf;
    }
    return s;
}
std::string fmtFloat(float v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.9g", double(v));
    return buf;
}
std::string fmtVec(const glm::vec3& v) {
    char buf[96];
    std::snprintf(buf, sizeof buf, "(%.9g, %.9g, %.9g)", double(v.x), double(v.y), double(v.z));
    return buf;
}
std::string join(const std::vector<std::string>& parts, const char* sep) {
    std::string s;
    for (const auto& p : parts) s += (s.empty() ? "" : sep) + p;
    return s;
}
std::string probeName(std::size_t i) { return "probe " + std::to_string(i); }
std::string systemError() { return std::strerror(errno); }

using HashState = std::unique_ptr<XXH3_state_t, decltype(&XXH3_freeState)>;
HashState newHashState() {
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
std::uint64_t hashProbe(std::span<const std::uint8_t> ao, std::span<const std::uint8_t> depth) {
    HashState s = newHashState();
    XXH3_64bits_update(s.get(), ao.data(), ao.size());
    XXH3_64bits_update(s.get(), depth.data(), depth.size());
    return XXH3_64bits_digest(s.get());
}

// ---- writing ----------------------------------------------------------------------------------------

// Buffered writes to the temporary file, hashing every byte for the trailing file checksum.
class Sink {
public:
    explicit Sink(DurableFile& file) : file_(file), hash_(newHashState()) { buffer_.reserve(kBufferSize); }

    void write(std::span<const std::uint8_t> bytes) {
        XXH3_64bits_update(hash_.get(), bytes.data(), bytes.size());
        if (buffer_.size() + bytes.size() > kBufferSize) flush();
        if (bytes.size() >= kBufferSize) writeAll(bytes.data(), bytes.size());  // big sections go straight out
        else buffer_.insert(buffer_.end(), bytes.begin(), bytes.end());
    }
    void zeros(std::size_t n) {
        const std::array<std::uint8_t, kCacheSectionAlignment> z{};
        write(std::span(z.data(), n));
    }
    // Appends the checksum of everything written so far (not itself hashed) and flushes.
    void finish() {
        std::array<std::uint8_t, 8> trailer;
        put64(trailer.data(), XXH3_64bits_digest(hash_.get()));
        buffer_.insert(buffer_.end(), trailer.begin(), trailer.end());
        flush();
    }

private:
    static constexpr std::size_t kBufferSize = 1 << 20;
    void flush() {
        writeAll(buffer_.data(), buffer_.size());
        buffer_.clear();
    }
    void writeAll(const std::uint8_t* p, std::size_t n) { file_.write(std::as_bytes(std::span(p, n))); }
    DurableFile& file_;
    HashState hash_;
    std::vector<std::uint8_t> buffer_;
};

std::array<std::uint8_t, kHeaderSize> encodeHeader(const CacheParams& p, std::uint32_t probeCount,
                                                   std::uint64_t payloadSize, std::uint64_t tableChecksum) {
    std::array<std::uint8_t, kHeaderSize> h{};
    const std::uint64_t payloadOffset = kHeaderSize + kEntrySize * probeCount;
    std::memcpy(h.data() + hdr::magic, kMagic.data(), kMagic.size());
    const bool recentred = p.origin != glm::vec3(0.0f);
    // The oldest format that holds the file (cache_file.h).
    put32(&h[hdr::version], p.denoise != 0 ? 3u : recentred ? 2u : 1u);
    put32(&h[hdr::headerSize], kHeaderSize);
    put64(&h[hdr::sceneHash], p.sceneHash);
    put32(&h[hdr::res], p.res);
    put32(&h[hdr::depthRes], p.depthRes);
    h[hdr::depthFormat] = std::uint8_t(p.depthFormat);
    h[hdr::estimator] = p.estimator;
    h[hdr::falloff] = p.falloff;
    h[hdr::denoise] = p.denoise;  // reserved (0) before format 3
    put32(&h[hdr::spp], p.spp);
    putF32(&h[hdr::radius], p.radius);
    put32(&h[hdr::seed], p.seed);
    put32(&h[hdr::directions], p.directions);
    put32(&h[hdr::steps], p.steps);
    putF32(&h[hdr::hybridThreshold], p.hybridThreshold);
    put32(&h[hdr::probeCount], probeCount);
    put64(&h[hdr::tableOffset], kHeaderSize);
    put64(&h[hdr::payloadOffset], payloadOffset);
    put64(&h[hdr::payloadSize], payloadSize);
    put64(&h[hdr::fileSize], payloadOffset + payloadSize + kTrailerSize);
    put64(&h[hdr::tableChecksum], tableChecksum);
    if (recentred)
        for (int k = 0; k < 3; ++k) putF32(&h[hdr::origin + 4 * std::size_t(k)], p.origin[k]);
    put64(&h[hdr::headerChecksum], XXH3_64bits(h.data(), hdr::headerChecksum));
    return h;
}

CacheParams decodeParams(const std::uint8_t* h, std::uint32_t version) {
    CacheParams p;
    if (version >= 2)
        for (int k = 0; k < 3; ++k) p.origin[k] = getF32(h + hdr::origin + 4 * std::size_t(k));
    p.sceneHash = get64(h + hdr::sceneHash);
    p.res = get32(h + hdr::res);
    p.depthRes = get32(h + hdr::depthRes);
    p.depthFormat = DepthFormat(h[hdr::depthFormat]);
    p.estimator = h[hdr::estimator];
    p.falloff = h[hdr::falloff];
    if (version >= 3) p.denoise = h[hdr::denoise];
    p.spp = get32(h + hdr::spp);
    p.radius = getF32(h + hdr::radius);
    p.seed = get32(h + hdr::seed);
    p.directions = get32(h + hdr::directions);
    p.steps = get32(h + hdr::steps);
    p.hybridThreshold = getF32(h + hdr::hybridThreshold);
    return p;
}

bool allZero(const std::uint8_t* p, std::size_t n) {
    return std::all_of(p, p + n, [](std::uint8_t b) { return b == 0; });
}

// Checks the probes' sizes against the parameters before a byte is written, listing every problem.
void checkProbesToWrite(const std::filesystem::path& path, const CacheParams& params,
                        std::span<const ProbeView> probes) {
    std::vector<std::string> problems = cacheParamProblems(params);
    if (probes.size() > std::numeric_limits<std::uint32_t>::max())
        problems.push_back(std::to_string(probes.size()) + " probes, at most 2^32 - 1 fit the table");
    const std::uint64_t aoSize = aoSectionSize(params), depthSize = depthSectionSize(params);
    std::map<std::uint32_t, std::size_t> indices;
    for (std::size_t i = 0; i < probes.size() && problems.size() < 16; ++i) {
        const ProbeView& v = probes[i];
        if (const auto [it, fresh] = indices.emplace(v.index, i); !fresh)
            problems.push_back(probeName(i) + ": index " + std::to_string(v.index) + " is also " +
                               probeName(it->second) + "'s");
        if (v.aoConfidence.size() != aoSize)
            problems.push_back(probeName(i) + ": AO section has " + std::to_string(v.aoConfidence.size()) +
                               " bytes, res " + std::to_string(params.res) + " needs " + std::to_string(aoSize));
        if (v.depth.size() != depthSize)
            problems.push_back(probeName(i) + ": depth section has " + std::to_string(v.depth.size()) +
                               " bytes, depthRes " + std::to_string(params.depthRes) + " " +
                               depthFormatName(params.depthFormat) + " needs " + std::to_string(depthSize));
        if (!std::isfinite(v.position.x) || !std::isfinite(v.position.y) || !std::isfinite(v.position.z))
            problems.push_back(probeName(i) + ": position " + fmtVec(v.position) + " is not finite");
        if (!(std::isfinite(v.maxDistance) && v.maxDistance >= 0.0f))
            problems.push_back(probeName(i) + ": maxDistance " + fmtFloat(v.maxDistance) + " is not finite and >= 0");
    }
    if (!problems.empty()) throw Error(path.string() + ": cannot write cache: " + join(problems, "; "));
}

using PositionKey = std::array<std::uint32_t, 3>;
PositionKey positionKey(const glm::vec3& p) {
    return {std::bit_cast<std::uint32_t>(p.x), std::bit_cast<std::uint32_t>(p.y), std::bit_cast<std::uint32_t>(p.z)};
}

}  // namespace

// ---- parameters and sizes -----------------------------------------------------------------------------

std::uint32_t depthBytesPerTexel(DepthFormat f) {
    switch (f) {
        case DepthFormat::R16Unorm: return 2;
        case DepthFormat::R16Float: return 2;
        case DepthFormat::R32Float: return 4;
    }
    return 0;
}

const char* depthFormatName(DepthFormat f) {
    switch (f) {
        case DepthFormat::R16Unorm: return "r16unorm";
        case DepthFormat::R16Float: return "r16float";
        case DepthFormat::R32Float: return "r32float";
    }
    return "?";
}

std::vector<std::string> cacheParamProblems(const CacheParams& p) {
    std::vector<std::string> problems;
    if (p.res < 4 || p.res > kMaxRes || p.res % 4 != 0)
        problems.push_back("res " + std::to_string(p.res) + " is not a multiple of 4 in 4..16384");
    if (p.depthRes < 1 || p.depthRes > kMaxRes)
        problems.push_back("depthRes " + std::to_string(p.depthRes) + " is not in 1..16384");
    if (depthBytesPerTexel(p.depthFormat) == 0)
        problems.push_back("depth format " + std::to_string(unsigned(p.depthFormat)) +
                           " is not r16unorm (1), r16float (2) or r32float (3)");
    if (p.estimator > 3)
        problems.push_back("estimator " + std::to_string(p.estimator) +
                           " is not hsplit (0), gtao (1), traced (2) or hybrid (3)");
    if (p.falloff > 1) problems.push_back("falloff " + std::to_string(p.falloff) + " is not none (0) or smooth (1)");
    if (p.denoise > kMaxCacheDenoise)
        problems.push_back("denoise " + std::to_string(p.denoise) + " is not in 0.." + std::to_string(kMaxCacheDenoise));
    if (!(std::isfinite(p.radius) && p.radius > 0.0f))
        problems.push_back("radius " + fmtFloat(p.radius) + " is not finite and > 0");
    if (!std::isfinite(p.hybridThreshold))
        problems.push_back("hybrid threshold " + fmtFloat(p.hybridThreshold) + " is not finite");
    if (!std::isfinite(p.origin.x) || !std::isfinite(p.origin.y) || !std::isfinite(p.origin.z))
        problems.push_back("origin " + fmtVec(p.origin) + " is not finite");
    return problems;
}

std::vector<std::string> cacheParamDifferences(const CacheParams& a, const CacheParams& b) {
    std::vector<std::string> d;
    auto num = [&d](const char* name, auto x, auto y) {
        if (x != y) d.push_back(std::string(name) + " " + std::to_string(x) + " vs " + std::to_string(y));
    };
    if (a.sceneHash != b.sceneHash) d.push_back("scene hash " + hex64(a.sceneHash) + " vs " + hex64(b.sceneHash));
    num("res", a.res, b.res);
    num("depthRes", a.depthRes, b.depthRes);
    if (a.depthFormat != b.depthFormat)
        d.push_back(std::string("depth format ") + depthFormatName(a.depthFormat) + " vs " +
                    depthFormatName(b.depthFormat));
    num("estimator", unsigned(a.estimator), unsigned(b.estimator));
    num("falloff", unsigned(a.falloff), unsigned(b.falloff));
    num("denoise", unsigned(a.denoise), unsigned(b.denoise));
    num("spp", a.spp, b.spp);
    if (a.radius != b.radius) d.push_back("radius " + fmtFloat(a.radius) + " vs " + fmtFloat(b.radius));
    num("seed", a.seed, b.seed);
    num("directions", a.directions, b.directions);
    num("steps", a.steps, b.steps);
    if (a.hybridThreshold != b.hybridThreshold)
        d.push_back("hybrid threshold " + fmtFloat(a.hybridThreshold) + " vs " + fmtFloat(b.hybridThreshold));
    if (a.origin != b.origin) d.push_back("origin " + fmtVec(a.origin) + " vs " + fmtVec(b.origin));
    return d;
}

std::uint64_t aoSectionSize(const CacheParams& p) {
    const std::uint64_t blocks = std::uint64_t(p.res / 4) * (p.res / 4);
    return kFaces * blocks * 16;  // BC5: one 16-byte block per 4×4 texels
}

std::uint64_t depthSectionSize(const CacheParams& p) {
    return kFaces * std::uint64_t(p.depthRes) * p.depthRes * depthBytesPerTexel(p.depthFormat);
}

std::uint64_t cacheFileSize(const CacheParams& p, std::uint64_t probes) {
    return kHeaderSize + probes * (kEntrySize + alignUp(aoSectionSize(p) + depthSectionSize(p))) + kTrailerSize;
}

ProbeView viewOf(const ProbeRecord& r) { return {r.index, r.position, r.maxDistance, r.aoConfidence, r.depth}; }

// ---- writer -------------------------------------------------------------------------------------------

void writeCache(const std::filesystem::path& path, const CacheParams& params, std::span<const ProbeView> probes,
                const WriteOptions& options) {
    checkProbesToWrite(path, params, probes);
    const std::uint32_t count = std::uint32_t(probes.size());
    const std::uint64_t aoSize = aoSectionSize(params), depthSize = depthSectionSize(params);
    const std::uint64_t stride = alignUp(aoSize + depthSize);
    const std::uint64_t payloadOffset = kHeaderSize + kEntrySize * count;

    // Probe checksums first (they live in the table, which precedes the payload): the payload is
    // read twice, which costs far less than the disk write.
    ReleasePacer pacer(options.releaseSources);
    std::vector<std::uint8_t> table(kEntrySize * count);
    for (std::uint32_t i = 0; i < count; ++i) {
        std::uint8_t* e = table.data() + kEntrySize * i;
        const ProbeView& v = probes[i];
        const std::uint64_t aoOffset = payloadOffset + stride * i;
        putF32(e + ent::position + 0, v.position.x);
        putF32(e + ent::position + 4, v.position.y);
        putF32(e + ent::position + 8, v.position.z);
        putF32(e + ent::maxDistance, v.maxDistance);
        put32(e + ent::index, v.index);
        put64(e + ent::aoOffset, aoOffset);
        put64(e + ent::aoSize, aoSize);
        put64(e + ent::depthOffset, aoOffset + aoSize);  // aoSize is a multiple of 16: no gap
        put64(e + ent::depthSize, depthSize);
        put64(e + ent::checksum, hashProbe(v.aoConfidence, v.depth));
        pacer.read(aoSize + depthSize);
    }
    const auto header = encodeHeader(params, count, stride * count, XXH3_64bits(table.data(), table.size()));

    DurableFile tmp(path, "cache");
    {
        Sink sink(tmp);
        sink.write(header);
        sink.write(table);
        for (const ProbeView& v : probes) {
            sink.write(v.aoConfidence);
            sink.write(v.depth);
            sink.zeros(stride - aoSize - depthSize);
            if (options.progress) options.progress->advance();
            pacer.read(aoSize + depthSize);
        }
        sink.finish();
    }
    if (options.releaseSources) options.releaseSources();
    tmp.finish();
    if (options.beforeRename) options.beforeRename();
    tmp.commit();
}

void writeCache(const std::filesystem::path& path, const CacheParams& params, const std::vector<ProbeRecord>& probes,
                const WriteOptions& options) {
    std::vector<ProbeView> views;
    views.reserve(probes.size());
    for (const ProbeRecord& r : probes) views.push_back(viewOf(r));
    writeCache(path, params, views, options);
}

// ---- reader -------------------------------------------------------------------------------------------

CacheReader::CacheReader(const std::filesystem::path& path) : path_(path) {
    const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0) throw Error(path.string() + ": cannot open cache: " + systemError());
    struct stat st {};
    if (::fstat(fd, &st) != 0) {
        const std::string why = systemError();
        ::close(fd);
        throw Error(path.string() + ": cannot open cache: " + why);
    }
    if (!S_ISREG(st.st_mode)) {
        ::close(fd);
        throw Error(path.string() + ": not a cubeao cache (" +
                    (S_ISDIR(st.st_mode) ? "a directory" : "not a regular file") + ")");
    }
    size_ = std::uint64_t(st.st_size);
    if (size_ > 0) {  // mmap of length 0 fails (EINVAL): an empty file is reported by validate()
        void* m = ::mmap(nullptr, size_, PROT_READ, MAP_PRIVATE, fd, 0);
        if (m == MAP_FAILED) {
            const std::string why = systemError();
            ::close(fd);
            throw Error(path.string() + ": cannot map cache: " + why);
        }
        data_ = static_cast<const std::uint8_t*>(m);
    }
    ::close(fd);  // the mapping keeps the file alive
    try {
        validate();
    } catch (...) {
        if (data_) ::munmap(const_cast<std::uint8_t*>(data_), size_);
        throw;
    }
}

CacheReader::~CacheReader() {
    if (data_) ::munmap(const_cast<std::uint8_t*>(data_), size_);
}

CacheReader::CacheReader(CacheReader&& o) noexcept
    : path_(std::move(o.path_)),
      data_(std::exchange(o.data_, nullptr)),
      size_(std::exchange(o.size_, 0)),
      version_(o.version_),
      params_(o.params_),
      entries_(std::move(o.entries_)),
      verified_(std::move(o.verified_)) {}

CacheReader& CacheReader::operator=(CacheReader&& o) noexcept {
    if (this != &o) {
        if (data_) ::munmap(const_cast<std::uint8_t*>(data_), size_);
        path_ = std::move(o.path_);
        data_ = std::exchange(o.data_, nullptr);
        size_ = std::exchange(o.size_, 0);
        version_ = o.version_;
        params_ = o.params_;
        entries_ = std::move(o.entries_);
        verified_ = std::move(o.verified_);
    }
    return *this;
}

std::string CacheReader::where(const std::string& section) const { return path_.string() + ": " + section + ": "; }

// Header checks in the order that gives the most useful message: magic (is it ours at all?), version
// (the only fields every format keeps at the same place), then the checksum, then the values.
void CacheReader::validate() {
    if (size_ == 0) throw Error(path_.string() + ": not a cubeao cache (the file is empty)");
    const std::size_t magicBytes = std::size_t(std::min<std::uint64_t>(size_, kMagic.size()));
    if (std::memcmp(data_, kMagic.data(), magicBytes) != 0)
        throw Error(path_.string() + ": not a cubeao cache (magic: the file starts with " +
                    hexBytes(data_, magicBytes) + ", a cache with " + hexBytes(kMagic.data(), kMagic.size()) + ")");
    const std::string sizeNote = "the file is " + std::to_string(size_) + " bytes";
    if (size_ < hdr::headerSize + 4)
        throw Error(where("header") + "truncated (" + sizeNote + ", the header alone is 128)");
    version_ = get32(data_ + hdr::version);
    if (version_ == 0) throw Error(where("header") + "format version 0 does not exist");
    if (version_ > kCacheFormatVersion)
        throw Error(where("header") + "written by a newer cubeao (format " + std::to_string(version_) +
                    ", this build reads up to " + std::to_string(kCacheFormatVersion) + ")");
    const std::uint32_t headerSize = get32(data_ + hdr::headerSize);
    if (headerSize != kHeaderSize)
        throw Error(where("header") + "header size " + std::to_string(headerSize) + ", format 1 has 128");
    if (size_ < kHeaderSize) throw Error(where("header") + "truncated (" + sizeNote + ", the header alone is 128)");
    const std::uint64_t storedHeaderHash = get64(data_ + hdr::headerChecksum);
    const std::uint64_t headerHash = XXH3_64bits(data_, hdr::headerChecksum);
    if (storedHeaderHash != headerHash)
        throw Error(where("header") + "checksum mismatch (stored " + hex64(storedHeaderHash) + ", computed " +
                    hex64(headerHash) + ")");
    const std::size_t reservedFrom = version_ >= 2 ? hdr::reserved2 : hdr::reserved1;
    if ((version_ < 3 && data_[hdr::reserved0] != 0) || !allZero(data_ + reservedFrom, hdr::headerChecksum - reservedFrom))
        throw Error(where("header") + "reserved bytes are not zero");
    params_ = decodeParams(data_, version_);
    if (const auto problems = cacheParamProblems(params_); !problems.empty())
        throw Error(where("header") + "bad bake parameters: " + join(problems, "; "));

    const std::uint32_t count = get32(data_ + hdr::probeCount);
    const std::uint64_t tableOffset = get64(data_ + hdr::tableOffset);
    const std::uint64_t payloadOffset = get64(data_ + hdr::payloadOffset);
    const std::uint64_t payloadSize = get64(data_ + hdr::payloadSize);
    const std::uint64_t fileSize = get64(data_ + hdr::fileSize);
    if (tableOffset != kHeaderSize)
        throw Error(where("header") + "probe table offset " + std::to_string(tableOffset) +
                    ", expected 128 (right after the header)");
    if (payloadOffset != kHeaderSize + kEntrySize * count)
        throw Error(where("header") + "payload offset " + std::to_string(payloadOffset) + ", the table of " +
                    std::to_string(count) + " probes ends at " + std::to_string(kHeaderSize + kEntrySize * count));
    if (payloadSize > std::numeric_limits<std::uint64_t>::max() - payloadOffset - kTrailerSize ||
        fileSize != payloadOffset + payloadSize + kTrailerSize)
        throw Error(where("header") + "file size " + std::to_string(fileSize) + " is not payload offset " +
                    std::to_string(payloadOffset) + " + payload size " + std::to_string(payloadSize) + " + 8");
    if (size_ > fileSize)
        throw Error(where("file checksum") + std::to_string(size_ - fileSize) +
                    " unexpected bytes after the end (" + sizeNote + ", the header says " + std::to_string(fileSize) +
                    ")");
    const std::string truncated = "truncated (" + sizeNote + ", the header says " + std::to_string(fileSize) + ")";
    if (size_ < payloadOffset) throw Error(where("probe table") + truncated);

    validateTable(get64(data_ + hdr::tableChecksum));
    if (size_ < fileSize) {  // name the probe whose bytes the cut falls in
        const std::uint64_t payloadEnd = payloadOffset + payloadSize;
        if (size_ >= payloadEnd) throw Error(where("file checksum") + truncated);
        for (std::size_t i = entries_.size(); i-- > 0;)
            if (size_ >= entries_[i].aoOffset) throw Error(where(probeName(i)) + truncated);
        throw Error(where("payload") + truncated);
    }
}

// Table entries: every offset and size checked against the payload before any payload byte is read.
void CacheReader::validateTable(std::uint64_t tableChecksum) {
    const std::uint32_t count = get32(data_ + hdr::probeCount);
    const std::uint8_t* table = data_ + kHeaderSize;
    const std::uint64_t computed = XXH3_64bits(table, kEntrySize * count);
    if (computed != tableChecksum)
        throw Error(where("probe table") + "checksum mismatch (stored " + hex64(tableChecksum) + ", computed " +
                    hex64(computed) + ")");
    const std::uint64_t payloadOffset = kHeaderSize + kEntrySize * count;
    const std::uint64_t payloadEnd = payloadOffset + get64(data_ + hdr::payloadSize);
    const std::uint64_t aoSize = aoSectionSize(params_), depthSize = depthSectionSize(params_);
    entries_.clear();
    entries_.reserve(count);
    std::uint64_t cursor = payloadOffset;  // sections appear in table order without overlap
    std::map<std::uint32_t, std::uint32_t> indices;  // probe index → table entry
    for (std::uint32_t i = 0; i < count; ++i) {
        const std::uint8_t* e = table + kEntrySize * i;
        const std::string at = where(probeName(i));
        Entry r{get32(e + ent::index),
                {getF32(e + ent::position), getF32(e + ent::position + 4), getF32(e + ent::position + 8)},
                getF32(e + ent::maxDistance), get64(e + ent::aoOffset), get64(e + ent::aoSize),
                get64(e + ent::depthOffset), get64(e + ent::depthSize), get64(e + ent::checksum)};
        if (!std::isfinite(r.position.x) || !std::isfinite(r.position.y) || !std::isfinite(r.position.z))
            throw Error(at + "position " + fmtVec(r.position) + " is not finite");
        if (!(std::isfinite(r.maxDistance) && r.maxDistance >= 0.0f))
            throw Error(at + "maxDistance " + fmtFloat(r.maxDistance) + " is not finite and >= 0");
        if (!allZero(e + ent::reserved, kEntrySize - ent::reserved))
            throw Error(at + "reserved bytes of its table entry are not zero");
        if (const auto [it, fresh] = indices.emplace(r.index, i); !fresh)
            throw Error(at + "index " + std::to_string(r.index) + " is also " + probeName(it->second) + "'s");
        if (r.aoSize != aoSize)
            throw Error(at + "AO section is " + std::to_string(r.aoSize) + " bytes, res " +
                        std::to_string(params_.res) + " needs " + std::to_string(aoSize));
        if (r.depthSize != depthSize)
            throw Error(at + "depth section is " + std::to_string(r.depthSize) + " bytes, depthRes " +
                        std::to_string(params_.depthRes) + " " + depthFormatName(params_.depthFormat) + " needs " +
                        std::to_string(depthSize));
        const auto section = [&](const char* name, std::uint64_t offset, std::uint64_t size) {
            const std::string range = std::string(name) + " section at offset " + std::to_string(offset);
            if (offset % kCacheSectionAlignment != 0) throw Error(at + range + " is not 16-byte aligned");
            if (offset < cursor)
                throw Error(at + range + " overlaps the bytes before it (which end at " + std::to_string(cursor) + ")");
            if (offset > payloadEnd || size > payloadEnd - offset)
                throw Error(at + range + " + " + std::to_string(size) + " bytes runs past the end of the payload (" +
                            std::to_string(payloadEnd) + ")");
            cursor = offset + size;
        };
        section("AO", r.aoOffset, r.aoSize);
        section("depth", r.depthOffset, r.depthSize);
        entries_.push_back(r);
    }
    verified_ = std::make_unique<std::atomic<std::uint8_t>[]>(count);
}

void CacheReader::expectScene(std::uint64_t sceneHash) const {
    if (params_.sceneHash != sceneHash)
        throw Error(path_.string() + ": baked for scene " + hex64(params_.sceneHash) + ", not for this scene " +
                    hex64(sceneHash) + " (re-bake the cache for this scene)");
}

void CacheReader::expectParams(const CacheParams& p) const {
    const auto d = cacheParamDifferences(params_, p);
    if (!d.empty())
        throw Error(path_.string() + ": baked with other parameters (cache vs expected): " + join(d, ", "));
}

const CacheReader::Entry& CacheReader::entry(std::size_t i) const {
    if (i >= entries_.size())
        throw Error(where(probeName(i)) + "no such probe (the cache has " + std::to_string(entries_.size()) + ")");
    return entries_[i];
}

glm::vec3 CacheReader::position(std::size_t i) const { return entry(i).position; }
float CacheReader::maxDistance(std::size_t i) const { return entry(i).maxDistance; }
std::uint32_t CacheReader::index(std::size_t i) const { return entry(i).index; }

std::uint64_t CacheReader::probeChecksum(const Entry& e) const {
    return hashProbe({data_ + e.aoOffset, e.aoSize}, {data_ + e.depthOffset, e.depthSize});
}

void CacheReader::checkProbe(std::size_t i) const {
    if (verified_[i].load(std::memory_order_acquire)) return;
    const std::uint64_t computed = probeChecksum(entries_[i]);
    if (computed != entries_[i].checksum)
        throw Error(where(probeName(i)) + "checksum mismatch (stored " + hex64(entries_[i].checksum) + ", computed " +
                    hex64(computed) + ")");
    verified_[i].store(1, std::memory_order_release);
}

ProbeView CacheReader::probe(std::size_t i) const {
    const Entry& e = entry(i);
    checkProbe(i);
    return {e.index, e.position, e.maxDistance, {data_ + e.aoOffset, e.aoSize}, {data_ + e.depthOffset, e.depthSize}};
}

std::span<const std::uint8_t> CacheReader::unverifiedDepth(std::size_t i) const {
    const Entry& e = entry(i);
    return {data_ + e.depthOffset, e.depthSize};
}

namespace {

// WILLNEED on the pages of [offset, offset + size) of a mapping (a neighbour's page read early is harmless).
void willNeed(const std::uint8_t* data, std::uint64_t offset, std::uint64_t size) {
    const auto page = std::uint64_t(::sysconf(_SC_PAGESIZE));
    const std::uint64_t first = offset / page * page;
    if (data && size > 0) ::madvise(const_cast<std::uint8_t*>(data) + first, offset + size - first, MADV_WILLNEED);
}

}  // namespace

void CacheReader::prefetch(std::size_t i) const {
    const Entry& e = entry(i);
    willNeed(data_, e.aoOffset, e.aoSize);
    willNeed(data_, e.depthOffset, e.depthSize);
}

void CacheReader::prefetchDepth(std::size_t i) const {
    const Entry& e = entry(i);
    willNeed(data_, e.depthOffset, e.depthSize);
}

void CacheReader::adviseRandomAccess() const {
    if (data_) ::madvise(const_cast<std::uint8_t*>(data_), size_, MADV_RANDOM);
}

void CacheReader::releaseAll() const {
    if (data_) ::madvise(const_cast<std::uint8_t*>(data_), size_, MADV_DONTNEED);
}

ProbeRecord CacheReader::copyProbe(std::size_t i) const {
    prefetch(i);  // one read of its pages, also after adviseRandomAccess
    const ProbeView v = probe(i);
    return {v.index, v.position, v.maxDistance, {v.aoConfidence.begin(), v.aoConfidence.end()},
            {v.depth.begin(), v.depth.end()}};
}

void CacheReader::verifyAll() const {
    constexpr std::size_t kListed = 8;
    std::vector<std::string> damage;
    std::size_t damaged = 0;
    ReleasePacer pacer([this] { releaseAll(); });  // checking a cache of any size keeps little of it resident
    for (std::size_t i = 0; i < entries_.size(); ++i) {
        prefetch(i);  // read ahead even after adviseRandomAccess
        const std::uint64_t computed = probeChecksum(entries_[i]);
        pacer.read(entries_[i].aoSize + entries_[i].depthSize);
        if (computed == entries_[i].checksum) {
            verified_[i].store(1, std::memory_order_release);
            continue;
        }
        if (++damaged <= kListed)
            damage.push_back(probeName(i) + ": checksum mismatch (stored " + hex64(entries_[i].checksum) +
                             ", computed " + hex64(computed) + ")");
    }
    if (damaged > kListed) damage.push_back("and " + std::to_string(damaged - kListed) + " more damaged probes");
    const std::uint64_t stored = get64(data_ + size_ - kTrailerSize);
    const HashState hash = newHashState();
    for (std::uint64_t at = 0; at < size_ - kTrailerSize; at += WriteOptions::kReleaseBytes) {
        const std::uint64_t n = std::min(WriteOptions::kReleaseBytes, size_ - kTrailerSize - at);
        willNeed(data_, at, n);
        XXH3_64bits_update(hash.get(), data_ + at, n);
        pacer.read(n);
    }
    releaseAll();
    const std::uint64_t computed = XXH3_64bits_digest(hash.get());
    if (stored != computed)
        damage.push_back("file checksum: mismatch (stored " + hex64(stored) + ", computed " + hex64(computed) + ")" +
                         (damaged ? "" : ": damage outside every probe's sections (padding or the checksum itself)"));
    if (!damage.empty()) throw Error(path_.string() + ": " + join(damage, "; "));
}

double CacheReader::bytesPerTexel() const {
    if (entries_.empty()) return 0.0;
    return double(size_) / (double(entries_.size()) * kFaces * double(params_.res) * double(params_.res));
}

// ---- append and merge ---------------------------------------------------------------------------------

void appendToCache(const std::filesystem::path& path, const CacheParams& params, std::span<const ProbeView> newProbes,
                   const WriteOptions& options) {
    std::error_code ec;
    if (std::filesystem::status(path, ec).type() == std::filesystem::file_type::not_found) {
        writeCache(path, params, newProbes, options);
        return;
    }
    const CacheReader old(path);  // reports permission and other errors; the mapping outlives the rename
    if (const auto d = cacheParamDifferences(old.params(), params); !d.empty())
        throw Error(path.string() + ": cannot append: the cache was baked with other parameters (cache vs new): " +
                    join(d, ", "));
    std::map<PositionKey, std::size_t> seen;
    std::map<std::uint32_t, std::size_t> indices;
    std::vector<ProbeView> all;
    all.reserve(old.probeCount() + newProbes.size());
    const std::uint64_t probeBytes = aoSectionSize(params) + depthSectionSize(params);
    ReleasePacer pacer([&] { old.releaseAll(); });
    for (std::size_t i = 0; i < old.probeCount(); ++i) {
        all.push_back(old.probe(i));  // checksum checked: damage is never copied into a fresh checksum
        pacer.read(probeBytes);
        seen.emplace(positionKey(all.back().position), i);
        indices.emplace(all.back().index, i);
    }
    const auto which = [&](std::size_t at) {
        return "probe " + std::to_string(at < old.probeCount() ? at : at - old.probeCount()) +
               (at < old.probeCount() ? " of the cache" : " of the new probes");
    };
    for (std::size_t i = 0; i < newProbes.size(); ++i) {
        const std::string probe = path.string() + ": cannot append: new probe " + std::to_string(i);
        if (const auto [it, fresh] = seen.emplace(positionKey(newProbes[i].position), old.probeCount() + i); !fresh)
            throw Error(probe + " at " + fmtVec(newProbes[i].position) + " is already " + which(it->second));
        if (const auto [it, fresh] = indices.emplace(newProbes[i].index, old.probeCount() + i); !fresh)
            throw Error(probe + " has index " + std::to_string(newProbes[i].index) + ", as " + which(it->second));
        all.push_back(newProbes[i]);
    }
    WriteOptions withRelease = options;
    withRelease.releaseSources = [&] {
        old.releaseAll();
        if (options.releaseSources) options.releaseSources();
    };
    writeCache(path, params, all, withRelease);
}

void appendToCache(const std::filesystem::path& path, const CacheParams& params,
                   const std::vector<ProbeRecord>& newProbes, const WriteOptions& options) {
    std::vector<ProbeView> views;
    views.reserve(newProbes.size());
    for (const ProbeRecord& r : newProbes) views.push_back(viewOf(r));
    appendToCache(path, params, views, options);
}

void mergeCaches(const std::filesystem::path& out, const std::vector<std::filesystem::path>& inputs,
                 const WriteOptions& options) {
    if (inputs.empty()) throw Error(out.string() + ": merge needs at least one input cache");
    std::vector<CacheReader> readers;
    readers.reserve(inputs.size());
    for (const auto& in : inputs) readers.emplace_back(in);
    const CacheParams& params = readers.front().params();
    for (std::size_t k = 1; k < readers.size(); ++k)
        if (const auto d = cacheParamDifferences(params, readers[k].params()); !d.empty())
            throw Error(inputs[k].string() + ": cannot merge with " + inputs[0].string() +
                        ", baked with other parameters (" + inputs[0].filename().string() + " vs this): " +
                        join(d, ", "));
    // The same position or index twice means the same probe was baked by two shards (overlapping
    // --shard ranges, or one input given twice): refuse rather than guess which copy is right.
    std::map<PositionKey, std::pair<std::size_t, std::size_t>> seen;
    std::map<std::uint32_t, std::pair<std::size_t, std::size_t>> indices;
    std::vector<ProbeView> all;
    const std::uint64_t probeBytes = aoSectionSize(params) + depthSectionSize(params);
    std::size_t k = 0;  // the input being read
    ReleasePacer pacer([&] { readers[k].releaseAll(); });
    for (; k < readers.size(); ++k)
        for (std::size_t i = 0; i < readers[k].probeCount(); ++i) {
            const std::string probe = inputs[k].string() + ": probe " + std::to_string(i);
            const auto other = [&](std::pair<std::size_t, std::size_t> at) {
                return "probe " + std::to_string(at.second) + " of " + inputs[at.first].string() +
                       " (baked twice: overlapping shards?)";
            };
            if (const auto [it, fresh] = seen.emplace(positionKey(readers[k].position(i)), std::pair(k, i)); !fresh)
                throw Error(probe + " at " + fmtVec(readers[k].position(i)) + " is also " + other(it->second));
            if (const auto [it, fresh] = indices.emplace(readers[k].index(i), std::pair(k, i)); !fresh)
                throw Error(probe + " has index " + std::to_string(readers[k].index(i)) + ", as " + other(it->second));
            all.push_back(readers[k].probe(i));  // checks the probe's checksum: reads its payload
            pacer.read(probeBytes);
        }
    // Index order: shards merged in any order give the same file as one unsharded bake.
    std::stable_sort(all.begin(), all.end(), [](const ProbeView& x, const ProbeView& y) { return x.index < y.index; });
    // The inputs stay mapped (the views point into them) but not resident: a merge of caches of any
    // size holds about WriteOptions::kReleaseBytes of them at a time.
    WriteOptions withRelease = options;
    withRelease.releaseSources = [&] {
        for (const CacheReader& r : readers) r.releaseAll();
        if (options.releaseSources) options.releaseSources();
    };
    writeCache(out, params, all, withRelease);
}

}  // namespace cubeao
