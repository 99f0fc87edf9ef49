// The `.cubeao` probe cache file (DESIGN.md §5 "Cache file"; byte layout in docs/FORMAT.md): write it
// atomically, map it read-only and check every offset, size and checksum before a byte is used.
// Part of cubeao_runtime (what an engine links): no OIIO, no Embree, no bake types here.
#pragma once

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

namespace cubeao {

class Progress;

// Newest format this build writes and reads (docs/FORMAT.md "Versioning"). Format 2 adds the scene's
// origin (CacheParams::origin), format 3 the bake's AO filter (CacheParams::denoise), format 4 the AO
// section's format (CacheParams::aoFormat), format 5 the levels of detail (CacheParams::levels). A cache
// is written in the oldest format that holds it: one whose origin is 0, whose AO is unfiltered, BC5 and
// of one level is still format 1, byte for byte what earlier builds wrote and can read.
constexpr std::uint32_t kCacheFormatVersion = 5;
// The widest AO filter a header can name (bake_settings.h kMaxDenoiseRadius).
constexpr std::uint32_t kMaxCacheDenoise = 8;
// Levels of detail (format 5): level k of a probe is its cube at res >> k (AO) and depthRes >> k
// (distance), each level made from the full-resolution data. At most this many, and no level's AO
// face smaller than kMinLevelRes texels (defaultLevels).
constexpr std::uint32_t kMaxCacheLevels = 8;
constexpr std::uint32_t kMinLevelRes = 16;
// Every payload section starts at a multiple of this, so BC blocks and depth texels can be uploaded
// straight from the mapping.
constexpr std::uint64_t kCacheSectionAlignment = 16;

// Texel format of a probe's distance cube. Values are what the file stores (0 is left invalid so a
// zeroed header is caught).
enum class DepthFormat : std::uint8_t {
    R16Unorm = 1,  // distance / maxDistance of the probe record, 0..65535
    R16Float = 2,  // IEEE half, world units
    R32Float = 3,  // IEEE single, world units
};
std::uint32_t depthBytesPerTexel(DepthFormat f);  // 2, 2, 4; 0 for a value outside the enum
const char* depthFormatName(DepthFormat f);       // "r16unorm", "r16float", "r32float", "?"

// Format of a probe's AO section (cache/bc4.h has the blocks and the cube layout). Values are what
// the file stores (header byte 116, format 4).
enum class AoFormat : std::uint8_t {
    Bc5 = 0,  // AO in red, confidence in green: 16 bytes per 4×4 texels (1 byte per texel)
    Bc4 = 1,  // AO alone, for caches whose confidence is 1 everywhere (traced): 8 bytes per 4×4 texels;
              // read as confidence 1 (the run time's texture swizzles green to one)
};
std::uint32_t aoBlockBytes(AoFormat f);  // 16, 8; 0 for a value outside the enum
const char* aoFormatName(AoFormat f);    // "bc5", "bc4", "?"
// "bc5" or "bc4"; UsageError naming the choices otherwise (`option` names the flag in the message).
AoFormat parseAoFormat(const std::string& name, const std::string& option = "--ao");
// The format a bake with `estimator` (CacheParams numbering) stores by default: BC4 for traced, whose
// confidence is 1 in every texel, BC5 for the estimators that estimate one (hsplit, gtao, hybrid).
AoFormat defaultAoFormat(std::uint8_t estimator);

// An AO section of `res`² faces in format `from` as format `to`, lossless for the AO: a BC5 block is
// its red BC4 block followed by its green one, so BC4 is the first half of each BC5 block and BC5
// from BC4 appends the green block of confidence 1 the encoder makes (FF FE 00 00 00 00 00 00). The same
// bytes when from == to. Error when the size is not that of `from` at `res`.
// A section of `levels` levels (format 5) converts level by level: every level is whole blocks.
std::vector<std::uint8_t> convertAoSection(std::span<const std::uint8_t> section, std::uint32_t res, AoFormat from,
                                           AoFormat to, std::uint32_t levels = 1);

// Everything a bake was made with; two caches can be merged or appended to only when these are
// equal (operator==, bit for bit). Enum fields keep the bake's numbering so the CLI can cast:
// estimator = Estimator (hsplit 0, gtao 1, traced 2, hybrid 3), falloff = Falloff (none 0, smooth 1).
struct CacheParams {
    std::uint64_t sceneHash = 0;   // Scene::hash (geometryHash) of the scene the probes belong to
    std::uint32_t res = 0;         // AO face resolution, texels per side; a multiple of 4 (BC blocks)
    std::uint32_t depthRes = 0;    // distance cube resolution, texels per side
    DepthFormat depthFormat = DepthFormat::R16Unorm;
    std::uint8_t estimator = 0;
    std::uint8_t falloff = 0;
    std::uint8_t denoise = 0;      // the edge-aware filter of traced AO, texels a side (0: none; format 3)
    std::uint32_t spp = 0;
    float radius = 0.0f;           // AO radius R, world units
    std::uint32_t seed = 0;
    std::uint32_t directions = 0;  // horizon directions N_d
    std::uint32_t steps = 0;       // march steps N_s
    float hybridThreshold = 0.0f;
    AoFormat aoFormat = AoFormat::Bc5;  // the AO sections' blocks (format 4; BC5 before it)
    std::uint8_t levels = 1;            // levels of detail per probe, finest first (format 5; 1 before it)
    // File coordinates of the scene's local origin (Scene::origin: whole units rounded to float, so exact
    // here); probe positions in the table are local, file coordinates = position + origin. 0 for scenes
    // that were not re-centred (and for every format-1 file).
    glm::vec3 origin{0.0f};

