// The GPU bake against its twins: cube conventions (GLSL vs C++), the rasterised G-buffer vs Embree
// primary rays, the horizon pass vs the C++ horizon estimators on the same G-buffer, and traced AO vs
// the Embree reference on the same rays (issue: verify_mae ≤ 0.005).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <random>

#include <glm/geometric.hpp>
#include <glm/vec4.hpp>

#include "cubeao/bake/bake.h"
#include "cubeao/bake/cube.h"
#include "cubeao/bake/gpu_bake.h"
#include "cubeao/bake/horizon.h"
#include "cubeao/gl/handles.h"
#include "cubeao/gl/shader.h"
#include "cubeao/scene/import.h"
#include "bake_test_settings.h"
#include "gl_fixture.h"
#include "test_util.h"

namespace {

namespace fs = std::filesystem;
using namespace cubeao;
using test::bakeSettings;

const Scene& boxRoom() {
    static const Scene scene = loadScene("builtin:box-room");
    return scene;
}

constexpr glm::vec3 kBoxProbe{3.0f, 1.4f, 2.5f};  // in the open, off every axis of symmetry

TEST_F(GlTest, CubeHeaderMatchesTheCppTwin) {
    // Random directions plus exact cube edges and corners, where the tie rule decides the face.
    std::vector<glm::vec4> dirs = {{1, 1, 0, 0}, {1, -1, 1, 0}, {-1, 1, 1, 0}, {0, -1, -1, 0}, {-2, 0, 2, 0}};
    std::mt19937 rng(7);
    std::normal_distribution<float> g;
    while (dirs.size() < 512) dirs.emplace_back(g(rng), g(rng), g(rng), 0.0f);
    const std::string src = R"(#version 450 core
#include "cube.glsl"
layout(local_size_x = 64) in;
layout(std430, binding = 0) readonly buffer In { vec4 dirs[]; };
layout(std430, binding = 1) writeonly buffer Out { vec4 values[]; };  // sc, face, texel index | texel direction
void main() {
    uint i = gl_GlobalInvocationID.x;
    vec2 sc;
    int face = cubeFaceOf(dirs[i].xyz, sc);
    ivec3 t = cubeTexelOfDirection(dirs[i].xyz, 16);
    values[2u * i] = vec4(sc, float(face), float((t.z * 16 + t.y) * 16 + t.x));
    values[2u * i + 1u] = vec4(cubeTexelDirection(int(i % 6u), ivec2(int(i / 6u) % 16, int(i / 96u)), 16), 0.0);
})";
    const gl::Program program = gl::buildProgram({{GL_COMPUTE_SHADER, src, "cube_test.comp"}});
    const gl::Buffer in = gl::Buffer::create(), out = gl::Buffer::create();
    glNamedBufferStorage(in.id(), GLsizeiptr(dirs.size() * sizeof(glm::vec4)), dirs.data(), 0);
    glNamedBufferStorage(out.id(), GLsizeiptr(2 * dirs.size() * sizeof(glm::vec4)), nullptr, 0);
    glUseProgram(program.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, in.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, out.id());
    glDispatchCompute(GLuint(dirs.size() / 64), 1, 1);
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    std::vector<glm::vec4> gpu(2 * dirs.size());
    glGetNamedBufferSubData(out.id(), 0, GLsizeiptr(gpu.size() * sizeof(glm::vec4)), gpu.data());

    for (std::size_t i = 0; i < dirs.size(); ++i) {
        const cube::FacePoint fp = cube::faceOf(glm::vec3(dirs[i]));
        EXPECT_EQ(int(gpu[2 * i].z), fp.face) << i;  // integer decisions: exact, ties included
        EXPECT_NEAR(gpu[2 * i].x, fp.sc.x, 1e-6f) << i;
        EXPECT_NEAR(gpu[2 * i].y, fp.sc.y, 1e-6f) << i;
        EXPECT_EQ(std::size_t(gpu[2 * i].w), cube::texelIndex(glm::vec3(dirs[i]), 16)) << i;
        const glm::vec3 d = cube::texelDirection(int(i % 6), int(i / 6) % 16, int(i / 96), 16);
        for (int k = 0; k < 3; ++k) EXPECT_NEAR(gpu[2 * i + 1][k], d[k], 1e-6f) << i;
    }
}

