// Where a bake's probes go (the sink of the bake driver, bake_driver.h): a .cubeao cache (DESIGN.md
// §5 "Cache file") written in batches, or memory (tests, benches).
//
// BakeCacheWriter writes each batch as its own small cache beside the output, a part file
// `OUT.part-NNNNNN` (atomic: temporary file, fsync, rename), and merges the output and its parts once,
// in finish() (docs/FORMAT.md "Appending"). So a batch costs in proportion to the batch, not to the
// probes baked before it; an interrupted bake loses at most the batch in progress and leaves every
// earlier batch on disk; and the next run with the same parameters resumes: the probes whose index
// is already in the output or in one of its parts are skipped, and its finish() merges them all.
#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <set>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

#include "cubeao/cache/cache_file.h"

namespace cubeao {

class ProbeSink {
public:
    virtual ~ProbeSink() = default;
    // Whether probe `index` is stored already (so the bake skips it).
    virtual bool has(std::uint32_t index) const = 0;
    virtual void add(ProbeRecord probe) = 0;
};

// Keeps every probe in `records`, in the order added.
class MemoryProbeSink final : public ProbeSink {
public:
    bool has(std::uint32_t index) const override { return indices_.count(index) != 0; }
    void add(ProbeRecord probe) override;
    std::vector<ProbeRecord> records;

private:
    std::set<std::uint32_t> indices_;
};

class BakeCacheWriter final : public ProbeSink {
public:
    struct Options {
        // A batch is written when it holds this many probes or its oldest probe waited this long,
        // whichever comes first: each batch is a file (fsync, rename), so not per probe.
        std::size_t batchProbes = 16;
        double batchSeconds = 30.0;
    };

    // Plans a bake of `probes` (probe i of the set has index i) into `path`. An existing cache and
    // its part files must have exactly `params` (scene hash included) and hold each of their indices
    // at the position the probe set gives it; otherwise, or when `path` is a directory or not a
    // cache, Error says what differs and to choose another output or delete the file. Parts whose
    // probes are all in `path` already (left by a finish() interrupted after its rename) are removed,
    // and so are the temporary files of a write that was killed before its rename (".NAME.tmp-PID-…",
    // PID no longer running). Nothing is written yet.
    BakeCacheWriter(std::filesystem::path path, const CacheParams& params, std::span<const glm::vec3> probes,
                    Options options);
    BakeCacheWriter(std::filesystem::path path, const CacheParams& params, std::span<const glm::vec3> probes)
        : BakeCacheWriter(std::move(path), params, probes, Options{}) {}
    // Writes what is pending as a part if finish() was not reached (an exception while baking), so
    // the probes already baked are kept for the next run; errors are swallowed (the first one is
    // already propagating).
    ~BakeCacheWriter() override;
    BakeCacheWriter(const BakeCacheWriter&) = delete;
    BakeCacheWriter& operator=(const BakeCacheWriter&) = delete;

    bool has(std::uint32_t index) const override { return stored_.count(index) != 0; }
    std::size_t probesAtStart() const { return atStart_; }

    // Queues a baked probe; writes the batch as a part when it is due.
    void add(ProbeRecord probe) override;
    // Writes what is pending, then merges the output and every part into the output, sorted by
    // probe index (mergeCaches: the file an unsharded bake in one run writes), and removes the
    // parts. Creates an empty cache when there is nothing at all (a shard with no probes still yields
    // a file `merge` accepts); leaves the output untouched when no part was written.
    void finish();

    // Part file `n` of the cache `path`: "PATH.part-NNNNNN".
    static std::filesystem::path partPath(const std::filesystem::path& path, std::size_t n);
    const std::vector<std::filesystem::path>& parts() const { return parts_; }

    std::size_t appends() const { return appends_; }  // batches written by this writer
    double writeMs() const { return writeMs_; }       // time spent writing batches
    double mergeMs() const { return mergeMs_; }       // time finish() spent merging

private:
    void flush();
    void adoptParts(std::span<const glm::vec3> probes, const std::set<std::uint32_t>& inOutput);

    std::filesystem::path path_;
    CacheParams params_;
    Options options_;
    std::set<std::uint32_t> stored_;             // indices in the output or a part, or queued
    std::vector<std::filesystem::path> parts_;   // existing part files, in number order
    std::size_t nextPart_ = 0;
    std::size_t atStart_ = 0, appends_ = 0;
    std::vector<ProbeRecord> pending_;
    std::chrono::steady_clock::time_point oldestPending_;
    double writeMs_ = 0.0, mergeMs_ = 0.0;
};

}  // namespace cubeao
