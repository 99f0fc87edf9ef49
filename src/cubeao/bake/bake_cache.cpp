#include "cubeao/bake/bake_cache.h"

#include <cstdio>
#include <memory>
#include <string>
#include <system_error>

#include <spdlog/spdlog.h>

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

BakeCacheWriter::BakeCacheWriter(fs::path path, const CacheParams& params, std::span<const ProbeSpec> probes,
                                 Options options)
    : path_(std::move(path)), params_(params), options_(options) {
    std::error_code ec;
    const fs::file_status status = fs::status(path_, ec);
    if (status.type() == fs::file_type::directory)
        throw Error(path_.string() + ": --out is a directory; bake now writes one .cubeao cache file (" +
                    "e.g. --out " + (path_ / "probes.cubeao").string() + ")");
    if (status.type() == fs::file_type::not_found) return;

    std::unique_ptr<CacheReader> cache;
    try {
        cache = std::make_unique<CacheReader>(path_);
    } catch (const Error& e) {
        throw Error(std::string(e.what()) + " (--out exists and is not a readable cache: " + kStartOver + ")");
    }
    if (const auto d = cacheParamDifferences(cache->params(), params); !d.empty()) {
        std::string list;
        for (const auto& x : d) list += (list.empty() ? "" : ", ") + x;
        throw Error(path_.string() + ": exists with other bake parameters (cache vs this bake: " + list + "); " +
                    kStartOver);
    }
    for (std::size_t i = 0; i < cache->probeCount(); ++i) {
        const std::uint32_t index = cache->index(i);
        const glm::vec3 cached = cache->position(i);
        if (index >= probes.size() || probes[index].position != cached)
            throw Error(path_.string() + ": holds probe index " + std::to_string(index) + " at " + vecText(cached) +
                        (index < probes.size() ? ", the probe set puts it at " + vecText(probes[index].position)
                                               : ", the probe set has " + std::to_string(probes.size()) + " probes") +
                        ": the probe set changed; " + kStartOver);
        stored_.insert(index);
    }
    atStart_ = cache->probeCount();
}

BakeCacheWriter::~BakeCacheWriter() {
    if (pending_.empty()) return;
    try {
        flush();
    } catch (const std::exception& e) {
        spdlog::error("{}: could not save the {} probes baked since the last append: {}", path_.string(),
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
    std::error_code ec;
    if (pending_.empty() && fs::exists(path_, ec)) return;
    flush();  // appendToCache creates the file, empty or not
}

void BakeCacheWriter::flush() {
    const auto start = std::chrono::steady_clock::now();
    appendToCache(path_, params_, pending_);
    pending_.clear();
    ++appends_;
    writeMs_ += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace cubeao
