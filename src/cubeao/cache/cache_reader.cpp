// The mmap cache reader: every structural check on open, probe checksums on first access, page advice.
#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <utility>

#include "cubeao/cache/cache_codec.h"
#include "cubeao/core/error.h"

namespace cubeao {
namespace {

using namespace cache_codec;

bool allZero(const std::uint8_t* p, std::size_t n) {
    return std::all_of(p, p + n, [](std::uint8_t b) { return b == 0; });
}

}  // namespace

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
    const std::size_t reservedFrom = version_ >= 5   ? hdr::reserved4
                                     : version_ >= 4 ? hdr::reserved3
                                     : version_ >= 2 ? hdr::reserved2
                                                     : hdr::reserved1;
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
    return {e.index,
            e.position,
            e.maxDistance,
            {data_ + e.aoOffset, e.aoSize},
            {data_ + e.depthOffset, e.depthSize},
            params_.aoFormat};
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
            {v.depth.begin(), v.depth.end()}, v.aoFormat};
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

}  // namespace cubeao
