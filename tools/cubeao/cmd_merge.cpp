// cubeao merge OUT.cubeao IN.cubeao... [--probes probes.json [--shards N]] [--ao bc4|bc5]: one cache from
// caches baked in shards (`bake --shard I/N`), written atomically (DESIGN.md §5). The inputs must share
// scene and bake parameters and no probe may occur twice (cache/cache_file.h mergeCaches); OUT may be
// one of the inputs. The AO format alone may differ: OUT has --ao's (default: the first input's) and
// the others are converted, so `merge OUT IN --ao bc4` turns a traced BC5 cache into BC4 (lossless).
// With --probes the inputs must also hold exactly the probe set's probes, at its positions: a cluster bake
// (tools/slurm/) merges whatever shards exist, and a shard that failed must end in a refusal naming what
// is missing, not in a cache that quietly lacks probes.
#include <algorithm>
#include <cstdio>
#include <optional>
#include <set>

#include "commands.h"
#include "cubeao/placement/probe_set.h"
#include "cubeao/cache/cache_file.h"
#include "cubeao/core/error.h"
#include "cubeao/core/progress.h"

namespace cubeao::cli {
namespace {

struct MergeArgs {
    std::string out;
    std::vector<std::string> inputs;
    std::string probes;
    std::string ao;          // empty: the first input's AO format
    std::size_t shards = 0;  // 0: not given
    std::uint32_t levels = 0;  // 0: the first input's
    bool json = false;
};

constexpr std::size_t kListedIndices = 20;  // a refusal lists this many indices, then "..."

std::string vecText(const glm::vec3& v) {
    char buf[96];
    std::snprintf(buf, sizeof buf, "(%.9g, %.9g, %.9g)", v.x, v.y, v.z);
    return buf;
}

// "2, 6, 10", at most kListedIndices of them, then "...". `denominator` > 0: "2/4, 6/4" (shards).
std::string indexList(const std::vector<std::size_t>& indices, std::size_t denominator = 0) {
    std::string s;
    for (std::size_t k = 0; k < indices.size() && k < kListedIndices; ++k)
        s += (k ? ", " : "") + std::to_string(indices[k]) + (denominator ? "/" + std::to_string(denominator) : "");
    if (indices.size() > kListedIndices) s += ", ...";
    return s;
}

// Throws cubeao::Error unless the inputs hold exactly the probes of --probes: every index
// 0..count-1 once, none outside, each at its probes.json position. Reads only headers and tables.
void checkComplete(const MergeArgs& a, const std::vector<CacheReader>& caches) {
    // Positions in the caches are relative to the scene's origin (CacheParams::origin), read here as bake
    // reads them (probe_set.h), so equal probes compare equal bit for bit. Inputs with other parameters
    // are refused by mergeCaches, naming the difference.
    const std::vector<ProbeSpec> set = readProbeSet(a.probes, glm::dvec3(caches.front().params().origin));
    std::vector<bool> present(set.size(), false);
    std::vector<std::string> problems;
    for (const CacheReader& cache : caches) {
        for (std::size_t i = 0; i < cache.probeCount(); ++i) {
            const std::uint32_t index = cache.index(i);
            if (index >= set.size()) {
                problems.push_back(cache.path().string() + ": probe " + std::to_string(index) + " is not in " +
                                   a.probes + " (" + std::to_string(set.size()) + " probes)");
                continue;
            }
            present[index] = true;
            if (cache.position(i) != set[index].position)
                problems.push_back(cache.path().string() + ": probe " + std::to_string(index) + " at " +
                                   vecText(cache.position(i)) + ", " + a.probes + " has it at " +
                                   vecText(set[index].position) + " (baked from another probe set?)");
        }
    }
    std::vector<std::size_t> missing;
    for (std::size_t i = 0; i < present.size(); ++i)
        if (!present[i]) missing.push_back(i);
    if (!missing.empty()) {
        std::string msg = "incomplete: " + std::to_string(missing.size()) + " of " + std::to_string(set.size()) +
                          " probes missing: " + indexList(missing);
        if (a.shards > 0) {
            std::set<std::size_t> shardSet;
            for (std::size_t i : missing) shardSet.insert(i % a.shards);
            const std::vector<std::size_t> shards(shardSet.begin(), shardSet.end());
            msg += " (shard" + std::string(shards.size() > 1 ? "s " : " ") + indexList(shards, a.shards) + ")";
        }
        problems.insert(problems.begin(), msg);
    }
    if (problems.empty()) return;
    std::string msg = "merge: " + problems.front();
    const std::size_t shown = std::min<std::size_t>(problems.size(), kListedIndices);
    for (std::size_t k = 1; k < shown; ++k) msg += "\n  " + problems[k];
    if (problems.size() > shown) msg += "\n  ... (" + std::to_string(problems.size() - shown) + " more)";
    throw Error(msg + "\n  " + a.out + " not written");
}

void run(const MergeArgs& a) {
    if (a.shards > 0 && a.probes.empty()) throw UsageError("merge: --shards needs --probes");
    const std::optional<AoFormat> ao = a.ao.empty() ? std::nullopt : std::optional(parseAoFormat(a.ao));
    std::size_t total = 0;  // for the progress: the inputs' probes (headers only; checked again in the merge)
    {
        std::vector<CacheReader> caches;
        for (const std::string& in : a.inputs) {
            caches.emplace_back(in);
            total += caches.back().probeCount();
        }
        if (!a.probes.empty()) checkComplete(a, caches);
    }  // unmapped before the merge, which may replace one of them
    {
        Progress progress("merge", total, "probes");
        WriteOptions options;
        options.progress = &progress;
        mergeCaches(a.out, std::vector<std::filesystem::path>(a.inputs.begin(), a.inputs.end()), options, ao,
                    a.levels > 0 ? std::optional<std::uint32_t>(a.levels) : std::nullopt);
    }
    const CacheReader merged(a.out);
    std::printf("merge: %zu caches, %zu probes -> %s (%s AO, %.4f bytes per texel)\n", a.inputs.size(),
                merged.probeCount(), a.out.c_str(), aoFormatName(merged.params().aoFormat), merged.bytesPerTexel());
    if (a.json)
        printJson({{"probes", merged.probeCount()},
                   {"out", a.out},
                   {"inputs", a.inputs},
                   {"complete", !a.probes.empty()},
                   {"ao_format", aoFormatName(merged.params().aoFormat)},
                   {"levels", merged.params().levels},
                   {"bytes_per_texel", merged.bytesPerTexel()},
                   {"file_bytes", merged.fileSize()}});
}

}  // namespace

void addMerge(CLI::App& app) {
    auto* cmd = app.add_subcommand("merge", "Merge probe caches baked in shards into one");
    auto a = std::make_shared<MergeArgs>();
    cmd->add_option("out", a->out, "Cache to write (.cubeao; may be one of the inputs)")->required();
    cmd->add_option("inputs", a->inputs, "Caches to merge, in order")->required();
    cmd->add_option("--probes", a->probes,
                    "probes.json the shards were baked from: refuse (exit 1, OUT untouched) unless the inputs hold "
                    "exactly its probes, naming the missing ones");
    cmd->add_option("--shards", a->shards, "N of the shards' --shard I/N: a refusal also names the shards (I/N) "
                                           "with missing probes")
        ->check(CLI::PositiveNumber);
    cmd->add_option("--levels", a->levels,
                    "Levels of detail OUT keeps, the finest first (default: the first input's; inputs may have "
                    "more, not fewer: levels come from a bake's full-resolution data)")
        ->check(CLI::PositiveNumber);
    cmd->add_option("--ao", a->ao, "AO format of OUT: bc4 (AO alone; traced caches) | bc5 (AO + confidence); "
                                   "inputs in the other are converted (default: the first input's)");
    cmd->add_flag("--json", a->json, "Print one JSON object as the last line");
    cmd->callback([a] { run(*a); });
}

}  // namespace cubeao::cli
