// The composite pass (src/cubeao/runtime/composite.h, shaders/runtime/composite.comp): the lit
// preview follows compositePixel's formula.
#include <gtest/gtest.h>

#include <memory>

#include <glm/geometric.hpp>

#include "cubeao/runtime/blur.h"
#include "cubeao/runtime/camera_gbuffer.h"
#include "cubeao/runtime/composite.h"
#include "cubeao/runtime/renderer.h"
#include "cubeao/ssao/ssao_pass.h"
#include "runtime_test_util.h"

namespace {

using namespace cubeao;
using namespace cubeao::test;

// ---- GL ------------------------------------------------------------------------------------------

TEST_F(RuntimeGl, CompositeFollowsTheFormula) {
    const Scene& scene = boxRoom();
    CompositeSettings c = compositeSettings();
    c.alpha = 0.75f;
    FrameRenderer r(scene.positions, scene.indices,
                    std::make_unique<SsaoPass>(methodSettings(SsaoMethod::Hbao, scene.defaultRadius())),
                    BlurSettings{}, c);
    const CameraView view = viewOf(boxRoomPath(), 3, 64, 36);
    const RenderedFrame out = r.render(view, 3);
    const CameraGBufferImage g = r.gbuffer().readBack();
    const glm::vec3 light = glm::normalize(view.viewFromWorldRotation() * c.lightDirection);
    for (int y = 0; y < 36; y += 5)
        for (int x = 0; x < 64; x += 7) {
            const std::size_t i = g.index(x, y);
            const glm::vec3 expected = g.empty(x, y) ? c.sky : compositePixel(g.normal[i], light, out.ao.pixels[i], c);
            for (int k = 0; k < 3; ++k) EXPECT_NEAR(out.shadedRgb[3 * i + std::size_t(k)], expected[k], 1.0f / 255.0f);
        }
}

}  // namespace
