// The cache writer: every probe checked against the parameters before a byte is written, then header,
// table and payload streamed through one DurableFile (core/durable_file.h) with the file checksum last.
#include <cmath>
#include <limits>
#include <map>

#include "cubeao/cache/cache_codec.h"
#include "cubeao/core/error.h"
#include "cubeao/core/durable_file.h"
#include "cubeao/core/progress.h"

namespace cubeao {
namespace {

using namespace cache_codec;

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

// A probe's AO section as the file stores it: its own bytes, or converted when the probe is in
// another format than the cache (`converted` holds those bytes while they are used).
std::span<const std::uint8_t> storedAo(const ProbeView& v, const CacheParams& params, std::vector<std::uint8_t>& converted) {
    if (v.aoFormat == params.aoFormat) return v.aoConfidence;
    converted = convertAoSection(v.aoConfidence, params.res, v.aoFormat, params.aoFormat, params.levels);
    return converted;
}

// Checks the probes' sizes against the parameters before a byte is written, listing every problem.
void checkProbesToWrite(const std::filesystem::path& path, const CacheParams& params,
                        std::span<const ProbeView> probes) {
    std::vector<std::string> problems = cacheParamProblems(params);
    if (probes.size() > std::numeric_limits<std::uint32_t>::max())
        problems.push_back(std::to_string(probes.size()) + " probes, at most 2^32 - 1 fit the table");
    const std::uint64_t depthSize = depthSectionSize(params);
    std::map<std::uint32_t, std::size_t> indices;
    for (std::size_t i = 0; i < probes.size() && problems.size() < 16; ++i) {
        const ProbeView& v = probes[i];
        if (const auto [it, fresh] = indices.emplace(v.index, i); !fresh)
            problems.push_back(probeName(i) + ": index " + std::to_string(v.index) + " is also " +
                               probeName(it->second) + "'s");
        // The probe's AO may come in another format: converted on the way.
        if (const std::uint64_t need = aoSectionSize(withAoFormat(params, v.aoFormat));
            v.aoConfidence.size() != need || need == 0)
            problems.push_back(probeName(i) + ": AO section has " + std::to_string(v.aoConfidence.size()) + " bytes, " +
                               aoFormatName(v.aoFormat) + " at res " + std::to_string(params.res) + " needs " +
                               std::to_string(need));
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

}  // namespace

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
    std::vector<std::uint8_t> converted;
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
        put64(e + ent::depthOffset, aoOffset + aoSize);  // aoSize is a multiple of 16 (48 (res/4)² for BC4): no gap
        put64(e + ent::depthSize, depthSize);
        put64(e + ent::checksum, hashProbe(storedAo(v, params, converted), v.depth));
        pacer.read(aoSize + depthSize);
    }
    const auto header = encodeHeader(params, count, stride * count, XXH3_64bits(table.data(), table.size()));

    DurableFile tmp(path, "cache");
    {
        Sink sink(tmp);
        sink.write(header);
        sink.write(table);
        for (const ProbeView& v : probes) {
            sink.write(storedAo(v, params, converted));
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

}  // namespace cubeao
