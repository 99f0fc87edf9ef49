// The run-time camera (src/cubeao/runtime/camera_view.h, camera_gbuffer.h): camera conventions
// against PinholeCamera and the camera G-buffer against Embree primary rays.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <limits>

#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>

#include "cubeao/reference/embree_scene.h"
#include "cubeao/runtime/camera_gbuffer.h"
#include "runtime_test_util.h"

namespace {

using namespace cubeao;
using namespace cubeao::test;

// ---- camera conventions (no GL) -----------------------------------------------------------------

TEST(CameraView, PixelRaysArePinholeRays) {
    const CameraPath& path = boxRoomPath();
    for (std::size_t f : {std::size_t(0), std::size_t(17)}) {
        const PinholeCamera cam(path, f, 37, 21);
        const CameraView view = CameraView::fromPinhole(cam, path.nearPlane);
        const glm::mat3 worldFromView = glm::transpose(view.viewFromWorldRotation());
        for (int y : {0, 5, 20})
            for (int x : {0, 18, 36}) {
                const glm::vec3 world = glm::normalize(worldFromView * view.pixelRay(float(x), float(y)));
                const glm::vec3 expected = cam.rayDirection(x, y);
                EXPECT_NEAR(glm::length(world - expected), 0.0f, 1e-6f) << x << "," << y;
                // And back: a point on the ray projects to the pixel centre.
                const glm::vec2 px = view.projectToPixel(view.viewPosition(x, y, 3.7f));
                EXPECT_NEAR(px.x, x + 0.5f, 1e-4f);
                EXPECT_NEAR(px.y, y + 0.5f, 1e-4f);
            }
        // The eye maps to the view-space origin.
        EXPECT_NEAR(glm::length(glm::vec3(view.viewFromWorld * glm::vec4(cam.eye, 1.0f))), 0.0f, 1e-5f);
    }
}

TEST(CameraView, ReversedZPutsTheNearPlaneAtOne) {
    const CameraView view = viewOf(boxRoomPath(), 0, 64, 36);
    for (float d : {view.nearPlane, 1.0f, 100.0f}) {
        const glm::vec4 clip = view.clipFromView() * glm::vec4(0.0f, 0.0f, -d, 1.0f);
        EXPECT_NEAR(clip.z / clip.w, view.nearPlane / d, 1e-6f);
    }
    EXPECT_NEAR(view.projectedPixels(1.0f, 2.0f), 0.5f * view.focalPixels(), 1e-5f);
}

// ---- GL ------------------------------------------------------------------------------------------

TEST_F(RuntimeGl, CameraGBufferMatchesEmbreePrimaryRays) {
    const Scene& scene = boxRoom();
    const EmbreeScene rt(scene);
    CameraGBuffer gbuffer(scene.positions, scene.indices);
    const int w = 160, h = 90;
    std::size_t pixels = 0, mismatched = 0;
    double worstDepth = 0.0;
    for (std::size_t f : {std::size_t(0), std::size_t(11), std::size_t(23)}) {
        const PinholeCamera cam(boxRoomPath(), f, w, h);
        const CameraView view = CameraView::fromPinhole(cam, boxRoomPath().nearPlane);
        gbuffer.render(view);  // the same object every frame: textures are reused
        const CameraGBufferImage g = gbuffer.readBack();
        const glm::mat3 worldFromView = glm::transpose(view.viewFromWorldRotation());
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                ++pixels;
                const glm::vec3 dir = cam.rayDirection(x, y);
                const RayHit hit = rt.intersect(cam.eye, dir, 0.0f, std::numeric_limits<float>::infinity());
                if (hit.hit != !g.empty(x, y)) {
                    ++mismatched;
                    continue;
                }
                if (!hit.hit) continue;
                const double t = double(g.depth[g.index(x, y)]) * glm::length(view.pixelRay(float(x), float(y)));
                const glm::vec3 n = worldFromView * g.normal[g.index(x, y)];
                const glm::vec3 expected = glm::dot(hit.normal, dir) > 0.0f ? -hit.normal : hit.normal;
                const double relative = std::abs(t - hit.t) / hit.t;
                // Pixel centres on a triangle edge may pick either triangle (rasteriser tie rules vs
                // Embree's): count, not fail, when the two hit different surfaces.
                if (relative > 1e-4 || glm::dot(n, expected) < 1.0f - 1e-5f) {
                    ++mismatched;
                    continue;
                }
                worstDepth = std::max(worstDepth, relative);
            }
    }
    // Stated bound: at most 0.5 % of pixels differ (silhouette and crease pixels); all others agree
    // in depth to 1e-4 relative and in normal to 1e-5 in the cosine.
    EXPECT_LE(double(mismatched), 0.005 * double(pixels)) << mismatched << " of " << pixels;
    std::printf("[ info ] G-buffer vs Embree: %zu of %zu pixels differ, worst relative depth %.2e elsewhere\n",
                mismatched, pixels, worstDepth);
}

}  // namespace
