// Where a bake's probes go (DESIGN.md §5 "Cache file"): a .cubeao cache that the bake appends to in
// batches, each an atomic rewrite (docs/FORMAT.md "Appending"), so an interrupted bake loses at most
// the batch in progress and leaves the previous cache intact, and the next run with the same
// parameters resumes: probes whose index is already in the cache are skipped.
#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <set>
#include <span>
#include <vector>

#include "cubeao/bake/probe_set.h"
#include "cubeao/cache/cache_file.h"

namespace cubeao {

class BakeCacheWriter {
public:
    struct Options {
        // A batch is appended when it holds this many probes or its oldest probe waited this long,
        // whichever comes first: each append rewrites the file (O(file size)), so not per probe.
        std::size_t batchProbes = 16;
        double batchSeconds = 30.0;
    };

    // Plans a bake of `probes` (probe i of the set has index i) into `path`. An existing cache must
    // have exactly `params` (scene hash included) and hold each of its indices at the position the
    // probe set gives it; otherwise, or when `path` is a directory or not a cache, Error says what
    // differs and to choose another output or delete the file. Nothing is written yet.
    BakeCacheWriter(std::filesystem::path path, const CacheParams& params, std::span<const ProbeSpec> probes,
                    Options options);
    BakeCacheWriter(std::filesystem::path path, const CacheParams& params, std::span<const ProbeSpec> probes)
        : BakeCacheWriter(std::move(path), params, probes, Options{}) {}
    // Appends what is pending if finish() was not reached (an exception while baking), so the probes
    // already baked are kept; errors are swallowed (the first one is already propagating).
    ~BakeCacheWriter();
    BakeCacheWriter(const BakeCacheWriter&) = delete;
    BakeCacheWriter& operator=(const BakeCacheWriter&) = delete;

    // Whether probe `index` is in the cache already (so the bake skips it).
    bool has(std::uint32_t index) const { return stored_.count(index) != 0; }
    std::size_t probesAtStart() const { return atStart_; }

    // Queues a baked probe; appends the batch when it is due.
    void add(ProbeRecord probe);
    // Appends what is pending; creates an empty cache when there is no file yet (a shard with no
    // probes still yields a file `merge` accepts).
    void finish();

    std::size_t appends() const { return appends_; }
    double writeMs() const { return writeMs_; }  // time spent in appends

private:
    void flush();

    std::filesystem::path path_;
    CacheParams params_;
    Options options_;
    std::set<std::uint32_t> stored_;  // indices in the file, or queued for it
    std::size_t atStart_ = 0, appends_ = 0;
    std::vector<ProbeRecord> pending_;
    std::chrono::steady_clock::time_point oldestPending_;
    double writeMs_ = 0.0;
};

}  // namespace cubeao
