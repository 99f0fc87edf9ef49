// cubeao export CACHE.cubeao --format dds|ktx2 --out DIR [--ao bc5|bc4] [--distance native|float] [--json]:
// every probe of a cache as two cube-map files engines and texture tools read directly (issue 17), AO
// (+ confidence) and the distance cube, plus DIR/manifest.json: what each file holds, where each probe
// is in file coordinates, and the bake parameters. The BC blocks are copied, never re-encoded, and
// need no flip or reorder (cache/texture_export.h says why).
//
// Nothing half-written is left behind: every file is written to a hidden temporary file beside its
// target (core/durable_file.h; removed on any failure), fsynced, and only when all of them are
// complete renamed into DIR, manifest.json last. A DIR with a manifest therefore holds every file the
// manifest names; files of an earlier export into DIR are replaced one by one, each atomically.
#include <cstdio>
#include <deque>
#include <optional>
#include <filesystem>
#include <fstream>
#include <memory>

#include "cache_json.h"
#include "cli_util.h"
#include "commands.h"
#include "cubeao/bake/bake_settings.h"
#include "cubeao/cache/cache_file.h"
#include "cubeao/cache/texture_export.h"
#include "cubeao/core/durable_file.h"
#include "cubeao/core/error.h"
#include "cubeao/core/falloff.h"
#include "cubeao/core/progress.h"
#include "cubeao/scene/scene.h"

namespace cubeao::cli {
namespace {

namespace fs = std::filesystem;
using texport::TexelFormat;

constexpr int kManifestVersion = 1;
// The manifest keeps the order fields are written in (nlohmann::json would sort them).
using Ordered = nlohmann::ordered_json;

struct ExportArgs {
    std::string cache, format = "dds", out, ao, distance = "native";  // ao empty: the cache's
    bool json = false;
};

// The files of one export: each written and fsynced through a DurableFile (its hidden temporary name
// beside its target in DIR), and renamed into place only when all of them are complete.
class Staging {
public:
    explicit Staging(const fs::path& dir) : dir_(dir) {
        std::error_code ec;
        if (fs::exists(dir, ec) && !fs::is_directory(dir, ec))
            throw Error(dir.string() + ": cannot export there: it exists and is not a directory");
        createdDir_ = fs::create_directories(dir, ec);
        if (ec) throw Error(dir.string() + ": cannot create the output directory: " + ec.message());
    }
    ~Staging() {
        files_.clear();  // removes the temporary files of an export that did not commit
        std::error_code ec;
        if (!committed_ && createdDir_) fs::remove(dir_, ec);  // only when empty: remove() refuses otherwise
    }
    Staging(const Staging&) = delete;
    Staging& operator=(const Staging&) = delete;

    // Writes `name`: complete and fsynced, not yet visible, or an Error naming it.
    void write(const std::string& name, std::span<const std::uint8_t> bytes) {
        DurableFile& file = files_.emplace_back(dir_ / name, "export file");
        file.write(std::as_bytes(bytes));
        file.finish();
        bytes_ += bytes.size();
    }

    // Renames every staged file into DIR in the order written (the manifest last), then syncs DIR.
    void commit() {
        for (DurableFile& file : files_) file.publish();
        committed_ = true;
        syncDirectoryOf(dir_ / "manifest.json");
    }

