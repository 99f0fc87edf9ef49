#include "cubeao/bake/bake_cache.h"

#include <signal.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <memory>
#include <optional>
#include <string>
#include <system_error>

#include <spdlog/spdlog.h>

#include "cubeao/core/durable_file.h"
#include "cubeao/core/error.h"

namespace cubeao {
namespace {

namespace fs = std::filesystem;

const char* const kStartOver = "choose another --out or delete the file to bake from scratch";

std::string vecText(const glm::vec3& v) {
    char buf[96];
    std::snprintf(buf, sizeof buf, "(%.9g, %.9g, %.9g)", double(v.x), double(v.y), double(v.z));
    return buf;
}

}  // namespace

void MemoryProbeSink::add(ProbeRecord probe) {
    if (!indices_.insert(probe.index).second) throw Error("probe index " + std::to_string(probe.index) + " baked twice");
    records.push_back(std::move(probe));
}

namespace {

// The probe indices of the cache `file` (the output or one of its parts), after checking that it is
// the same bake: parameters and scene hash, and every index at the position the probe set gives it.
std::vector<std::uint32_t> sameBakeIndices(const fs::path& file, const CacheParams& params,
                                           std::span<const glm::vec3> probes) {
    std::unique_ptr<CacheReader> cache;
    try {
        cache = std::make_unique<CacheReader>(file);
    } catch (const Error& e) {
        throw Error(std::string(e.what()) + " (--out exists and is not a readable cache: " + kStartOver + ")");
    }
    if (const auto d = cacheParamDifferences(cache->params(), params); !d.empty()) {
        std::string list;
        for (const auto& x : d) list += (list.empty() ? "" : ", ") + x;
        // A traced cache of an earlier build holds BC5: resuming it is a matter of the format alone.
        const bool formatOnly = d.size() == 1 && cache->params().aoFormat != params.aoFormat;
        throw Error(file.string() + ": exists with other bake parameters (cache vs this bake: " + list + "); " +
                    (formatOnly ? std::string("--ao ") + aoFormatName(cache->params().aoFormat) +
                                      " resumes it as it is (cubeao merge --ao converts it), or " + kStartOver
                                : std::string(kStartOver)));
    }
    std::vector<std::uint32_t> indices;
    for (std::size_t i = 0; i < cache->probeCount(); ++i) {
        const std::uint32_t index = cache->index(i);
        const glm::vec3 cached = cache->position(i);
        if (index >= probes.size() || probes[index] != cached)
            throw Error(file.string() + ": holds probe index " + std::to_string(index) + " at " + vecText(cached) +
                        (index < probes.size() ? ", the probe set puts it at " + vecText(probes[index])
                                               : ", the probe set has " + std::to_string(probes.size()) + " probes") +
                        ": the probe set changed; " + kStartOver);
        indices.push_back(index);
    }
    return indices;
}

// The number of the part file `name` when it is one of `prefix` ("OUT.part-"): partPath writes at least
// 6 digits (%06zu), part 1,000,000 on more; past 18 it is not ours (and std::stoul would overflow).
std::optional<std::size_t> partNumber(const std::string& name, const std::string& prefix) {
    const std::size_t digitCount = name.size() - std::min(name.size(), prefix.size());
    if (digitCount < 6 || digitCount > 18 || name.compare(0, prefix.size(), prefix) != 0) return std::nullopt;
    const std::string digits = name.substr(prefix.size());
    if (digits.find_first_not_of("0123456789") != std::string::npos) return std::nullopt;
    return std::stoul(digits);
}

// The writer's process id when `name` is the temporary file of a writeCache for the output `outName` or
// for one of its parts (temporaryFileWriter); 0 otherwise.
pid_t tempFileOwner(const std::string& name, const std::string& outName) {
    const std::string prefix = "." + outName;
    if (name.compare(0, prefix.size(), prefix) != 0) return 0;
    const std::size_t tmp = name.find(".tmp-", prefix.size());
    if (tmp == std::string::npos) return 0;
    const std::string target = name.substr(1, tmp - 1);
    if (target != outName && !partNumber(target, outName + ".part-")) return 0;
    return pid_t(temporaryFileWriter(name, target));
}

double msSince(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace

fs::path BakeCacheWriter::partPath(const fs::path& path, std::size_t n) {
    char suffix[32];
    std::snprintf(suffix, sizeof suffix, ".part-%06zu", n);
    return fs::path(path.string() + suffix);
}

BakeCacheWriter::BakeCacheWriter(fs::path path, const CacheParams& params, std::span<const glm::vec3> probes,
                                 Options options)
    : path_(std::move(path)), params_(params), options_(options) {
    std::error_code ec;
    const fs::file_status status = fs::status(path_, ec);
    if (status.type() == fs::file_type::directory)
        throw Error(path_.string() + ": --out is a directory; bake now writes one .cubeao cache file (" +
                    "e.g. --out " + (path_ / "probes.cubeao").string() + ")");
    std::set<std::uint32_t> inOutput;
    if (status.type() != fs::file_type::not_found)
        for (const std::uint32_t index : sameBakeIndices(path_, params_, probes)) inOutput.insert(index);
    stored_ = inOutput;
    adoptParts(probes, inOutput);
    atStart_ = stored_.size();
}

// Part files of an earlier run: numbered "PATH.part-NNNNNN" beside the output (their temporary files
// have other names and are never taken for parts).
void BakeCacheWriter::adoptParts(std::span<const glm::vec3> probes, const std::set<std::uint32_t>& inOutput) {
    const fs::path dir = path_.has_parent_path() ? path_.parent_path() : fs::path(".");
    const std::string prefix = path_.filename().string() + ".part-";
    std::vector<std::pair<std::size_t, fs::path>> found;
    std::error_code ec;
    for (const fs::directory_entry& e : fs::directory_iterator(dir, ec)) {
        const std::string name = e.path().filename().string();
        // A temporary file of a writer that was killed (SIGKILL, power loss) before its rename: never a
        // part, only disk space. One whose process still runs on this machine is left alone.
        if (const pid_t owner = tempFileOwner(name, path_.filename().string());
            owner > 0 && ::kill(owner, 0) != 0 && errno == ESRCH) {
            std::error_code removeError;
            if (fs::remove(e.path(), removeError))
                spdlog::info("{}: temporary file of an interrupted write (process {} is gone): removed",
                             e.path().string(), owner);
            continue;
        }
        if (const auto n = partNumber(name, prefix))
            found.emplace_back(*n, path_.has_parent_path() ? e.path() : fs::path(name));
    }
    std::sort(found.begin(), found.end());
    for (const auto& [n, part] : found) {
        const std::vector<std::uint32_t> indices = sameBakeIndices(part, params_, probes);
        nextPart_ = std::max(nextPart_, n + 1);
        if (!indices.empty() && std::all_of(indices.begin(), indices.end(), [&](std::uint32_t i) { return inOutput.count(i); })) {
            spdlog::info("{}: already merged into {} (an earlier finish was interrupted): removed", part.string(),
                         path_.string());
            fs::remove(part);
            continue;
        }
        for (const std::uint32_t index : indices)
            if (!stored_.insert(index).second)
                throw Error(part.string() + ": holds probe index " + std::to_string(index) +
                            ", which the cache or an earlier part holds too; " + kStartOver + " and its parts");
        parts_.push_back(part);
    }
}

BakeCacheWriter::~BakeCacheWriter() {
    if (pending_.empty()) return;
    try {
        flush();
    } catch (const std::exception& e) {
        spdlog::error("{}: could not save the {} probes baked since the last batch: {}", path_.string(),
                      pending_.size(), e.what());
    }
}

void BakeCacheWriter::add(ProbeRecord probe) {
    if (has(probe.index))
        throw Error(path_.string() + ": probe index " + std::to_string(probe.index) + " baked twice");
    stored_.insert(probe.index);
    if (pending_.empty()) oldestPending_ = std::chrono::steady_clock::now();
    pending_.push_back(std::move(probe));
    const double waited = std::chrono::duration<double>(std::chrono::steady_clock::now() - oldestPending_).count();
    if (pending_.size() >= options_.batchProbes || waited >= options_.batchSeconds) flush();
}

void BakeCacheWriter::finish() {
    if (!pending_.empty()) flush();
    std::error_code ec;
    const bool haveOutput = fs::exists(path_, ec);
    if (parts_.empty()) {
        if (!haveOutput) writeCache(path_, params_, std::vector<ProbeRecord>{});
        return;
    }
    const auto start = std::chrono::steady_clock::now();
    std::vector<fs::path> inputs;
    if (haveOutput) inputs.push_back(path_);
    inputs.insert(inputs.end(), parts_.begin(), parts_.end());
    mergeCaches(path_, inputs);  // atomic; until its rename the output and the parts are as they were
    for (const fs::path& part : parts_) fs::remove(part, ec);  // a leftover is removed by the next run
    parts_.clear();
    mergeMs_ += msSince(start);
}

// One batch, one part file: O(batch), however many probes the output and earlier parts hold.
void BakeCacheWriter::flush() {
    const auto start = std::chrono::steady_clock::now();
    const fs::path part = partPath(path_, nextPart_);
    writeCache(part, params_, pending_);
    ++nextPart_;
    parts_.push_back(part);
    pending_.clear();
    ++appends_;
    writeMs_ += msSince(start);
}

}  // namespace cubeao
