// cubeao bench cache: how long loading a probe cache takes, cold (file not in the page cache) and
// warm. "Load" = open (header and table checked) + every probe's sections touched and checksummed
// (CacheReader::probe), i.e. what a run time does before it uploads a probe. The cache is synthetic
// (random payload: loading does not depend on the values) at the bake's default sizes.
// Cold runs evict the file with posix_fadvise(POSIX_FADV_DONTNEED) after an fsync, which needs no
// privileges (drop_caches does), and report with mincore how much of the file was still resident,
// so a "cold" figure that was not cold shows.
#include <fcntl.h>
#include <sys/mman.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <random>

#include "cli_util.h"
#include "commands.h"
#include "cubeao/cache/cache_file.h"
#include "cubeao/cache/depth_cube.h"
#include "cubeao/core/error.h"

namespace cubeao::cli {
namespace {

namespace fs = std::filesystem;

struct CacheBenchArgs {
    int probes = 200, res = 512, runs = 3;
    std::string out;
    bool keep = false, json = false;
};

template <class F>
double timeMs(F&& f) {
    const auto start = std::chrono::steady_clock::now();
    f();
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

// Fraction of the file's pages in the page cache (mincore on a fresh mapping).
double residentFraction(const fs::path& path) {
    const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0) return -1.0;
    const std::size_t size = fs::file_size(path), page = std::size_t(::sysconf(_SC_PAGESIZE));
    void* m = ::mmap(nullptr, size, PROT_READ, MAP_SHARED, fd, 0);
    ::close(fd);
    if (m == MAP_FAILED) return -1.0;
    std::vector<unsigned char> pages((size + page - 1) / page);
    double fraction = -1.0;
    if (::mincore(m, size, pages.data()) == 0)
        fraction = double(std::count_if(pages.begin(), pages.end(), [](unsigned char c) { return c & 1; })) /
                   double(pages.size());
    ::munmap(m, size);
    return fraction;
}

void evict(const fs::path& path) {
    const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0) throw Error(path.string() + ": cannot open to evict from the page cache");
    ::fdatasync(fd);
    ::posix_fadvise(fd, 0, 0, POSIX_FADV_DONTNEED);
    ::close(fd);
}

struct LoadTime {
    double openMs = 0.0, readMs = 0.0, resident = 0.0;
};

LoadTime load(const fs::path& path, bool cold) {
    if (cold) evict(path);
    LoadTime t;
    t.resident = residentFraction(path);
    std::unique_ptr<CacheReader> cache;
    t.openMs = timeMs([&] { cache = std::make_unique<CacheReader>(path); });
    t.readMs = timeMs([&] {
        for (std::size_t i = 0; i < cache->probeCount(); ++i) cache->probe(i);  // checksum: every byte read
    });
    return t;
}

void run(const CacheBenchArgs& a) {
    checkRange("--probes", a.probes, 1, 1'000'000);
    checkRange("--res", a.res, 4, 4096);
    if (a.res % 4 != 0) throw UsageError("--res must be a multiple of 4 (BC5 blocks; got " + std::to_string(a.res) + ")");
    checkRange("--runs", a.runs, 1, 1000);
    CacheParams p;
    p.sceneHash = 1;
    p.res = std::uint32_t(a.res);
    p.depthRes = std::uint32_t(depth::depthResFor(a.res));
    p.depthFormat = depth::kDefaultFormat;
    p.radius = 1.0f;
    // The probes are made in memory before they are written: bound the whole before any is allocated.
    constexpr std::uint64_t kMaxBytes = std::uint64_t(4) << 30;
    if (const std::uint64_t bytes = cacheFileSize(p, std::uint64_t(a.probes)); bytes > kMaxBytes)
        throw UsageError("--probes " + std::to_string(a.probes) + " at --res " + std::to_string(a.res) + " make a " +
                         std::to_string(bytes >> 20) + " MiB cache: at most 4096 MiB (fewer probes or a lower --res)");
    const fs::path path = a.out.empty() ? fs::temp_directory_path() / "cubeao-bench-cache.cubeao" : fs::path(a.out);
    std::vector<ProbeRecord> probes(std::size_t(a.probes));
    std::mt19937_64 rng(1);
    for (std::size_t i = 0; i < probes.size(); ++i) {
        probes[i] = {std::uint32_t(i), {float(i), 0.0f, 0.0f}, 10.0f, std::vector<std::uint8_t>(aoSectionSize(p)),
                     std::vector<std::uint8_t>(depthSectionSize(p))};
        for (auto* v : {&probes[i].aoConfidence, &probes[i].depth})
            for (auto& b : *v) b = std::uint8_t(rng());
    }
    const double writeMs = timeMs([&] { writeCache(path, p, probes); });
    probes.clear();
    std::vector<LoadTime> cold, warm;
    for (int r = 0; r < a.runs; ++r) {
        cold.push_back(load(path, true));
        warm.push_back(load(path, false));
    }
    const auto median = [](std::vector<LoadTime> v, double LoadTime::*field) {
        std::sort(v.begin(), v.end(), [&](const LoadTime& x, const LoadTime& y) { return x.*field < y.*field; });
        return v[v.size() / 2].*field;
    };
    const CacheReader cache(path);
    std::printf("%d probes at %d² (depth %u² %s): %.1f MB, %.4f bytes/texel, written in %.0f ms (atomic, fsync)\n",
                a.probes, a.res, p.depthRes, depthFormatName(p.depthFormat), double(cache.fileSize()) / 1e6,
                cache.bytesPerTexel(), writeMs);
    nlohmann::json result = {{"bench", "cache"}, {"probes", a.probes}, {"res", a.res}, {"file_bytes", cache.fileSize()},
                             {"bytes_per_texel", cache.bytesPerTexel()}, {"write_ms", writeMs}, {"runs", a.runs}};
    for (auto [name, runs] : {std::pair{"cold", &cold}, std::pair{"warm", &warm}}) {
        const double open = median(*runs, &LoadTime::openMs), read = median(*runs, &LoadTime::readMs);
        const double resident = median(*runs, &LoadTime::resident);
        std::printf("  %s: open %.2f ms, every probe read and checksummed %.1f ms (%.0f MB/s); %.0f%% resident before\n",
                    name, open, read, double(cache.fileSize()) / 1e3 / read, 100.0 * resident);
        result[name] = {{"open_ms", open}, {"read_ms", read}, {"load_ms", open + read}, {"resident_before", resident}};
    }
    if (!a.keep) fs::remove(path);
    if (a.json) printJson(result);
}

}  // namespace

void addBenchCache(CLI::App& bench) {
    auto* cmd = bench.add_subcommand("cache", "Probe cache: load time cold and warm");
    auto a = std::make_shared<CacheBenchArgs>();
    cmd->add_option("--probes", a->probes, "Probes in the cache")->capture_default_str();
    cmd->add_option("--res", a->res, "Face resolution")->capture_default_str();
    cmd->add_option("--runs", a->runs, "Cold and warm loads each (median reported)")->capture_default_str();
    cmd->add_option("--out", a->out, "Where to write the cache (default: the temp directory)");
    cmd->add_flag("--keep", a->keep, "Keep the cache file");
    cmd->add_flag("--json", a->json, "Print one JSON object as the last line");
    cmd->callback([a] { run(*a); });
}

}  // namespace cubeao::cli