    std::uint64_t bytes() const { return bytes_; }

private:
    fs::path dir_;
    std::deque<DurableFile> files_;
    std::uint64_t bytes_ = 0;
    bool createdDir_ = false, committed_ = false;
};

// The trailing XXH3-64 of the cache (docs/FORMAT.md "File checksum"), after verifyAll() matched it.
std::uint64_t fileChecksum(const CacheReader& cache) {
    std::ifstream in(cache.path(), std::ios::binary);
    in.seekg(std::streamoff(cache.fileSize() - 8));
    std::uint8_t b[8] = {};
    in.read(reinterpret_cast<char*>(b), 8);
    if (in.gcount() != 8) throw Error(cache.path().string() + ": cannot read the file checksum");
    std::uint64_t v = 0;
    for (int k = 7; k >= 0; --k) v = v << 8 | b[k];
    return v;
}

Ordered formatJson(TexelFormat f, std::uint32_t res) {
    const texport::FormatCodes& c = texport::formatCodes(f);
    return {{"format", c.name}, {"dxgi_format", c.dxgi}, {"vk_format", c.vk}, {"res", res}};
}

// manifest.json: the source cache (checksummed), the cube convention, both textures' formats and how to
// decode them, the bake's parameters, and each probe's files.
Ordered exportManifest(const std::string& container, const std::string& cacheFile, const CacheReader& cache,
                       TexelFormat aoFormat, TexelFormat distanceFormat, Ordered probes) {
    const CacheParams& p = cache.params();
    Ordered distance = formatJson(distanceFormat, p.depthRes);
    if (distanceFormat == TexelFormat::R16Unorm) {
        distance["units"] = "max_distance";
        distance["decode"] = "distance = value / 65535 * max_distance of the probe (world units); 0: nothing there";
    } else {
        distance["units"] = "world";
        distance["decode"] = "distance in world units; 0: nothing there";
    }
    distance["filter"] = "each texel: the nearest non-empty distance of the res/depth_res square of AO texels it covers";
    Ordered ao = formatJson(aoFormat, p.res);
    ao["channels"] = aoFormat == TexelFormat::Bc5Unorm ? Ordered{{"r", "ao, 1 = open"}, {"g", "confidence"}}
                                                       : Ordered{{"r", "ao, 1 = open"}};
    Ordered bake = bakeParamsJson<Ordered>(p);
    bake["origin"] = {p.origin.x, p.origin.y, p.origin.z};
    return {
        {"cubeao_export", kManifestVersion},
        {"container", container},
        {"source",
         {{"cache", fs::absolute(cacheFile).lexically_normal().string()},
          {"format_version", cache.formatVersion()},
          {"file_bytes", cache.fileSize()},
          {"file_checksum", hashToString(fileChecksum(cache))},
          {"checksum_algorithm", "XXH3-64 of every byte before the last 8 (docs/FORMAT.md)"},
          {"scene_hash", hashToString(p.sceneHash)}}},
        {"cube",
         {{"faces", {"+x", "-x", "+y", "-y", "+z", "-z"}},
          {"orientation", "GL/D3D/Vulkan cube map convention: sample with the direction from the probe, world axes, "
                          "no flip"},
          {"mip_levels", 1}}},
        {"ao", ao},
        {"distance", distance},
        {"bake", bake},
        {"probes", std::move(probes)}};
}

void run(const ExportArgs& a) {
    // Command line first, before any file is opened.
    if (a.format != "dds" && a.format != "ktx2")
        throw UsageError("--format \"" + a.format + "\": expected dds or ktx2");
    const std::optional<AoFormat> asked = a.ao.empty() ? std::nullopt : std::optional(parseAoFormat(a.ao));
    if (a.distance != "native" && a.distance != "float")
        throw UsageError("--distance \"" + a.distance + "\": expected native or float");
    if (a.out.empty()) throw UsageError("--out: an output directory is required");

    const CacheReader cache(a.cache);
    cache.verifyAll();  // never export damaged blocks; and the checksum the manifest quotes is then the file's
    const CacheParams& p = cache.params();
    const AoFormat exported = asked.value_or(p.aoFormat);
    const TexelFormat aoFormat = exported == AoFormat::Bc4 ? TexelFormat::Bc4Unorm : TexelFormat::Bc5Unorm;
    const bool floatDistance = a.distance == "float";
    const TexelFormat distanceFormat = floatDistance ? TexelFormat::R32Float : texport::texelFormatOf(p.depthFormat);
    const bool ktx2 = a.format == "ktx2";
    const std::string ext = ktx2 ? ".ktx2" : ".dds";
    const std::string writer = "cubeao export";
    const auto file = [&](TexelFormat f, std::uint32_t res, std::span<const std::uint8_t> faces) {
        return ktx2 ? texport::ktx2File(f, res, faces, writer) : texport::ddsFile(f, res, faces);
    };

    Staging staging(a.out);
    Ordered probes = Ordered::array();
    Progress progress("export", cache.probeCount(), "probes");
    for (std::size_t i = 0; i < cache.probeCount(); ++i) {
        const ProbeView v = levelView(cache.probe(i), p, 0);  // the finest level (a cache's levels are not exported)
        char stem[32];
        std::snprintf(stem, sizeof stem, "probe_%04u", v.index);
        const std::string aoName = stem + ("_ao" + ext), distanceName = stem + ("_distance" + ext);
        if (floatDistance)
            staging.write(distanceName, file(distanceFormat, p.depthRes,
                                             texport::distancesAsFloat(v.depth, p.depthRes, p.depthFormat,
                                                                       v.maxDistance)));
        else
            staging.write(distanceName, file(distanceFormat, p.depthRes, v.depth));
        staging.write(aoName, file(aoFormat, p.res, convertAoSection(v.aoConfidence, p.res, v.aoFormat, exported)));
        // File coordinates in double (docs/FORMAT.md: position + origin), as probes.json has them.
        const glm::dvec3 pos = glm::dvec3(v.position) + glm::dvec3(p.origin);
        probes.push_back({{"id", v.index},
                          {"position", {pos.x, pos.y, pos.z}},
                          {"max_distance", v.maxDistance},
                          {"ao", aoName},
                          {"distance", distanceName}});
        progress.advance();
    }

    const Ordered manifest = exportManifest(a.format, a.cache, cache, aoFormat, distanceFormat, std::move(probes));
    const std::string text = manifest.dump(2) + "\n";
    staging.write("manifest.json", std::span(reinterpret_cast<const std::uint8_t*>(text.data()), text.size()));
    staging.commit();

    const std::size_t files = 2 * cache.probeCount() + 1;
    std::printf("export: %zu probes -> %s (%s: %s %u² AO, %s %u² distance), %zu files, %llu bytes\n",
                cache.probeCount(), a.out.c_str(), a.format.c_str(), texport::formatCodes(aoFormat).name, p.res,
                texport::formatCodes(distanceFormat).name, p.depthRes, files, (unsigned long long)staging.bytes());
    if (a.json)
        printJson({{"probes", cache.probeCount()},
                   {"out", a.out},
                   {"manifest", (fs::path(a.out) / "manifest.json").string()},
                   {"format", a.format},
                   {"ao_format", texport::formatCodes(aoFormat).name},
                   {"distance_format", texport::formatCodes(distanceFormat).name},
                   {"files", files},
                   {"bytes", staging.bytes()}});
}

}  // namespace

void addExport(CLI::App& app) {
    auto* cmd = app.add_subcommand("export", "Write every probe of a cache as DDS or KTX2 cube maps + manifest.json");
    auto a = std::make_shared<ExportArgs>();
    cmd->add_option("cache", a->cache, "Probe cache (.cubeao)")->required();
    cmd->add_option("--format", a->format, "dds (DX10 header) or ktx2")->capture_default_str();
    cmd->add_option("--out", a->out, "Output directory (created if missing)")->required();
    cmd->add_option("--ao", a->ao, "bc5: AO + confidence (1 for a BC4 cache); bc4: AO only (default: as cached)");
    cmd->add_option("--distance", a->distance,
                    "native: the cache's texels as they are (r16unorm: fraction of max_distance); "
                    "float: R32_FLOAT world units")
        ->capture_default_str();
    cmd->add_flag("--json", a->json, "Print one JSON object as the last line");
    cmd->callback([a] { run(*a); });
}

}  // namespace cubeao::cli