TEST_F(GlTest, GBufferMatchesEmbreePrimaryRaysAndBothGpuModesAgree) {
    const Scene& scene = boxRoom();
    const BakeSettings s = bakeSettings(Estimator::HorizonSplit, 32, 0.5f, 32);
    GpuBaker baker(scene, s);
    baker.setReadback(BakeReadback::All);
    const BakedProbe layered = baker.bake(kBoxProbe, 0);
    baker.setGBufferMode(GBufferMode::SixPass);
    const BakedProbe sixPass = baker.bake(kBoxProbe, 0);
    const CubeGBuffer cpu = renderGBufferCpu(EmbreeScene(scene), kBoxProbe, s.res);

    ASSERT_EQ(layered.gbuffer.texels.size(), cpu.texels.size());
    std::size_t mismatched = 0, compared = 0;
    for (std::size_t i = 0; i < cpu.texels.size(); ++i) {
        const glm::vec4 a = layered.gbuffer.texels[i], b = sixPass.gbuffer.texels[i], c = cpu.texels[i];
        EXPECT_EQ(std::memcmp(&a, &b, sizeof a), 0) << "layered and six-pass differ at texel " << i;
        EXPECT_FALSE(CubeGBuffer::empty(c)) << "the room is closed: every ray hits, texel " << i;
        // A texel centre on a triangle edge may go to either neighbour; in a room of boxes the
        // neighbours differ in distance, so count them and require them to be rare.
        if (std::fabs(a.w - c.w) > 1e-4f * c.w || glm::dot(glm::vec3(a), glm::vec3(c)) < 0.9999f) {
            ++mismatched;
            continue;
        }
        ++compared;
    }
    EXPECT_LE(mismatched, cpu.texels.size() / 200) << "texels where GL and Embree saw different surfaces";
    EXPECT_GT(compared, 0u);
}

// The horizon pass on the GPU and the C++ estimators on the very same G-buffer: identical up to
// float rounding, except where a march point lands within rounding of a texel border and the two
// pick neighbouring texels (rare, bounded by the per-texel difference allowed below).
void expectHorizonTwin(Estimator e) {
    const Scene& scene = boxRoom();
    const BakeSettings s = bakeSettings(e, 32, 1.0f, 32);
    GpuBaker baker(scene, s);
    const CubeGBuffer g = renderGBufferCpu(EmbreeScene(scene), kBoxProbe, s.res);
    std::uint64_t gpuFetches = 0, cpuFetches = 0;
    const std::vector<glm::vec2> gpu = baker.horizonOn(g, 3, &gpuFetches);
    double sumAo = 0.0;
    std::size_t far = 0, surface = 0;
    for (int f = 0; f < cube::kFaces; ++f)
        for (int j = 0; j < s.res; ++j)
            for (int i = 0; i < s.res; ++i) {
                const std::size_t t = cube::texelIndex(f, i, j, s.res);
                if (CubeGBuffer::empty(g.texels[t])) continue;
                const glm::vec3 p = g.surfacePoint(f, i, j), n(g.texels[t]);
                const std::uint32_t key = texelKey(f, i, j, s.res, 3, s.ao.seed);
                const HorizonEstimate cpu = e == Estimator::Gtao ? gtaoAo(g, p, n, s, key) : horizonSplitAo(g, p, n, s, key);
                cpuFetches += cpu.fetches;
                const float d = std::fabs(cpu.ao - gpu[t].x);
                sumAo += d;
                far += d > 1e-3f ? 1 : 0;
                ++surface;
                EXPECT_LE(d, 0.1f) << "texel " << f << "/" << i << "," << j;
                EXPECT_NEAR(cpu.confidence, gpu[t].y, 0.02f) << "texel " << f << "/" << i << "," << j;
            }
    EXPECT_LT(sumAo / double(surface), 1e-3) << estimatorName(e);
    EXPECT_LE(far, surface / 100) << estimatorName(e) << ": texels differing by more than 1e-3";
    // The same decisions make the same lookups, up to the rare border flips above.
    EXPECT_NEAR(double(gpuFetches), double(cpuFetches), 0.01 * double(cpuFetches)) << estimatorName(e);
}

