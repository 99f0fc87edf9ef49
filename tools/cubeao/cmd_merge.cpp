// cubeao merge OUT.cubeao IN.cubeao...: one cache from caches baked in shards (`bake --shard I/N`),
// written atomically (DESIGN.md §5). The inputs must share scene and bake parameters and no probe may
// occur twice (cache/cache_file.h mergeCaches); OUT may be one of the inputs.
#include <cstdio>

#include "commands.h"
#include "cubeao/cache/cache_file.h"
#include "cubeao/core/progress.h"

namespace cubeao::cli {
namespace {

struct MergeArgs {
    std::string out;
    std::vector<std::string> inputs;
    bool json = false;
};

void run(const MergeArgs& a) {
    std::size_t total = 0;  // for the progress: the inputs' probes (headers only; checked again in the merge)
    for (const std::string& in : a.inputs) total += CacheReader(in).probeCount();
    {
        Progress progress("merge", total, "probes");
        WriteOptions options;
        options.progress = &progress;
        mergeCaches(a.out, std::vector<std::filesystem::path>(a.inputs.begin(), a.inputs.end()), options);
    }
    const CacheReader merged(a.out);
    std::printf("merge: %zu caches, %zu probes -> %s (%.4f bytes per texel)\n", a.inputs.size(), merged.probeCount(),
                a.out.c_str(), merged.bytesPerTexel());
    if (a.json)
        printJson({{"probes", merged.probeCount()},
                   {"out", a.out},
                   {"inputs", a.inputs},
                   {"bytes_per_texel", merged.bytesPerTexel()},
                   {"file_bytes", merged.fileSize()}});
}

}  // namespace

void addMerge(CLI::App& app) {
    auto* cmd = app.add_subcommand("merge", "Merge probe caches baked in shards into one");
    auto a = std::make_shared<MergeArgs>();
    cmd->add_option("out", a->out, "Cache to write (.cubeao; may be one of the inputs)")->required();
    cmd->add_option("inputs", a->inputs, "Caches to merge, in order")->required();
    cmd->add_flag("--json", a->json, "Print one JSON object as the last line");
    cmd->callback([a] { run(*a); });
}

}  // namespace cubeao::cli
