// cubeao info SCENE|CACHE.cubeao [--verify] [--json]: for a scene, what was loaded and what was
// repaired; for a probe cache (DESIGN.md §5: recognised by its .cubeao extension or its magic), the
// probes, resolutions and bake parameters, and with --verify every checksum (exit 1 on any damage).
#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "commands.h"
#include "cubeao/bake/bake_settings.h"
#include "cubeao/cache/cache_file.h"
#include "cubeao/core/error.h"
#include "cubeao/scene/import.h"

namespace cubeao::cli {
namespace {

namespace fs = std::filesystem;

struct InfoArgs {
    std::string target;
    bool verify = false, json = false;
};

bool isCache(const std::string& target) {
    const fs::path p(target);
    if (p.extension() == ".cubeao") return true;
    std::error_code ec;
    if (!fs::is_regular_file(p, ec)) return false;
    std::array<char, 8> head{};
    std::ifstream in(p, std::ios::binary);
    in.read(head.data(), head.size());
    return in.gcount() == 8 && std::string(head.data(), 8) == "\x89" "CUBEAO\n";
}

void sceneInfo(const InfoArgs& a) {
    if (a.verify) throw UsageError("--verify checks a cache's checksums; " + a.target + " is a scene");
    const Scene s = loadScene(a.target);
    const auto& b = s.bounds;
    std::printf("%s\n  triangles  %zu\n  vertices   %zu\n  bbox       (%g, %g, %g) -> (%g, %g, %g)\n"
                "  hash       %s\n  radius     %g (default: 2%% of the diagonal)\n"
                "  repaired   %zu zero-area triangles, %zu duplicate vertices, %zu unused vertices%s\n",
                s.source.c_str(), s.triangleCount(), s.vertexCount(), b.min.x, b.min.y, b.min.z, b.max.x,
                b.max.y, b.max.z, hashToString(s.hash).c_str(), s.defaultRadius(), s.problems.degenerateTriangles,
                s.problems.duplicateVertices, s.problems.unusedVertices,
                s.problems.normalsComputed ? "; normals computed" : "");
    if (!s.problems.warnings.empty())
        std::printf("  importer   %zu warnings (first: %s)\n", s.problems.warnings.size(),
                    s.problems.warnings.front().c_str());
    if (!a.json) return;
    printJson({{"scene", s.source},
               {"triangles", s.triangleCount()},
               {"vertices", s.vertexCount()},
               {"bbox", {{"min", {b.min.x, b.min.y, b.min.z}}, {"max", {b.max.x, b.max.y, b.max.z}}}},
               {"up", {s.up.x, s.up.y, s.up.z}},
               {"hash", hashToString(s.hash)},
               {"default_radius", s.defaultRadius()},
               {"problems", s.problems.toJson()}});
}

void cacheInfo(const InfoArgs& a) {
    const CacheReader cache(a.target);
    const CacheParams& p = cache.params();
    nlohmann::json j = {{"cache", a.target},
                        {"format_version", cache.formatVersion()},
                        {"scene_hash", hashToString(p.sceneHash)},
                        {"probes", cache.probeCount()},
                        {"res", p.res},
                        {"depth_res", p.depthRes},
                        {"depth_format", depthFormatName(p.depthFormat)},
                        {"estimator", estimatorName(Estimator(p.estimator))},
                        {"falloff", falloffName(Falloff(p.falloff))},
                        {"radius", p.radius},
                        {"spp", p.spp},
                        {"seed", p.seed},
                        {"directions", p.directions},
                        {"steps", p.steps},
                        {"hybrid_threshold", p.hybridThreshold},
                        {"bytes_per_texel", cache.bytesPerTexel()},
                        {"file_bytes", cache.fileSize()}};
    std::printf("%s: probe cache, format %u, scene %s\n  probes     %zu\n  faces      %u² AO + confidence (BC5), "
                "%u² distance (%s)\n  estimator  %s, R = %g, falloff %s, spp %u, seed %u, %u directions × %u steps\n"
                "  size       %llu bytes, %.4f bytes per AO texel\n",
                a.target.c_str(), cache.formatVersion(), hashToString(p.sceneHash).c_str(), cache.probeCount(), p.res,
                p.depthRes, depthFormatName(p.depthFormat), estimatorName(Estimator(p.estimator)), double(p.radius),
                falloffName(Falloff(p.falloff)), p.spp, p.seed, p.directions, p.steps,
                (unsigned long long)cache.fileSize(), cache.bytesPerTexel());
    if (a.verify) {
        try {
            cache.verifyAll();
        } catch (const Error& e) {
            std::printf("  verify     DAMAGED: %s\n", e.what());
            j["verified"] = false;
            j["damage"] = e.what();
            if (a.json) printJson(j);
            throw;
        }
        std::printf("  verify     every checksum matches\n");
        j["verified"] = true;
    }
    if (a.json) printJson(j);
}

}  // namespace

void addInfo(CLI::App& app) {
    auto* cmd = app.add_subcommand("info", "Describe a scene (triangles, bounding box, problems repaired on load) "
                                           "or a probe cache (probes, parameters, bytes per texel)");
    auto a = std::make_shared<InfoArgs>();
    cmd->add_option("target", a->target,
                    "Model file (OBJ/PLY/OFF/STL/IFC/glTF/FBX/3DS/DAE), builtin:NAME, or a .cubeao probe cache")
        ->required();
    cmd->add_flag("--verify", a->verify, "Cache: check every checksum; exit 1 on any damage");
    cmd->add_flag("--json", a->json, "Print one JSON object as the last line");
    cmd->callback([a] { isCache(a->target) ? cacheInfo(*a) : sceneInfo(*a); });
}

}  // namespace cubeao::cli
