// Georeferenced models (issue 15): a model far from its file's origin is imported in double and
// re-centred (Scene::origin); camera paths, probes.json and the cache header stay in file coordinates.
// End to end: builtin:box-room written to OBJ as it is and moved by (10^5, 0, 10^5), with its camera path
// moved the same, gives the same reference AO, the same probes and the same probe render.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>
#include <nlohmann/json.hpp>

#include "cli_run.h"
#include "cubeao/placement/probe_set.h"
#include "cubeao/cache/cache_file.h"
#include "cubeao/scene/builtin.h"
#include "cubeao/scene/camera_path.h"
#include "cubeao/scene/import.h"
#include "gl_fixture.h"
#include "test_util.h"

namespace cubeao {
namespace {

namespace fs = std::filesystem;
using test::CliRun;
using test::lastLine;
using test::runCli;
using test::TempDir;

const glm::dvec3 kShift(1e5, 0.0, 1e5);

// `scene` as OBJ text (positions, normals, triangles), every position + shift. %.17g of a float plus a
// whole number in double is exact, so the file holds exactly the moved floats.
std::string objText(const Scene& scene, const glm::dvec3& shift) {
    std::string s;
    char line[160];
    for (const glm::vec3& p : scene.positions) {
        std::snprintf(line, sizeof line, "v %.17g %.17g %.17g\n", double(p.x) + shift.x, double(p.y) + shift.y,
                      double(p.z) + shift.z);
        s += line;
    }
    for (const glm::vec3& n : scene.normals) {
        std::snprintf(line, sizeof line, "vn %.9g %.9g %.9g\n", double(n.x), double(n.y), double(n.z));
        s += line;
    }
    for (std::size_t t = 0; t < scene.indices.size(); t += 3) {
        const auto a = scene.indices[t] + 1, b = scene.indices[t + 1] + 1, c = scene.indices[t + 2] + 1;
        std::snprintf(line, sizeof line, "f %u//%u %u//%u %u//%u\n", a, a, b, b, c, c);
        s += line;
    }
    return s;
}

TEST(Georef, NearSceneIsNotRecentred) {
    EXPECT_EQ(chooseOrigin({-58, -2, -35}, {68, 30.6, 45}), glm::dvec3(0.0));  // Sibenik as it is
    EXPECT_EQ(chooseOrigin({9000, 0, 9000}, {9010, 3, 9010}), glm::dvec3(0.0));  // within 2^14
    EXPECT_EQ(chooseOrigin({-30000, 0, -30000}, {30000, 10, 30000}), glm::dvec3(0.0));  // big, centred
    const glm::dvec3 o = chooseOrigin({99942.25, -2, 99965}, {100068.5, 30.6, 100045});
    EXPECT_EQ(o, glm::dvec3(100005, 14, 100005));  // the centre, rounded to whole units
    // Beyond 2^24 the whole number is rounded to a float too, so it is exact in both.
    const glm::dvec3 far = chooseOrigin({5.5e9 + 3, 0, 0}, {5.5e9 + 40, 1, 1});
    EXPECT_EQ(far.x, double(float(far.x)));
    EXPECT_LT(std::fabs(far.x - (5.5e9 + 21.5)), 512.0);
}

TEST(Georef, ObjCoordinatesKeepTheirDigits) {
    TempDir dir("georef");
    const std::string obj = dir.write("far.obj",
                                      "v 100000.123456 0.5 100000.654321\n"
                                      "v 100001.123456 0.5 100000.654321\n"
                                      "v 100000.123456 1.5 100000.654321\n"
                                      "v 100000.123456 0.5 100001.987654\n"
                                      "f 1 2 3\nf 1 3 4\n");
    const Scene s = loadScene(obj);
    ASSERT_TRUE(s.recentred());
    EXPECT_EQ(s.origin, glm::dvec3(100001, 1, 100001));
    const glm::dvec3 file[] = {{100000.123456, 0.5, 100000.654321}, {100001.123456, 0.5, 100000.654321},
                               {100000.123456, 1.5, 100000.654321}, {100000.123456, 0.5, 100001.987654}};
    ASSERT_EQ(s.vertexCount(), 4u);
    for (const glm::vec3& p : s.positions) {
        double best = 1e30;
        for (const glm::dvec3& f : file) best = std::min(best, glm::length(s.toFile(p) - f));
        EXPECT_LT(best, 1e-4) << "a vertex lost its digits";  // float at 10^5: 8 mm steps
        EXPECT_LT(best, 1e-6);  // measured: the local float's rounding only
    }
    // OFF goes the same way (its own double parse).
    const std::string off = dir.write("far.off",
                                      "OFF\n4 2 0\n"
                                      "100000.123456 0.5 100000.654321\n100001.123456 0.5 100000.654321\n"
                                      "100000.123456 1.5 100000.654321\n100000.123456 0.5 100001.987654\n"
                                      "3 0 1 2\n3 0 2 3\n");
    const Scene o = loadScene(off);
    ASSERT_TRUE(o.recentred());
    for (const glm::vec3& p : o.positions) {
        double best = 1e30;
        for (const glm::dvec3& f : file) best = std::min(best, glm::length(o.toFile(p) - f));
        EXPECT_LT(best, 1e-6);
    }
    // Near the origin: no re-centring, and the hash is the floats' as before.
    const Scene n = loadScene(dir.write("near.obj", "v 0.123456 0.5 0.654321\nv 1.123456 0.5 0.654321\n"
                                                    "v 0.123456 1.5 0.654321\nf 1 2 3\n"));
    EXPECT_FALSE(n.recentred());
    EXPECT_EQ(n.hash, geometryHash(n.positions, n.indices));
    EXPECT_EQ(n.positions[0], glm::vec3(0.123456f, 0.5f, 0.654321f));
}

TEST(Georef, SameLocalGeometryElsewhereHasAnotherHash) {
    TempDir dir("georef");
    const Scene room = loadScene("builtin:box-room");
    const Scene a = loadScene(dir.write("a.obj", objText(room, kShift)));
    const Scene b = loadScene(dir.write("b.obj", objText(room, kShift + glm::dvec3(1000, 0, 0))));
    ASSERT_TRUE(a.recentred() && b.recentred());
    EXPECT_EQ(a.positions, b.positions);  // moved by whole units: the same local floats
    EXPECT_NE(a.hash, b.hash) << "a cache of one must not pass for the other";
    EXPECT_EQ(a.hash, loadScene(dir.write("c.obj", objText(room, kShift))).hash);
}

TEST(Georef, CameraPathsAndProbeSetsStayInFileCoordinates) {
    TempDir dir("georef");
    const glm::dvec3 origin(100004, 2, 100003);
    CameraPath path = builtinCameraPath("builtin:box-room");
    const CameraPath original = path;
    path.origin = -kShift;  // frames relative to -shift; rebased on 0, each moves by -shift
    rebaseCameraPath(path, glm::dvec3(0.0));
    for (std::size_t i = 0; i < path.frames.size(); ++i)
        EXPECT_NEAR(path.frames[i].eye.x, double(original.frames[i].eye.x) - kShift.x, 0.01);
    // Write the original moved by the shift, read it against the scene's origin: local = eye + shift - origin.
    CameraPath moved = original;
    moved.origin = kShift;
    const fs::path file = dir / "walk.json";
    writeCameraPath(file, moved);
    const nlohmann::json j = nlohmann::json::parse(std::ifstream(file));
    EXPECT_DOUBLE_EQ(j["frames"][0]["eye"][0].get<double>(), double(original.frames[0].eye.x) + kShift.x);
    const CameraPath read = readCameraPath(file, origin);
    EXPECT_EQ(read.origin, origin);
    for (std::size_t i = 0; i < read.frames.size(); ++i)
        for (int k = 0; k < 3; ++k) {
            const double want = double(original.frames[i].eye[k]) + kShift[k] - origin[k];
            EXPECT_NEAR(read.frames[i].eye[k], want, 1e-6);
        }
    // probes.json: written as position + origin in double, read back to the same local floats.
    std::vector<ProbeSpec> probes = {{{-3.25f, 1.5f, 0.125f}}, {{0.1f, -0.7f, 2.3f}}};
    writeProbeSet(dir / "probes.json", probes, nlohmann::json::object(), origin);
    const nlohmann::json pj = nlohmann::json::parse(std::ifstream(dir / "probes.json"));
    EXPECT_DOUBLE_EQ(pj["probes"][1]["pos"][2].get<double>(), double(2.3f) + origin.z);
    const std::vector<ProbeSpec> back = readProbeSet(dir / "probes.json", origin);
    ASSERT_EQ(back.size(), 2u);
    EXPECT_EQ(back[0].position, probes[0].position);
    EXPECT_EQ(back[1].position, probes[1].position);
}

TEST(Georef, CacheHeaderCarriesTheOrigin) {
    TempDir dir("georef");
    CacheParams p;
    p.sceneHash = 5;
    p.res = 4;
    p.depthRes = 1;
    p.radius = 1.0f;
    ProbeRecord r;
    r.position = {1.5f, 2.0f, -0.25f};
    r.aoConfidence.assign(std::size_t(aoSectionSize(p)), 0);
    r.depth.assign(std::size_t(depthSectionSize(p)), 0);
    writeCache(dir / "near.cubeao", p, {r});
    EXPECT_EQ(CacheReader(dir / "near.cubeao").formatVersion(), 1u) << "no origin: format 1, as before";
    p.origin = {100004.0f, 2.0f, 100003.0f};
    writeCache(dir / "far.cubeao", p, {r});
    const CacheReader far(dir / "far.cubeao");
    EXPECT_EQ(far.formatVersion(), 2u);
    EXPECT_EQ(far.params().origin, p.origin);
    EXPECT_EQ(far.params(), p);
    EXPECT_EQ(far.position(0), r.position);
    far.verifyAll();
    CacheParams near = p;
    near.origin = glm::vec3(0.0f);
    EXPECT_TRUE(test::contains(test::errorMessage([&] { far.expectParams(near); }), "origin"));
}

std::string slurp(const fs::path& f) {
    std::ifstream in(f);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

// The whole chain on the room and on the room 10^5 units out. Tolerances: the reference uses the same
// rays per pixel (seeded by pixel and frame), so the two differ only where float rounding of the local
// geometry (x - 4 instead of x) moves a hit across an edge: measured MAE 0 (equal images); bound 0.003, well
// under the reference's own noise at 64 spp (~0.02 per pixel).
TEST_F(GlTest, MovedSceneGivesTheSameReferenceProbesAndRender) {
    TempDir dir("georef");
    const Scene room = loadScene("builtin:box-room");
    const std::string near = dir.write("room.obj", objText(room, glm::dvec3(0.0)));
    const std::string far = dir.write("far.obj", objText(room, kShift));
    CameraPath path = builtinCameraPath("builtin:box-room");
    writeCameraPath(dir / "near.json", path);
    path.origin = kShift;
    writeCameraPath(dir / "far.json", path);

    const std::string view = " --frames 0:3 --width 64 --height 36";
    for (const char* which : {"near", "far"}) {
        const std::string scene = std::string(which) == "near" ? near : far;
        const std::string cam = " --camera " + (dir / (std::string(which) + ".json")).string();
        const std::string out = (dir / which).string();
        ASSERT_EQ(runCli("reference " + scene + cam + view + " --spp 64 --radius 1 --out " + out + "/ref").code, 0);
        ASSERT_EQ(runCli("place " + scene + cam + " --method path --budget 2 --out " + out + "/probes.json").code, 0);
        ASSERT_EQ(runCli("bake " + scene + " --probes " + out + "/probes.json --out " + out +
                         "/c.cubeao --res 16 --spp 16 --radius 1 --device cpu")
                      .code,
                  0);
        const CliRun r =
            runCli("render " + scene + cam + view + " --cache " + out + "/c.cubeao --out " + out + "/render");
        ASSERT_EQ(r.code, 0) << r.out;
    }
    const CliRun ref = runCli("compare " + (dir / "near/ref").string() + " " + (dir / "far/ref").string() + " --json");
    ASSERT_EQ(ref.code, 0) << ref.out;
    const double refMae = lastLine(ref.out)["mae"].get<double>();
    const CliRun ren =
        runCli("compare " + (dir / "near/render").string() + " " + (dir / "far/render").string() + " --json");
    ASSERT_EQ(ren.code, 0) << ren.out;
    const double renderMae = lastLine(ren.out)["mae"].get<double>();
    std::printf("[ info ] moved by 1e5: reference MAE %.6f, probe render MAE %.6f\n", refMae, renderMae);
    EXPECT_LE(refMae, 0.003);
    EXPECT_LE(renderMae, 0.003);

    // probes.json: the moved scene's probes are the room's + the shift (file coordinates).
    const nlohmann::json pn = nlohmann::json::parse(slurp(dir / "near/probes.json"));
    const nlohmann::json pf = nlohmann::json::parse(slurp(dir / "far/probes.json"));
    ASSERT_EQ(pn["probes"].size(), pf["probes"].size());
    for (std::size_t i = 0; i < pn["probes"].size(); ++i)
        for (int k = 0; k < 3; ++k)
            EXPECT_NEAR(pf["probes"][i]["pos"][k].get<double>(), pn["probes"][i]["pos"][k].get<double>() + kShift[k],
                        1e-4);
    // The cache: local positions + the header's origin = the room's probes + the shift.
    const CacheReader cn(dir / "near/c.cubeao"), cf(dir / "far/c.cubeao");
    // Traced (BC4) and filtered by default: format 4 holds the origin either way (formats 1 and 2:
    // Georef.CacheHeaderCarriesTheOrigin).
    EXPECT_EQ(cn.formatVersion(), 4u);
    EXPECT_EQ(cf.formatVersion(), 4u);
    EXPECT_EQ(cn.params().origin, glm::vec3(0.0f));
    EXPECT_NE(cf.params().origin, glm::vec3(0.0f));
    ASSERT_EQ(cn.probeCount(), cf.probeCount());
    for (std::size_t i = 0; i < cn.probeCount(); ++i)
        for (int k = 0; k < 3; ++k)
            EXPECT_NEAR(double(cf.position(i)[k]) + double(cf.params().origin[k]),
                        double(cn.position(i)[k]) + kShift[k], 1e-4);
    // info names the origin.
    const CliRun info = runCli("info " + far + " --json");
    ASSERT_EQ(info.code, 0);
    EXPECT_NE(info.out.find("origin"), std::string::npos) << info.out;
    EXPECT_EQ(lastLine(runCli("info " + near + " --json").out).count("origin"), 0u);
}

}  // namespace
}  // namespace cubeao
