// The projection pass on the GPU (shaders/runtime/project.comp) against its CPU twin (projectAo in
// src/cubeao/runtime/projection.cpp) on the same cache, camera G-buffer and candidate grid.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <vector>

#include <glm/geometric.hpp>

#include "cubeao/cache/bc4.h"
#include "cubeao/cache/cache_file.h"
#include "cubeao/cache/depth_cube.h"
#include "cubeao/runtime/camera_gbuffer.h"
#include "cubeao/runtime/camera_view.h"
#include "cubeao/runtime/probe_projection.h"
#include "cubeao/runtime/projection.h"
#include "cubeao/scene/builtin.h"
#include "cubeao/scene/import.h"
#include "gl_fixture.h"
#include "test_util.h"

namespace {

using namespace cubeao;

struct Decoded {
    std::vector<float> ao, confidence, distance;
};

TEST_F(GlTest, ProbeProjectionMatchesTheCpuTwin) {
    test::TempDir dir;
    const std::string probes = dir.write("probes.json", R"({"version":1,"probes":[{"pos":[3,1.4,2.5]},{"pos":[6,1.5,1.5]},{"pos":[2,1.2,4.5]}]})");
    const std::string cacheFile = (dir.path() / "c.cubeao").string();
    const std::string cmd = std::string(CUBEAO_BINARY) + " bake builtin:box-room --probes " + probes + " --out " +
                            cacheFile + " --res 16 --spp 16 --radius 1 --device cpu > /dev/null 2>&1";
    ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;

    const Scene scene = loadScene("builtin:box-room");
    const CacheReader cache(cacheFile);
    const CacheParams& params = cache.params();
    std::vector<Decoded> decoded(cache.probeCount());
    std::vector<DecodedProbe> views(cache.probeCount());
    for (std::size_t i = 0; i < cache.probeCount(); ++i) {
        const ProbeView p = cache.probe(i);
        std::vector<glm::vec2> rg;
        ASSERT_TRUE(bc::decodeBc5Cube(p.aoConfidence.data(), p.aoConfidence.size(), int(params.res), rg));
        for (const glm::vec2& v : rg) decoded[i].ao.push_back(v.x), decoded[i].confidence.push_back(v.y);
        ASSERT_TRUE(depth::decode(p.depth, int(params.depthRes), params.depthFormat, p.maxDistance, decoded[i].distance));
        views[i] = {p.position, int(params.res), decoded[i].ao, decoded[i].confidence, int(params.depthRes), decoded[i].distance};
    }

    const CameraPath path = builtinCameraPath("builtin:box-room");
    const CameraView view = CameraView::fromPinhole(PinholeCamera(path, 3, 96, 54), path.nearPlane);
    CameraGBuffer gbuffer(scene.positions, scene.indices);
    gbuffer.render(view);
    ProbeProjectionPass pass(cache, scene.bounds.min, scene.bounds.max);
    const gl::Texture aoImage = gl::Texture::create(GL_TEXTURE_2D);
    glTextureStorage2D(aoImage.id(), 1, GL_R32F, view.width, view.height);
    pass.run(gbuffer, view, 3, aoImage.id());
    std::vector<float> gpu(std::size_t(view.width) * std::size_t(view.height));
    glGetTextureImage(aoImage.id(), 0, GL_RED, GL_FLOAT, GLsizei(gpu.size() * sizeof(float)), gpu.data());

    const CameraGBufferImage g = gbuffer.readBack();
    const glm::mat4 worldFromView = view.worldFromView();
    const ProjectSettings settings = resolveProjectSettings({});
    double sum = 0.0;
    std::size_t far = 0, covered = 0, surface = 0;
    for (int y = 0; y < view.height; ++y)
        for (int x = 0; x < view.width; ++x) {
            const std::size_t i = g.index(x, y);
            if (g.empty(x, y)) {
                EXPECT_EQ(gpu[i], 1.0f);
                continue;
            }
            const glm::vec3 p = glm::vec3(worldFromView * glm::vec4(view.viewPosition(x, y, g.depth[i]), 1.0f));
            const glm::vec3 n = glm::normalize(glm::mat3(worldFromView) * g.normal[i]);
            std::vector<DecodedProbe> candidates;
            for (std::uint32_t c : pass.grid().candidates(p)) candidates.push_back(views[c]);
            const Projected cpu = projectAo(candidates, p, n, settings);
            const float d = std::fabs(cpu.ao - gpu[i]);
            sum += d;
            far += d > 0.02f ? 1 : 0;
            covered += cpu.covered ? 1 : 0;
            ++surface;
        }
    ASSERT_GT(surface, 0u);
    // Same inputs and the same decisions; differences come from the BC5 decode (Mesa interpolates in
    // 8-bit fixed point, ≤ 1.6/255 from the spec) and from points within rounding of a texel border
    // or of the depth test's threshold, where GPU and CPU may pick neighbours.
    EXPECT_LT(sum / double(surface), 2e-3);
    EXPECT_LE(far, surface / 50) << "pixels differing by more than 0.02";
    EXPECT_GT(covered, surface * 9 / 10) << "three probes in an open room should see most of it";
    EXPECT_NEAR(pass.uncoveredFraction(), double(surface - covered) / double(gpu.size()), 0.01);
}

}  // namespace