TEST_F(GlTest, HorizonSplitPassMatchesTheCppTwin) { expectHorizonTwin(Estimator::HorizonSplit); }
TEST_F(GlTest, GtaoPassMatchesTheCppTwin) { expectHorizonTwin(Estimator::Gtao); }

void expectTracedTwin(const Scene& scene, const glm::vec3& probe, float radius, int res, int spp) {
    const BakeSettings s = bakeSettings(Estimator::Traced, res, radius, spp);
    GpuBaker baker(scene, s);
    baker.setReadback(BakeReadback::All);
    const BakedProbe baked = baker.bake(probe, 5);
    const VerifyResult v = verifyProbe(EmbreeScene(scene), baked, 5, s);
    EXPECT_GT(v.texels, 0u);
    // Same rays; only float differences between the GLSL BVH and Embree can flip a grazing ray.
    EXPECT_LE(v.mae, 0.005) << "GPU traced vs Embree twin on " << scene.source;
    EXPECT_EQ(baked.rays, v.texels * std::uint64_t(spp));
}

TEST_F(GlTest, TracedPassMatchesEmbreeOnBoxRoom) { expectTracedTwin(boxRoom(), kBoxProbe, 1.0f, 32, 32); }

TEST_F(GlTest, TracedPassMatchesEmbreeOnSibenik) {
    const fs::path file = fs::path(CUBEAO_SHARED_DIR) / "scenes/sibenik/sibenik.obj";
    if (!fs::exists(file)) GTEST_SKIP() << file << " not found (../shared scenes absent)";
    const Scene scene = loadScene(file.string());
    expectTracedTwin(scene, {18.0f, 2.5f, 0.3f}, 3.0f, 16, 16);  // in the nave, near the walk's start
}

TEST_F(GlTest, HybridTracesExactlyTheLowConfidenceTexels) {
    const Scene& scene = boxRoom();
    const BakeSettings hs = bakeSettings(Estimator::HorizonSplit, 16, 1.0f, 16);
    BakeSettings hy = hs;
    hy.estimator = Estimator::Hybrid;
    BakeSettings tr = hs;
    tr.estimator = Estimator::Traced;
    const auto bakeAll = [&](const BakeSettings& s) {
        GpuBaker baker(scene, s);
        baker.setReadback(BakeReadback::All);
        return baker.bake(kBoxProbe, 2);
    };
    const BakedProbe h = bakeAll(hs), y = bakeAll(hy), t = bakeAll(tr);
    std::uint64_t lowConfidence = 0;
    for (std::size_t i = 0; i < h.ao.size(); ++i) {
        if (CubeGBuffer::empty(h.gbuffer.texels[i])) continue;
        EXPECT_EQ(y.confidence[i], h.confidence[i]) << i;
        const bool traced = h.confidence[i] < hy.hybridThreshold;
        lowConfidence += traced ? 1 : 0;
        EXPECT_EQ(y.ao[i], traced ? t.ao[i] : h.ao[i]) << i;
    }
    EXPECT_EQ(y.tracedTexels, lowConfidence);
    EXPECT_GT(lowConfidence, 0u) << "the box room has hidden corners: some texels must be traced";
    EXPECT_LT(lowConfidence, h.ao.size()) << "and open floor that is not";
}

}  // namespace
