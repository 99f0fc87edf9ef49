// Appending probes to a cache and merging shards' caches: both read probes through CacheReader (their
// checksums checked, so damage is never copied under a fresh checksum) and write through writeCache.
#include <algorithm>
#include <filesystem>
#include <map>

#include "cubeao/cache/cache_codec.h"
#include "cubeao/core/error.h"

namespace cubeao {

using namespace cache_codec;

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
                 const WriteOptions& options, std::optional<AoFormat> aoFormat, std::optional<std::uint32_t> levels) {
    if (inputs.empty()) throw Error(out.string() + ": merge needs at least one input cache");
    std::vector<CacheReader> readers;
    readers.reserve(inputs.size());
    for (const auto& in : inputs) readers.emplace_back(in);
    // The output's parameters: the first input's, in the AO format asked for; each input's probes are
    // converted to it as they are written (writeCache), so inputs may differ in that alone.
    CacheParams params = readers.front().params();
    params.aoFormat = aoFormat.value_or(params.aoFormat);
    params.levels = std::uint8_t(std::min<std::uint32_t>(levels.value_or(params.levels), 255));
    if (const auto problems = cacheParamProblems(params); !problems.empty())
        throw Error(out.string() + ": cannot write " + aoFormatName(params.aoFormat) + " AO in " +
                    std::to_string(params.levels) + (params.levels == 1 ? " level" : " levels") + ": " +
                    join(problems, "; "));
    // The inputs' parameters as the output holds them: its AO format, and its levels where they have
    // at least as many (the finest come first, so fewer levels are a prefix of each section).
    const auto held = [&](CacheParams p) {
        if (p.levels < params.levels)
            throw Error(out.string() + ": cannot merge " + std::to_string(params.levels) + " levels of detail from a "
                        "cache of " + std::to_string(p.levels) + ": levels are made from the bake's full-resolution "
                        "data (bake --levels " + std::to_string(params.levels) + ")");
        p.levels = params.levels;
        return withAoFormat(p, params.aoFormat);
    };
    held(readers.front().params());
    for (std::size_t k = 1; k < readers.size(); ++k)
        if (const auto d = cacheParamDifferences(params, held(readers[k].params())); !d.empty())
            throw Error(inputs[k].string() + ": cannot merge with " + inputs[0].string() +
                        ", baked with other parameters (" + inputs[0].filename().string() + " vs this): " +
                        join(d, ", "));
    // The same position or index twice means the same probe was baked by two shards (overlapping
    // --shard ranges, or one input given twice): refuse rather than guess which copy is right.
    std::map<PositionKey, std::pair<std::size_t, std::size_t>> seen;
    std::map<std::uint32_t, std::pair<std::size_t, std::size_t>> indices;
    std::vector<ProbeView> all;
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
            ProbeView v = readers[k].probe(i);  // checks the probe's checksum: reads its payload
            pacer.read(v.aoConfidence.size() + v.depth.size());
            v.aoConfidence = v.aoConfidence.first(aoSectionSize(withAoFormat(params, v.aoFormat)));
            v.depth = v.depth.first(depthSectionSize(params));
            all.push_back(v);
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
