// cubeao info SCENE|CACHE.cubeao [--verify] [--json]: for a scene, what was loaded and what was
// repaired; for a probe cache (DESIGN.md §5: recognised by its .cubeao extension or its magic), the
// probes, resolutions and bake parameters, and with --verify every checksum (exit 1 on any damage).
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <memory>

#include "cache_json.h"
#include "commands.h"
#include "cubeao/bake/bake_settings.h"
#include "cubeao/cache/cache_file.h"
#include "cubeao/core/durable_file.h"
#include "cubeao/core/error.h"
#include "cubeao/placement/probe_set.h"
#include "cubeao/core/sampling.h"
#include "cubeao/placement/placement.h"
#include "cubeao/reference/embree_scene.h"
#include "cubeao/scene/builtin.h"
#include "cubeao/scene/import.h"
#include "cubeao/scene/repair.h"

namespace cubeao::cli {
namespace {

namespace fs = std::filesystem;

struct InfoArgs {
    std::string target, probes, camera, writeObj;
    int res = 512;
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

// The prediction's parts, for fitting the error model to measured walks (tools/calibrate_error.sh).
nlohmann::json errorTermsJson(const placement::ErrorTerms& t) {
    return {{"served_weight", t.served}, {"occluded_term", t.occluded}, {"texel_term", t.texel}, {"texel_near_term", t.texelNear},
            {"unserved_weight", t.unserved}, {"unserved_occluded", t.unservedOccluded}, {"capped_weight", t.capped}};
}

// `info SCENE --probes P.json [--camera WALK]`: where the probes of P stand and what they are predicted
// to give (issue 31). Free space is placement's, which does not depend on which way faces point: the
// walk's eyes and the outside of the box seed it. "backface_majority" is the old rule (most of 64 rays
// meet the back of a face), kept to show where a model's winding misleads it.
nlohmann::json probeCheck(const Scene& s, const InfoArgs& a) {
    const std::vector<ProbeSpec> probes = readProbeSet(a.probes, s.origin);
    std::unique_ptr<CameraPath> path;
    if (!a.camera.empty()) path = std::make_unique<CameraPath>(resolveCameraPath(a.camera, s));
    placement::PlaceSettings settings;
    settings.res = a.res;
    const placement::PlacementScene ps(s, settings, path.get());
    const EmbreeScene& embree = ps.embree();
    constexpr int kRays = 64;
    std::size_t inside = 0, tooClose = 0, outside = 0, backMajority = 0;
    float nearest = std::numeric_limits<float>::infinity();
    std::vector<glm::vec3> positions;
    for (std::size_t i = 0; i < probes.size(); ++i) {
        const glm::vec3 p = probes[i].position;
        positions.push_back(p);
        int back = 0;
        float closest = std::numeric_limits<float>::infinity();
        for (int k = 0; k < kRays; ++k) {
            const glm::vec2 u = sampling::rotatedHammersley(std::uint32_t(k), kRays, std::uint32_t(i));
            const float z = 1.0f - 2.0f * u.x, r = std::sqrt(std::max(0.0f, 1.0f - z * z)), phi = 6.2831853f * u.y;
            const glm::vec3 d(r * std::cos(phi), r * std::sin(phi), z);
            const RayHit h = embree.intersect(p, d, 0.0f, std::numeric_limits<float>::infinity());
            if (!h.hit) continue;
            closest = std::min(closest, h.t);
            if (glm::dot(h.normal, d) > 0.0f) ++back;
        }
        backMajority += 2 * back > kRays;
        nearest = std::min(nearest, closest);
        using Verdict = placement::FreeSpace::Verdict;
        const Verdict v = ps.freeSpace().classify(p);
        if (v == Verdict::Outside) ++outside;
        if (v == Verdict::TooClose) ++tooClose;
        if (v == Verdict::InsideClosed || v == Verdict::InsideByRays) {
            ++inside;
            const glm::dvec3 f = s.toFile(p);  // as probes.json has it
            std::printf("  probe %zu at (%.10g, %.10g, %.10g): inside geometry (no free space reaches it)\n", i, f.x,
                        f.y, f.z);
        }
    }
    const placement::Placement report = placement::evaluate(ps, positions, "given");
    std::printf("  probes     %zu in %s: %zu inside geometry, %zu within the clearance %g of a surface, %zu outside "
                "the box, nearest surface %g\n"
                "  predicted  walk MAE %.4f at %d² faces (what %s sees); served %.1f %% of the relevant area, fine "
                "coverage %.1f %%\n",
                probes.size(), a.probes.c_str(), inside, tooClose, ps.freeSpace().clearance(), outside, nearest,
                report.predictedMae, a.res, path ? "the walk" : "free space", 100.0 * report.served,
                100.0 * report.coverage);
    return {{"file", a.probes},
            {"probes", probes.size()},
            {"inside", inside},
            {"too_close", tooClose},
            {"outside_bbox", outside},
            {"backface_majority", backMajority},
            {"nearest_surface", std::isfinite(nearest) ? nlohmann::json(nearest) : nlohmann::json()},
            {"predicted_mae", report.predictedMae},
            {"served", report.served},
            {"coverage", report.coverage},
            {"error_terms", errorTermsJson(placement::errorTerms(ps, positions))}};
}

// `info SCENE --write-obj FILE`: the triangles as cubeao loaded and repaired them, in file coordinates,
// with their vertex normals: what placement and the bake see, for another tool (e.g. an IFC's
// triangles as OBJ) or to edit (tools/bench_place_default.sh reverses its faces).
void writeObj(const Scene& s, const std::string& path) {
    std::string text = "# " + s.source + ", as cubeao loaded it (cubeao info --write-obj)\n";
    // Local positions are floats: 9 digits give them back exactly; a re-centred scene's file
    // coordinates are doubles.
    const char* format = s.recentred() ? "v %.17g %.17g %.17g\n" : "v %.9g %.9g %.9g\n";
    char line[128];
    for (const glm::vec3& p : s.positions) {
        const glm::dvec3 f = s.toFile(p);
        text.append(line, std::size_t(std::snprintf(line, sizeof line, format, f.x, f.y, f.z)));
    }
    for (const glm::vec3& n : s.normals)
        text.append(line, std::size_t(std::snprintf(line, sizeof line, "vn %.9g %.9g %.9g\n", n.x, n.y, n.z)));
    for (std::size_t t = 0; t < s.indices.size(); t += 3) {
        const std::uint32_t a = s.indices[t] + 1, b = s.indices[t + 1] + 1, c = s.indices[t + 2] + 1;
        text.append(line, std::size_t(std::snprintf(line, sizeof line, "f %u//%u %u//%u %u//%u\n", a, a, b, b, c, c)));
    }
    writeFileDurably(path, text, "OBJ");
}

void sceneInfo(const InfoArgs& a) {
    if (a.verify) throw UsageError("--verify checks a cache's checksums; " + a.target + " is a scene");
    const Scene s = loadScene(a.target);
    if (!a.writeObj.empty()) writeObj(s, a.writeObj);
    // File coordinates, as the model file and camera paths have them (the scene itself is local).
    const auto& b = s.bounds;
    const glm::dvec3 lo = s.toFile(b.min), hi = s.toFile(b.max);
    std::printf("%s\n  triangles  %zu\n  vertices   %zu\n  bbox       (%g, %g, %g) -> (%g, %g, %g)\n"
                "  hash       %s\n  radius     %g (default: 2%% of the diagonal)\n"
                "  repaired   %zu zero-area triangles, %zu duplicate vertices, %zu unused vertices%s\n",
                s.source.c_str(), s.triangleCount(), s.vertexCount(), lo.x, lo.y, lo.z, hi.x, hi.y, hi.z,
                hashToString(s.hash).c_str(), s.defaultRadius(), s.problems.degenerateTriangles,
                s.problems.duplicateVertices, s.problems.unusedVertices,
                s.problems.normalsComputed ? "; normals computed" : "");
    if (s.recentred())
        std::printf("  origin     (%.10g, %.10g, %.10g): far from the file's origin, re-centred there\n", s.origin.x,
                    s.origin.y, s.origin.z);
    if (!s.problems.warnings.empty())
        std::printf("  importer   %zu warnings (first: %s)\n", s.problems.warnings.size(),
                    s.problems.warnings.front().c_str());
    const WindingCheck winding = checkWinding(s);
    if (winding.flippedEdges > 0)
        std::printf("  winding    inconsistent: %zu of %zu shared edges run the same way by both faces (%.1f %%); "
                    "rendering does not mind, placement's inside test does\n",
                    winding.flippedEdges, winding.sharedEdges, 100.0 * winding.flippedShare());
    nlohmann::json j{{"scene", s.source},
                     {"triangles", s.triangleCount()},
                     {"vertices", s.vertexCount()},
                     {"bbox", {{"min", {b.min.x, b.min.y, b.min.z}}, {"max", {b.max.x, b.max.y, b.max.z}}}},
                     {"up", {s.up.x, s.up.y, s.up.z}},
                     {"hash", hashToString(s.hash)},
                     {"default_radius", s.defaultRadius()},
                     {"problems", s.problems.toJson()}};
    if (s.recentred()) {
        j["origin"] = {s.origin.x, s.origin.y, s.origin.z};
        j["bbox"] = {{"min", {lo.x, lo.y, lo.z}}, {"max", {hi.x, hi.y, hi.z}}};
    }
    j["problems"]["shared_edges"] = winding.sharedEdges;
    j["problems"]["flipped_edges"] = winding.flippedEdges;
    if (!a.probes.empty()) j["probe_check"] = probeCheck(s, a);
    if (a.json) printJson(j);
}

void cacheInfo(const InfoArgs& a) {
    const CacheReader cache(a.target);
    const CacheParams& p = cache.params();
    nlohmann::json j = {{"cache", a.target},
                        {"format_version", cache.formatVersion()},
                        {"scene_hash", hashToString(p.sceneHash)},
                        {"probes", cache.probeCount()},
                        {"bytes_per_texel", cache.bytesPerTexel()},
                        {"file_bytes", cache.fileSize()}};
    j.update(bakeParamsJson(p));
    const char* ao = p.aoFormat == AoFormat::Bc4 ? "AO alone (BC4, confidence 1)" : "AO + confidence (BC5)";
    std::printf("%s: probe cache, format %u, scene %s\n  probes     %zu\n  faces      %u² %s, "
                "%u² distance (%s)\n  estimator  %s, R = %g, falloff %s, spp %u, seed %u, %u directions × %u steps, denoise %u\n"
                "  size       %llu bytes, %.4f bytes per AO texel\n",
                a.target.c_str(), cache.formatVersion(), hashToString(p.sceneHash).c_str(), cache.probeCount(), p.res, ao,
                p.depthRes, depthFormatName(p.depthFormat), estimatorName(Estimator(p.estimator)), double(p.radius),
                falloffName(Falloff(p.falloff)), p.spp, p.seed, p.directions, p.steps,
                unsigned(p.denoise), (unsigned long long)cache.fileSize(), cache.bytesPerTexel());
    if (p.levels > 1)
        std::printf("  levels     %u levels of detail per probe, %u² to %u² faces\n", unsigned(p.levels), p.res,
                    p.res >> (p.levels - 1));
    if (p.origin != glm::vec3(0.0f)) {
        std::printf("  origin     (%.10g, %.10g, %.10g): probe positions are relative to it\n", double(p.origin.x),
                    double(p.origin.y), double(p.origin.z));
        j["origin"] = {p.origin.x, p.origin.y, p.origin.z};
    }
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
    cmd->add_option("--probes", a->probes,
                    "Scene: check a probes.json against it (probes inside geometry, nearest surface) and predict its "
                    "walk MAE (placement's error model)");
    cmd->add_option("--camera", a->camera, "Scene with --probes: the walk the prediction is for (default: free space)");
    cmd->add_option("--res", a->res, "Scene with --probes: the bake's face size the prediction assumes")
        ->capture_default_str();
    cmd->add_option("--write-obj", a->writeObj,
                    "Scene: write its triangles as loaded and repaired (file coordinates, vertex normals) to this OBJ");
    cmd->add_flag("--json", a->json, "Print one JSON object as the last line");
    cmd->callback([a] {
        if (isCache(a->target) && !a->probes.empty()) throw UsageError("--probes checks a probe set against a scene");
        if (isCache(a->target) && !a->writeObj.empty()) throw UsageError("--write-obj writes a scene's triangles");
        isCache(a->target) ? cacheInfo(*a) : sceneInfo(*a);
    });
}

}  // namespace cubeao::cli