    bool operator==(const CacheParams&) const = default;
};

// Every range problem of `p` at once (empty: valid). Limits: res 4..16384 and a multiple of 4,
// depthRes 1..16384, a known depth format, estimator ≤ 3, falloff ≤ 1, denoise ≤ 8, radius finite and > 0,
// hybridThreshold finite, origin finite, a known AO format and BC4 only for traced (estimator 2): the
// others' confidence would be lost; levels 1..8 with res a multiple of 4 · 2^(levels − 1) and depthRes
// of 2^(levels − 1), so every level is whole BC blocks and whole distance texels.

std::vector<std::string> cacheParamProblems(const CacheParams& p);
// Fields that differ between `a` and `b`, "res 8 vs 16" style; empty when a == b.
std::vector<std::string> cacheParamDifferences(const CacheParams& a, const CacheParams& b);

// Section sizes every probe of a cache with these parameters has: every level's, finest first.
// AO: 6 faces × (res/4)² blocks × aoBlockBytes: 6·res² bytes for BC5 (1 byte per texel), half for BC4.
std::uint64_t aoSectionSize(const CacheParams& p);
// Distance cube: 6 faces × depthRes² texels × depthBytesPerTexel.
std::uint64_t depthSectionSize(const CacheParams& p);
// The most levels a bake of these sizes can store: while the next level's AO face is at least
// kMinLevelRes and both sizes halve evenly (1 for res < 2 · kMinLevelRes).
std::uint32_t maxLevels(std::uint32_t res, std::uint32_t depthRes);
// Level `level` alone, as a cache of one level: res >> level, depthRes >> level, levels 1. Its section
// sizes are the level's, and a ProbeView of it (levelView) is what the run time and tools read at
// that level. Error for a level ≥ p.levels.
CacheParams levelParams(const CacheParams& p, std::uint32_t level);
// Where level `level` starts in a probe's distance section (0 for level 0).
std::uint64_t depthLevelOffset(const CacheParams& p, std::uint32_t level);
// Exact size of a file holding `probes` probes (header, table, payload with padding, checksum).
std::uint64_t cacheFileSize(const CacheParams& p, std::uint64_t probes);

// One probe as the bake hands it over and tools get it back.
struct ProbeRecord {
    std::uint32_t index = 0;                  // the probe's index in probes.json: it seeds its texels'
                                              // sample keys, and is unique within a cache
    glm::vec3 position{0.0f};
    float maxDistance = 0.0f;                 // scale of R16Unorm distances (world units)
    std::vector<std::uint8_t> aoConfidence;   // the AO section in aoFormat (BC5: AO + confidence)
    std::vector<std::uint8_t> depth;          // depthSectionSize(params) bytes
    AoFormat aoFormat = AoFormat::Bc5;        // what a bake makes; a reader gives its cache's
};
// `r` with its AO section in format `to` (convertAoSection of `levels` levels; unchanged when it already is).
ProbeRecord withAoFormat(ProbeRecord r, AoFormat to, std::uint32_t res, std::uint32_t levels = 1);
// `p` with the AO format `to`: what a probe in that format is held as beside these parameters.
CacheParams withAoFormat(CacheParams p, AoFormat to);

// One probe without copies: spans into a reader's mapping (valid while the reader lives) or into
// the caller's buffers when writing.
struct ProbeView {
    std::uint32_t index = 0;
    glm::vec3 position{0.0f};
    float maxDistance = 0.0f;
    std::span<const std::uint8_t> aoConfidence;  // in aoFormat
    std::span<const std::uint8_t> depth;
    AoFormat aoFormat = AoFormat::Bc5;
};
ProbeView viewOf(const ProbeRecord& r);
// Level `level` of a probe of a cache with parameters `p`: spans into v's sections (in v.aoFormat).
ProbeView levelView(const ProbeView& v, const CacheParams& p, std::uint32_t level);

struct WriteOptions {
    // Called after the temporary file is complete and fsynced, right before the rename: a test
    // throws here to stand for a crash between write and rename.
    std::function<void()> beforeRename;
    // Advanced once per probe written (merge's progress); may be null.
    Progress* progress = nullptr;
    // Called after every kReleaseBytes of probe payload read (both passes over the probes: checksums,
    // then the write), and at the end. mergeCaches and appendToCache drop their inputs' mapped pages
    // here (CacheReader::releaseAll), so copying a cache of any size keeps only that much of it
    // resident. May be null.
    std::function<void()> releaseSources;
    static constexpr std::uint64_t kReleaseBytes = std::uint64_t(64) << 20;
};

// Writes `path` atomically through a DurableFile (core/durable_file.h): temporary file beside it,
// fsync, rename, directory fsync. On any failure the temporary file is removed, `path` is left as it
// was, and cubeao::Error names the file and what failed. Probe indices must be distinct. A probe whose
// AO is in another format than params.aoFormat is converted as it is written (convertAoSection).
void writeCache(const std::filesystem::path& path, const CacheParams& params, std::span<const ProbeView> probes,
                const WriteOptions& options = {});
void writeCache(const std::filesystem::path& path, const CacheParams& params, const std::vector<ProbeRecord>& probes,
                const WriteOptions& options = {});

// A cache mapped read-only. The constructor checks magic, version, header, the probe table and every
// probe's offsets and sizes (nothing past the end, aligned, in table order, no overlap, sizes as
// `params()` implies); it reads no payload byte. Probe checksums are checked on first access to a
// probe; verifyAll() checks all of them and the trailing file checksum. Every error is cubeao::Error
// "FILE: SECTION: problem" where SECTION is "header", "probe table", "probe N" or "file checksum".
// Thread-safe for concurrent const use. Caveat: a file truncated by another process while mapped
// raises SIGBUS on access (as for any mmap reader); caches are replaced by rename, never rewritten
// in place, so readers of the old file are unaffected by a new bake.
class CacheReader {
public:
    explicit CacheReader(const std::filesystem::path& path);
    ~CacheReader();
    CacheReader(CacheReader&& other) noexcept;
    CacheReader& operator=(CacheReader&& other) noexcept;
    CacheReader(const CacheReader&) = delete;
    CacheReader& operator=(const CacheReader&) = delete;

