// The procedural scenes: sizes, determinism, and camera paths that stay clear of the geometry.
#include <gtest/gtest.h>

#include <cmath>

#include "cubeao/core/error.h"
#include "cubeao/reference/embree_scene.h"
#include "cubeao/reference/sampling.h"
#include "cubeao/scene/builtin.h"

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
    EXPECT_EQ(builtinSceneNames(), (std::vector<std::string>{"box-room", "cloister", "sphere-plane"}));
    const Scene cloister = makeBuiltinScene("builtin:cloister");
    EXPECT_GE(cloister.triangleCount(), 20000u);  // "a few tens of thousands"
    EXPECT_LE(cloister.triangleCount(), 80000u);
    EXPECT_EQ(cloister.source, "builtin:cloister");
    EXPECT_EQ(makeBuiltinScene("builtin:box-room").triangleCount(), 12u + 3u * 10u);  // room + 3 bottomless boxes
}

TEST(Builtin, DeterministicGeometry) {
    for (const auto& name : builtinSceneNames()) {
        const Scene a = makeBuiltinScene("builtin:" + name), b = makeBuiltinScene("builtin:" + name);
        EXPECT_EQ(a.hash, b.hash) << name;
        EXPECT_EQ(a.problems.zeroNormals, 0u) << name;
    }
}

TEST(Builtin, CameraPathsStayInsideAndClearOfSurfaces) {
    for (const auto& name : builtinSceneNames()) {
        const Scene scene = makeBuiltinScene("builtin:" + name);
        const EmbreeScene rt(scene);
        const CameraPath path = builtinCameraPath("builtin:" + name);
        ASSERT_GE(path.frames.size(), 12u) << name;
        for (std::size_t f = 0; f < path.frames.size(); ++f) {
            bool enclosed = false;
            const float d = clearance(rt, path.frames[f].eye, enclosed);
            EXPECT_GE(d, 0.6f) << name << " frame " << f;
            if (name == "box-room") {
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

}  // namespace
}  // namespace cubeao
