// The report's plan (reference/top_down.h) on a scene whose answer is known: a 10 × 10 floor with a
// 1-high block in the middle and a roof at height 5 over it all.
#include <gtest/gtest.h>

#include <vector>

#include <glm/vec3.hpp>

#include "cubeao/reference/top_down.h"
#include "cubeao/scenes/mesh_builder.h"

namespace cubeao {
namespace {

Scene blockUnderARoof() {
    scenes::MeshBuilder b;
    b.addFloor(-5, -5, 5, 5, 0);
    b.addBox({-1, 0, -1}, {1, 1, 1}, false, false);
    b.addFloor(-5, -5, 5, 5, 5);  // the roof
    Scene scene = b.take();
    scene.source = "block under a roof";
    finalizeScene(scene);
    return scene;
}

float grey(const TopDownView& v, const glm::vec3& p) {
    const glm::vec2 px = v.toPixel(p);
    const std::size_t i = std::size_t(int(px.y)) * std::size_t(v.width) + std::size_t(int(px.x));
    return v.rgb[3 * i + 1];  // the green channel: the untinted shade
}

// The cut goes half a radius above the highest eye (1.5 + 0.5), under the roof, so the floor and the
// block show and the block, higher, is lighter; the floor at the block's foot is darkened (its outline);
// the probes and eyes land inside the image where they are.
TEST(TopDown, CutsUnderTheRoofAndShadesHeightAndTheFeetOfWalls) {
    const Scene scene = blockUnderARoof();
    const std::vector<glm::vec3> probes{{-3, 1, -3}, {3, 1, 3}};
    const std::vector<glm::vec3> walk{{-3, 1.5f, 0}, {3, 1.5f, 0}};
    const TopDownView v = renderTopDown(&scene, probes, walk, 1.0f, 200);
    ASSERT_GT(v.width, 0);
    ASSERT_EQ(v.rgb.size(), std::size_t(v.width) * std::size_t(v.height) * 3);
    EXPECT_LE(std::max(v.width, v.height), 200);
    EXPECT_TRUE(v.cutBelowTop);
    EXPECT_NEAR(v.cut, 2.0f, 0.01f);
    const float floor = grey(v, {-2.5f, 0, 2.5f}), block = grey(v, {0, 1, 0});
    EXPECT_GT(block, floor + 0.02f) << "higher is lighter";
    EXPECT_LT(grey(v, {1.0f + 0.5f * v.pixel, 0, 0}), 0.8f * floor) << "the foot of the block is outlined";
    for (const glm::vec3& p : probes) {
        const glm::vec2 px = v.toPixel(p);
        EXPECT_TRUE(px.x > 0 && px.y > 0 && px.x < float(v.width) && px.y < float(v.height));
    }
}

// Without a scene the plan is blank around the points; with neither there is nothing to draw.
TEST(TopDown, WithoutASceneFramesThePointsAndWithNothingDrawsNothing) {
    const std::vector<glm::vec3> probes{{0, 0, 0}, {4, 0, 2}};
    const TopDownView v = renderTopDown(nullptr, probes, {}, 1.0f, 100);
    ASSERT_GT(v.width, 0);
    for (const float c : v.rgb) EXPECT_EQ(c, 0.97f);
    EXPECT_EQ(renderTopDown(nullptr, {}, {}, 1.0f, 100).width, 0);
}

}  // namespace
}  // namespace cubeao