    const std::filesystem::path& path() const { return path_; }
    const CacheParams& params() const { return params_; }
    std::uint32_t formatVersion() const { return version_; }
    std::size_t probeCount() const { return entries_.size(); }
    std::uint64_t fileSize() const { return size_; }

    // Throws when the cache was baked for another scene, naming both hashes.
    void expectScene(std::uint64_t sceneHash) const;
    // Throws when params() != p, listing every difference.
    void expectParams(const CacheParams& p) const;

    // From the table (covered by the table checksum, checked on open): no payload page is touched,
    // so an engine can build its spatial index of probes without reading the payload.
    glm::vec3 position(std::size_t i) const;
    float maxDistance(std::size_t i) const;
    std::uint32_t index(std::size_t i) const;  // the probe's index in probes.json

    // Spans into the mapping; checks probe i's checksum the first time it is asked for.
    ProbeView probe(std::size_t i) const;
    ProbeRecord copyProbe(std::size_t i) const;  // for tools
    // Probe i's distance section without its checksum check, for readers that take a few texels of
    // every probe as a hint and tolerate damage (the run-time candidate grid): the check hashes the
    // AO too, so checking here would read the whole file at the start. probe(i) still checks the
    // probe before anything uses its bytes for pixels.
    std::span<const std::uint8_t> unverifiedDepth(std::size_t i) const;

