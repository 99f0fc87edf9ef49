// The procedural scenes: sizes, determinism, and camera paths that stay clear of the geometry.
#include <gtest/gtest.h>

#include <cmath>

#include "cubeao/core/error.h"
#include "cubeao/reference/embree_scene.h"
#include "cubeao/core/sampling.h"
#include "cubeao/scene/builtin.h"
#include "cubeao/scene/repair.h"
#include "cubeao/scenes/builtin_scenes.h"

namespace cubeao {
namespace {

// Distance to the nearest surface, estimated with 256 rays in all directions; infinity if any escapes.
float clearance(const EmbreeScene& rt, const glm::vec3& p, bool& enclosed) {
    float nearest = INFINITY;
    enclosed = true;
    for (std::uint32_t i = 0; i < 256; ++i) {
        const glm::vec2 u = sampling::rotatedHammersley(i, 256, 0);
        const float z = 1.0f - 2.0f * u.x, s = std::sqrt(std::max(0.0f, 1.0f - z * z));
        const glm::vec3 dir(s * std::cos(6.2831853f * u.y), z, s * std::sin(6.2831853f * u.y));
        const RayHit h = rt.intersect(p, dir, 0.0f, 1e9f);
        if (h.hit)
            nearest = std::min(nearest, h.t);
        else
            enclosed = false;
    }
    return nearest;
}

TEST(Builtin, NamesAndSizes) {
    EXPECT_EQ(builtinSceneNames(), (std::vector<std::string>{"box-room", "cloister", "sphere-plane", "town", "two-rooms"}));
    const Scene cloister = makeBuiltinScene("builtin:cloister");
    EXPECT_GE(cloister.triangleCount(), 20000u);  // "a few tens of thousands"
    EXPECT_LE(cloister.triangleCount(), 80000u);
    EXPECT_EQ(cloister.source, "builtin:cloister");
    EXPECT_EQ(makeBuiltinScene("builtin:box-room").triangleCount(), 12u + 3u * 10u);  // room + 3 bottomless boxes
    EXPECT_EQ(makeBuiltinScene("builtin:two-rooms").triangleCount(), 2u * 12u + 2u * 10u);  // 2 rooms, 2 blocks
}

// The self-contained scenes; builtin:town needs the shared models and has tests of its own (test_town.cpp).
const std::vector<std::string> kProcedural{"box-room", "cloister", "sphere-plane", "two-rooms"};

TEST(Builtin, DeterministicGeometry) {
    for (const auto& name : kProcedural) {
        const Scene a = makeBuiltinScene("builtin:" + name), b = makeBuiltinScene("builtin:" + name);
        EXPECT_EQ(a.hash, b.hash) << name;
        EXPECT_EQ(a.problems.zeroNormals, 0u) << name;
    }
}

TEST(Builtin, CameraPathsStayInsideAndClearOfSurfaces) {
    for (const auto& name : kProcedural) {
        const Scene scene = makeBuiltinScene("builtin:" + name);
        const EmbreeScene rt(scene);
        const CameraPath path = builtinCameraPath("builtin:" + name);
        ASSERT_GE(path.frames.size(), 12u) << name;
        for (std::size_t f = 0; f < path.frames.size(); ++f) {
            bool enclosed = false;
            const float d = clearance(rt, path.frames[f].eye, enclosed);
            EXPECT_GE(d, 0.6f) << name << " frame " << f;
            if (name == "box-room" || name == "two-rooms") {
                EXPECT_TRUE(enclosed) << "frame " << f;
            }
            if (f > 0) {  // a smooth walk: no jumps between consecutive frames
                EXPECT_LT(glm::length(path.frames[f].eye - path.frames[f - 1].eye), 1.0f) << name << " " << f;
            }
        }
    }
}

TEST(Builtin, ResolveCameraPath) {
    EXPECT_EQ(resolveCameraPath("", "builtin:cloister").frames.size(),
              builtinCameraPath("builtin:cloister").frames.size());
    EXPECT_EQ(resolveCameraPath("builtin:box-room", "some.obj").scene, "builtin:box-room");
    EXPECT_THROW(resolveCameraPath("", "some.obj"), UsageError);
}

// The table in scene/ is filled by cubeao_scenes (tests/test_main.cpp calls registerBuiltinScenes()):
// each name must reach its own scene and path, and a second registration must change nothing.
TEST(Builtin, RegistrationMapsEachNameToItsOwnScene) {
    const struct {
        const char* name;
        Scene (*make)();
        CameraPath (*path)();
    } expected[] = {{"sphere-plane", scenes::makeSpherePlane, scenes::spherePlanePath},
                    {"box-room", scenes::makeBoxRoom, scenes::boxRoomPath},
                    {"two-rooms", scenes::makeTwoRooms, scenes::twoRoomsPath},
                    {"cloister", scenes::makeCloister, scenes::cloisterPath}};
    for (const auto& e : expected) {
        SCOPED_TRACE(e.name);
        const std::string spec = std::string("builtin:") + e.name;
        Scene direct = e.make();
        prepareScene(direct, true);  // what makeBuiltinScene does to the raw geometry
        const Scene registered = makeBuiltinScene(spec);
        EXPECT_EQ(registered.triangleCount(), direct.triangleCount());
        EXPECT_EQ(registered.hash, direct.hash);
        const CameraPath a = builtinCameraPath(spec), b = e.path();
        ASSERT_EQ(a.frames.size(), b.frames.size());
        EXPECT_EQ(a.frames.front().eye, b.frames.front().eye);
        EXPECT_EQ(a.frames.back().target, b.frames.back().target);
    }
}

TEST(Builtin, RegistrationIsIdempotentAndRejectsDuplicates) {
    const std::vector<std::string> before = builtinSceneNames();
    const std::uint64_t hash = makeBuiltinScene("builtin:box-room").hash;
    scenes::registerBuiltinScenes();  // a second call: no-op, no "registered twice"
    EXPECT_EQ(builtinSceneNames(), before);
    try {
        registerBuiltinScene("box-room", {scenes::makeSpherePlane, scenes::spherePlanePath});
        ADD_FAILURE() << "registering box-room twice did not throw";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("builtin:box-room"), std::string::npos) << e.what();
    }
    EXPECT_EQ(makeBuiltinScene("builtin:box-room").hash, hash);  // the first registration stands
    EXPECT_THROW(registerBuiltinScene("", {scenes::makeBoxRoom, scenes::boxRoomPath}), Error);
    EXPECT_THROW(registerBuiltinScene("a:b", {scenes::makeBoxRoom, scenes::boxRoomPath}), Error);
    EXPECT_THROW(registerBuiltinScene("no-path", {scenes::makeBoxRoom, nullptr}), Error);
    EXPECT_EQ(builtinSceneNames(), before);
}

}  // namespace
}  // namespace cubeao