    // Page hints for a reader that streams probes (runtime/probe_source.h). prefetch: ask the
    // kernel to start reading probe i's payload now (MADV_WILLNEED), so a later probe(i) does not wait
    // for the disk. releaseAll: drop every page of the mapping from this process's resident set
    // (MADV_DONTNEED; the mapping is private and read-only, so the next access faults them back in
    // from the page cache), so streaming through a cache of any size keeps the RSS bounded. The whole
    // mapping, not one probe's pages: the kernel maps a probe's neighbours' pages along with its own
    // (large page-cache folios), and those would stay. Hints: failures are ignored.
    void prefetch(std::size_t i) const;
    void prefetchDepth(std::size_t i) const;  // the distance section alone
    void releaseAll() const;
    // The pages are read out of order from now on (a run-time streaming probes): a fault reads its
    // own page and no read-around (MADV_RANDOM), and the reader asks for what it wants with prefetch
    // and prefetchDepth (copyProbe and verifyAll ask for their pages themselves). Without it a fault
    // reads up to the device's read-ahead window around it (8 MiB on the development VM), so a few
    // distance texels of every probe read the whole file.
    void adviseRandomAccess() const;

    // Every probe checksum and the trailing file checksum; one Error listing every damaged probe.
    void verifyAll() const;

    // File size / (probes × 6 × res²): what a texel of AO costs on disk, everything included
    // (header, table, distance cube, padding). 0 for an empty cache.
    double bytesPerTexel() const;

private:
    struct Entry {
        std::uint32_t index;
        glm::vec3 position;
        float maxDistance;
        std::uint64_t aoOffset, aoSize, depthOffset, depthSize, checksum;
    };
    void validate();
    void validateTable(std::uint64_t tableChecksum);
    const Entry& entry(std::size_t i) const;  // Error for an index past the table
    std::uint64_t probeChecksum(const Entry& e) const;
    void checkProbe(std::size_t i) const;
    std::string where(const std::string& section) const;

    std::filesystem::path path_;
    const std::uint8_t* data_ = nullptr;  // the mapping; null for an empty file (never mapped)
    std::uint64_t size_ = 0;
    std::uint32_t version_ = 0;
    CacheParams params_;
    std::vector<Entry> entries_;
    std::unique_ptr<std::atomic<std::uint8_t>[]> verified_;  // per probe: checksum already matched
};

// `path`'s probes followed by `newProbes`, rewritten atomically (the whole file is written again, so
// O(file size): a bake writes its batches as part files instead, bake/bake_cache.h, docs/FORMAT.md
// "Appending"). The existing cache must have exactly `params` (scene
// hash included) and its probes must pass their checksums; a new probe at the position or with the
// index of an existing one is an error. A missing `path` is created as by writeCache.
void appendToCache(const std::filesystem::path& path, const CacheParams& params, std::span<const ProbeView> newProbes,
                   const WriteOptions& options = {});
void appendToCache(const std::filesystem::path& path, const CacheParams& params,
                   const std::vector<ProbeRecord>& newProbes, const WriteOptions& options = {});

// `cubeao merge OUT IN...`: the probes of every input, sorted by index (so shards merged in any order
// give the file an unsharded bake writes), written atomically to `out`
// (which may be one of the inputs). Inputs must share scene hash and parameters, and no position or
// index may occur twice (the same probe baked in two shards); errors name the input file. The AO
// format is the one parameter inputs may differ in: `out` is written in `aoFormat` (default: the
// first input's) and every probe in another is converted (convertAoSection), so `merge OUT IN`
// converts a cache (BC4 only for traced caches, as cacheParamProblems says). `levels` keeps that many
// levels of detail (default: the first input's), the finest first: inputs may have more (their coarser
// levels are left out), not fewer (levels are made from the bake's full-resolution data: Error naming
// `bake --levels`).
void mergeCaches(const std::filesystem::path& out, const std::vector<std::filesystem::path>& inputs,
                 const WriteOptions& options = {}, std::optional<AoFormat> aoFormat = {},
                 std::optional<std::uint32_t> levels = {});

}  // namespace cubeao
