// The BVH of the traced AO estimator (src/cubeao/bake/bvh.h): its structure, its C++ traversal
// against Embree (the reference that decides quality arguments), and the traversal kernel's GLSL
// compilation (shaders/common/bvh.h through bvh.glsl) against its C++ one, ray by ray.
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <memory>
#include <numeric>
#include <random>
#include <string>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/vec4.hpp>

#include "cubeao/bake/bvh.h"
#include "cubeao/bake/gpu_bvh.h"
#include "cubeao/gl/handles.h"
#include "cubeao/gl/shader.h"
#include "cubeao/reference/embree_scene.h"
#include "cubeao/scene/builtin.h"
#include "gl_fixture.h"
#include "test_util.h"

namespace cubeao {
namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

// A built-in scene with its BVH and its Embree scene, built once per test program.
struct Traced {
    Scene scene;
    Bvh bvh;
    EmbreeScene embree;
    explicit Traced(const std::string& spec) : scene(makeBuiltinScene(spec)), bvh(buildBvh(scene)), embree(scene) {}
};
const Traced& traced(const std::string& spec) {
    static std::map<std::string, std::unique_ptr<const Traced>> loaded;
    auto& entry = loaded[spec];
    if (!entry) entry = std::make_unique<const Traced>(spec);
    return *entry;
}

Scene sceneOf(std::vector<glm::vec3> positions, std::vector<std::uint32_t> indices) {
    Scene s;
    s.source = "test";
    s.positions = std::move(positions);
    s.normals.assign(s.positions.size(), glm::vec3(0.0f, 1.0f, 0.0f));
    s.indices = std::move(indices);
    finalizeScene(s);
    return s;
}

struct Ray {
    glm::vec3 org, dir;
    float tnear, tfar;
};

// Origins uniform in `box`, directions uniform on the sphere. Raw mt19937 bits, not <random>'s
// distributions, so the rays are the same with every standard library.
std::vector<Ray> randomRays(const Bounds& box, std::size_t n, float tfar, std::uint32_t seed) {
    std::mt19937 rng(seed);
    auto unit = [&] { return float(rng() >> 8) * 0x1p-24f; };
    std::vector<Ray> rays(n);
    for (Ray& r : rays) {
        r.org = box.min + (box.max - box.min) * glm::vec3(unit(), unit(), unit());
        const float z = 1.0f - 2.0f * unit(), phi = 6.2831853f * unit(), s = std::sqrt(std::max(0.0f, 1.0f - z * z));
        r.dir = glm::normalize(glm::vec3(s * std::cos(phi), s * std::sin(phi), z));
        r.tnear = 0.0f;
        r.tfar = tfar;
    }
    return rays;
}

// ---- structure ---------------------------------------------------------------------------------

bool inside(const glm::vec3& p, const glm::vec3& lo, const glm::vec3& hi) {
    return glm::all(glm::greaterThanEqual(p, lo)) && glm::all(glm::lessThanEqual(p, hi));
}

// Every invariant bvh.h promises, checked exhaustively.
void expectWellFormed(const Scene& scene, const Bvh& bvh) {
    const std::size_t n = scene.triangleCount();
    ASSERT_EQ(bvh.triangles.size(), n);
    ASSERT_EQ(bvh.primitive.size(), n);
    ASSERT_GE(bvh.nodes.size(), 1u);
    EXPECT_LE(bvh.nodes.size(), std::max<std::size_t>(1, 2 * n - 1));

    std::vector<std::uint32_t> sorted = bvh.primitive;
    std::sort(sorted.begin(), sorted.end());
    std::vector<std::uint32_t> all(n);
    std::iota(all.begin(), all.end(), 0u);
    EXPECT_EQ(sorted, all) << "every scene triangle exactly once";

    for (std::size_t i = 0; i < n; ++i) {
        const std::uint32_t p = bvh.primitive[i];
        const glm::vec3 v0 = scene.positions[scene.indices[3 * p]], v1 = scene.positions[scene.indices[3 * p + 1]],
                        v2 = scene.positions[scene.indices[3 * p + 2]];
        const BvhTriangle& t = bvh.triangles[i];
        ASSERT_EQ(t.v0, v0) << i;
        ASSERT_EQ(t.e1, v1 - v0) << i;
        ASSERT_EQ(t.e2, v2 - v0) << i;
        ASSERT_EQ(t.scenePrimitive, p) << i;
        ASSERT_EQ(t.pad1, 0.0f) << i;
        ASSERT_EQ(t.pad2, 0.0f) << i;
    }

    // Walk the tree: each node reached once, children inside parents, leaves tile [0, n).
    std::vector<int> reached(bvh.nodes.size(), 0), covered(n, 0);
    std::vector<std::uint32_t> stack{0};
    while (!stack.empty()) {
        const std::uint32_t index = stack.back();
        stack.pop_back();
        ASSERT_LT(index, bvh.nodes.size());
        ASSERT_EQ(++reached[index], 1) << "node " << index << " reached twice";
        const BvhNode& node = bvh.nodes[index];
        if (node.count == 0) {
            ASSERT_GT(node.leftOrFirst, 0u) << "interior node " << index << " points at the root";
            ASSERT_LT(node.leftOrFirst + 1, bvh.nodes.size());
            for (std::uint32_t c = node.leftOrFirst; c <= node.leftOrFirst + 1; ++c) {
                EXPECT_TRUE(inside(bvh.nodes[c].boundsMin, node.boundsMin, node.boundsMax)) << c;
                EXPECT_TRUE(inside(bvh.nodes[c].boundsMax, node.boundsMin, node.boundsMax)) << c;
                stack.push_back(c);
            }
            continue;
        }
        EXPECT_LE(node.count, kBvhMaxLeafSize) << "leaf " << index;
        ASSERT_LE(node.leftOrFirst + node.count, n) << "leaf " << index;
        for (std::uint32_t i = node.leftOrFirst; i < node.leftOrFirst + node.count; ++i) {
            ++covered[i];
            const std::uint32_t p = bvh.primitive[i];
            for (int k = 0; k < 3; ++k)
                EXPECT_TRUE(inside(scene.positions[scene.indices[3 * p + k]], node.boundsMin, node.boundsMax))
                    << "triangle " << i << " vertex " << k << " outside leaf " << index;
        }
    }
    EXPECT_EQ(std::count(reached.begin(), reached.end(), 1), std::ptrdiff_t(bvh.nodes.size())) << "unreachable nodes";
    EXPECT_EQ(std::count(covered.begin(), covered.end(), 1), std::ptrdiff_t(n)) << "leaves must tile the triangles";
    EXPECT_LE(bvhDepth(bvh), kBvhMaxDepth);
}

TEST(BvhBuild, CloisterIsWellFormed) {
    const Traced& t = traced("builtin:cloister");
    expectWellFormed(t.scene, t.bvh);
    EXPECT_EQ(t.bvh.nodes[0].boundsMin, t.scene.bounds.min);
    EXPECT_EQ(t.bvh.nodes[0].boundsMax, t.scene.bounds.max);
}

TEST(BvhBuild, SpherePlaneIsWellFormed) {
    const Traced& t = traced("builtin:sphere-plane");
    expectWellFormed(t.scene, t.bvh);
}

TEST(BvhBuild, EmptySceneIsOneEmptyLeafThatNothingHits) {
    const Scene empty = sceneOf({}, {});
    const Bvh bvh = buildBvh(empty);
    ASSERT_EQ(bvh.nodes.size(), 1u);
    EXPECT_EQ(bvh.nodes[0].count, 0u);
    EXPECT_EQ(bvh.nodes[0].leftOrFirst, 0u);
    EXPECT_TRUE(bvh.triangles.empty());
    EXPECT_TRUE(bvh.primitive.empty());
    EXPECT_EQ(bvhDepth(bvh), 0u);
    EXPECT_FALSE(bvhIntersect(bvh, glm::vec3(0.0f), glm::vec3(0.0f, 0.0f, 1.0f), 0.0f, kInf).hit);
    EXPECT_FALSE(bvhOccluded(bvh, glm::vec3(0.0f), glm::vec3(0.0f, 0.0f, 1.0f), 0.0f, kInf));
    EXPECT_FALSE(bvhOccluded(Bvh{}, glm::vec3(0.0f), glm::vec3(0.0f, 0.0f, 1.0f), 0.0f, kInf));
}

// One triangle in the plane z = 2: a root leaf. Exact answers, since every quantity is a small dyadic.
TEST(BvhTrace, SingleTriangleFromBothSidesAndItsEdges) {
    const Scene s = sceneOf({{0, 0, 2}, {1, 0, 2}, {0, 1, 2}}, {0, 1, 2});
    const Bvh bvh = buildBvh(s);
    expectWellFormed(s, bvh);
    ASSERT_EQ(bvh.nodes.size(), 1u);
    EXPECT_EQ(bvh.nodes[0].count, 1u);

    const glm::vec3 org(0.25f, 0.25f, 0.0f), forward(0.0f, 0.0f, 1.0f);  // axis-aligned: zero x, y components
    const BvhHit front = bvhIntersect(bvh, org, forward, 0.0f, kInf);
    ASSERT_TRUE(front.hit);
    EXPECT_EQ(front.t, 2.0f);
    EXPECT_EQ(front.triangle, 0u);
    const BvhHit back = bvhIntersect(bvh, glm::vec3(0.25f, 0.25f, 5.0f), -forward, 0.0f, kInf);
    ASSERT_TRUE(back.hit) << "two-sided: the back face occludes too";
    EXPECT_EQ(back.t, 3.0f);
    EXPECT_TRUE(bvhOccluded(bvh, org, forward, 0.0f, kInf));

    // tnear < t < tfar, both strict, as in Embree.
    EXPECT_FALSE(bvhOccluded(bvh, org, forward, 0.0f, 2.0f));
    EXPECT_FALSE(bvhIntersect(bvh, org, forward, 2.0f, kInf).hit);
    EXPECT_TRUE(bvhOccluded(bvh, org, forward, 0.0f, std::nextafter(2.0f, 3.0f)));
    // Unnormalised direction: t in units of its length.
    EXPECT_EQ(bvhIntersect(bvh, org, 4.0f * forward, 0.0f, kInf).t, 0.5f);

    EXPECT_FALSE(bvhOccluded(bvh, glm::vec3(0.75f, 0.75f, 0.0f), forward, 0.0f, kInf)) << "beyond the hypotenuse";
    EXPECT_FALSE(bvhOccluded(bvh, glm::vec3(-0.25f, 0.25f, 0.0f), forward, 0.0f, kInf)) << "left of the x = 0 edge";
    EXPECT_FALSE(bvhOccluded(bvh, org, -forward, 0.0f, kInf)) << "pointing away";
    EXPECT_FALSE(bvhOccluded(bvh, glm::vec3(-1.0f, 0.25f, 2.0f), glm::vec3(1.0f, 0.0f, 0.0f), 0.0f, kInf))
        << "in the triangle's plane: det == 0";
    // Oblique, through the centroid.
    const glm::vec3 centroid(1.0f / 3.0f, 1.0f / 3.0f, 2.0f), from(1.0f, -2.0f, -1.0f);
    const BvhHit oblique = bvhIntersect(bvh, from, glm::normalize(centroid - from), 0.0f, kInf);
    ASSERT_TRUE(oblique.hit);
    EXPECT_NEAR(oblique.t, glm::length(centroid - from), 1e-6f);
}

// Coincident triangles: no centroid split separates them, so the build falls back to halving the list.
TEST(BvhBuild, CoincidentTrianglesSplitInTheMiddleOfTheList) {
    std::vector<glm::vec3> positions;
    std::vector<std::uint32_t> indices;
    for (std::uint32_t i = 0; i < 37; ++i) {
        positions.insert(positions.end(), {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}});
        indices.insert(indices.end(), {3 * i, 3 * i + 1, 3 * i + 2});
    }
    const Scene s = sceneOf(positions, indices);
    const Bvh bvh = buildBvh(s);
    expectWellFormed(s, bvh);
    EXPECT_EQ(bvhDepth(bvh), 4u);  // the larger halves: 37 → 19 → 10 → 5 → 3
    const BvhHit hit = bvhIntersect(bvh, glm::vec3(0.2f, 0.2f, 1.0f), glm::vec3(0.0f, 0.0f, -1.0f), 0.0f, kInf);
    ASSERT_TRUE(hit.hit);
    EXPECT_EQ(hit.t, 1.0f);
}

// A row of ever larger gaps (x = 1.5^i): the 16 centroid bins put all but the farthest few triangles
// in bin 0, so the SAH peels a few off per level; alone it would go 33 levels deep here (measured).
// From depth 32 on the build splits at object medians, which bounds the depth, and so the traversal
// stack, by kBvhMaxDepth whatever the geometry.
TEST(BvhBuild, DepthStaysWithinTheTraversalStackOnAPeelingScene) {
    std::vector<glm::vec3> positions;
    std::vector<std::uint32_t> indices;
    constexpr std::uint32_t kCount = 200;
    for (std::uint32_t i = 0; i < kCount; ++i) {
        const float x = std::pow(1.5f, float(i));
        positions.insert(positions.end(), {{x, -1, -1}, {x, 1, -1}, {x, 0, 1}});
        indices.insert(indices.end(), {3 * i, 3 * i + 1, 3 * i + 2});
    }
    const Scene s = sceneOf(positions, indices);
    const Bvh bvh = buildBvh(s);
    expectWellFormed(s, bvh);
    EXPECT_GE(bvhDepth(bvh), 30u) << "the scene no longer exercises deep trees";
    const BvhHit first = bvhIntersect(bvh, glm::vec3(0.0f), glm::vec3(1.0f, 0.0f, 0.0f), 0.0f, kInf);
    ASSERT_TRUE(first.hit);
    EXPECT_EQ(first.t, 1.0f);
    EXPECT_EQ(first.triangle, 0u);
    // Looking back from between triangles k and k + 1 (t up to 7e16: below the 1e20 limit of bvh.h).
    for (const std::uint32_t k : {20u, 60u, 99u}) {
        const float x = std::pow(1.5f, float(k));
        const BvhHit back =
            bvhIntersect(bvh, glm::vec3(1.25f * x, 0.0f, 0.0f), glm::vec3(-1.0f, 0.0f, 0.0f), 0.0f, kInf);
        ASSERT_TRUE(back.hit) << k;
        EXPECT_EQ(back.triangle, k);
        EXPECT_NEAR(back.t, 0.25f * x, 1e-6f * x);
    }
}

// ---- the C++ traversal against Embree -----------------------------------------------------------

// Tolerances, from measurement (20k rays per scene and tfar, the seeds below; Release, x86-64, and
// llvmpipe for the GLSL):
// - hit/miss: 0 disagreements in 120k rays, for intersect and for occluded, C++ against Embree and
//   GLSL against C++. Möller–Trumbore is not watertight (Embree's robust mode is), so a ray through
//   a shared edge may slip through; the 0.1 % bound leaves room for that and for other GPUs' division.
// - t: C++ against Embree at most 2.2e-7 × the bounding-box diagonal (cloister; 1.4e-7 box room,
//   1.6e-7 sphere-plane), i.e. 2–3 float ulps of the farthest hits: the two intersectors round
//   differently. GLSL against C++ at most 1 ulp (llvmpipe fuses multiply-adds). 1e-6 × diagonal keeps
//   ≥ 4× headroom and is still 35 µm in the 34 m cloister, where AO radii are metres.
// - triangle: differs only on ties, two triangles hit at the same t within that tolerance (measured
//   ≤ 4.8e-7 m): coplanar overlapping faces (furniture standing on the floor) or a ray through a
//   shared edge. Box room 49 + 32 ties (tfar ∞, 0.5), cloister 64 + 46, sphere-plane 0; GLSL against
//   C++ none (the same traversal order).
constexpr float kTToleranceOfDiagonal = 1e-6f;
constexpr std::size_t kRays = 20000;

// One ray's answers from one tracer.
struct Answer {
    bool hit = false, occluded = false;
    float t = 0.0f;
    std::uint32_t triangle = ~0u;  // scene index
};

Answer cpuAnswer(const Bvh& bvh, const Ray& r) {
    const BvhHit h = bvhIntersect(bvh, r.org, r.dir, r.tnear, r.tfar);
    return {h.hit, bvhOccluded(bvh, r.org, r.dir, r.tnear, r.tfar), h.t, h.triangle};
}

struct Agreement {
    std::size_t rays = 0, hitDisagree = 0, occludedDisagree = 0, bothHit = 0;
    std::size_t ties = 0;              // different triangles at the same t (within tolerance)
    std::size_t triangleMismatch = 0;  // different triangles at different t
    float maxTError = 0.0f;            // over the rays both hit

    void add(const Answer& a, const Answer& b, float tTolerance) {
        ++rays;
        occludedDisagree += a.occluded != b.occluded;
        if (a.hit != b.hit) ++hitDisagree;
        if (!a.hit || !b.hit) return;
        ++bothHit;
        const float dt = std::abs(a.t - b.t);
        maxTError = std::max(maxTError, dt);
        if (a.triangle != b.triangle) ++(dt <= tTolerance ? ties : triangleMismatch);
    }
    void expectClose(float tTolerance) const {
        EXPECT_LE(hitDisagree, rays / 1000);
        EXPECT_LE(occludedDisagree, rays / 1000);
        EXPECT_LE(maxTError, tTolerance);
        EXPECT_EQ(triangleMismatch, 0u);
        EXPECT_GT(bothHit, rays / 50) << "too few hits to compare anything";
    }
};

// Origins anywhere in the scene's box (inside walls too: those rays must agree as well), directions
// uniform; tfar unbounded and 0.5 (an AO radius: many rays end in free space, testing tfar).
void expectAgreesWithEmbree(const std::string& spec, std::uint32_t seed) {
    const Traced& s = traced(spec);
    const float tTolerance = kTToleranceOfDiagonal * s.scene.bounds.diagonal();
    for (const float tfar : {kInf, 0.5f}) {
        SCOPED_TRACE(spec + ", tfar " + std::to_string(tfar));
        Agreement a;
        for (const Ray& r : randomRays(s.scene.bounds, kRays, tfar, seed)) {
            const RayHit ref = s.embree.intersect(r.org, r.dir, r.tnear, r.tfar);
            a.add(cpuAnswer(s.bvh, r),
                  {ref.hit, s.embree.occluded(r.org, r.dir, r.tnear, r.tfar), ref.t, ref.primitive}, tTolerance);
        }
        a.expectClose(tTolerance);
    }
}

TEST(BvhTrace, AgreesWithEmbreeInTheBoxRoom) { expectAgreesWithEmbree("builtin:box-room", 11u); }
TEST(BvhTrace, AgreesWithEmbreeOverTheSpherePlane) { expectAgreesWithEmbree("builtin:sphere-plane", 12u); }
TEST(BvhTrace, AgreesWithEmbreeInTheCloister) { expectAgreesWithEmbree("builtin:cloister", 13u); }

// ---- the GLSL traversal against the C++ twin ----------------------------------------------------

class BvhGl : public GlTest {};  // named Bvh* so that --gtest_filter='Bvh*' runs these too

// Traces `rays` with both GLSL functions. Per ray: t bits, BVH-order triangle, scene triangle (via
// bvhScenePrimitive), hit | occluded << 1.
std::vector<glm::uvec4> traceOnGpu(const Bvh& bvh, const std::vector<Ray>& rays) {
    const std::string src = R"(#version 450 core
#include "bvh.glsl"
layout(local_size_x = 64) in;
layout(std430, binding = 0) restrict readonly buffer Rays { vec4 rays[]; };  // org, tnear | dir, tfar
layout(std430, binding = 1) restrict writeonly buffer Results { uvec4 results[]; };
void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= uint(results.length())) return;
    vec4 a = rays[2u * i], b = rays[2u * i + 1u];
    float t;
    uint triangle;
    bool hit = bvhIntersect(a.xyz, b.xyz, a.w, b.w, t, triangle);
    bool occluded = bvhOccluded(a.xyz, b.xyz, a.w, b.w);
    results[i] = uvec4(floatBitsToUint(t), triangle, hit ? bvhScenePrimitive(triangle) : 0xffffffffu,
                       (hit ? 1u : 0u) | (occluded ? 2u : 0u));
})";
    // Not the default binding points, to exercise the defines.
    const gl::Program program = gl::buildProgram({{GL_COMPUTE_SHADER, src, "bvh_test.comp"}},
                                                 {{"BVH_NODE_BINDING", "2"}, {"BVH_TRIANGLE_BINDING", "3"}});
    std::vector<glm::vec4> packed;
    packed.reserve(2 * rays.size());
    for (const Ray& r : rays) {
        packed.emplace_back(r.org, r.tnear);
        packed.emplace_back(r.dir, r.tfar);
    }
    const GpuBvh gpuBvh(bvh);
    const gl::Buffer rayBuffer = gl::Buffer::create(), resultBuffer = gl::Buffer::create();
    glNamedBufferStorage(rayBuffer.id(), GLsizeiptr(packed.size() * sizeof(glm::vec4)), packed.data(), 0);
    glNamedBufferStorage(resultBuffer.id(), GLsizeiptr(rays.size() * sizeof(glm::uvec4)), nullptr, 0);
    glUseProgram(program.id());
    gpuBvh.bind(2, 3);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, rayBuffer.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, resultBuffer.id());
    glDispatchCompute(GLuint((rays.size() + 63) / 64), 1, 1);
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    std::vector<glm::uvec4> results(rays.size());
    glGetNamedBufferSubData(resultBuffer.id(), 0, GLsizeiptr(results.size() * sizeof(glm::uvec4)), results.data());
    EXPECT_EQ(glGetError(), static_cast<GLenum>(GL_NO_ERROR));
    return results;
}

void expectGpuMatchesTwin(const std::string& spec, std::uint32_t seed) {
    const Traced& s = traced(spec);
    const float tTolerance = kTToleranceOfDiagonal * s.scene.bounds.diagonal();
    for (const float tfar : {kInf, 0.5f}) {
        SCOPED_TRACE(spec + ", tfar " + std::to_string(tfar));
        const std::vector<Ray> rays = randomRays(s.scene.bounds, kRays, tfar, seed);
        const std::vector<glm::uvec4> gpu = traceOnGpu(s.bvh, rays);
        Agreement a;
        for (std::size_t i = 0; i < rays.size(); ++i) {
            const Answer g{bool(gpu[i].w & 1u), bool(gpu[i].w & 2u), std::bit_cast<float>(gpu[i].x), gpu[i].z};
            if (g.hit) {
                ASSERT_EQ(g.triangle, s.bvh.primitive[gpu[i].y]) << "bvhScenePrimitive, ray " << i;
            }
            a.add(g, cpuAnswer(s.bvh, rays[i]), tTolerance);
        }
        a.expectClose(tTolerance);
    }
}

TEST_F(BvhGl, GlslMatchesTheCppTwinInTheBoxRoom) { expectGpuMatchesTwin("builtin:box-room", 21u); }
TEST_F(BvhGl, GlslMatchesTheCppTwinOverTheSpherePlane) { expectGpuMatchesTwin("builtin:sphere-plane", 22u); }
TEST_F(BvhGl, GlslMatchesTheCppTwinInTheCloister) { expectGpuMatchesTwin("builtin:cloister", 23u); }

TEST_F(BvhGl, EmptySceneMissesOnTheGpu) {
    const std::vector<glm::uvec4> gpu =
        traceOnGpu(buildBvh(sceneOf({}, {})), {{glm::vec3(0.0f), glm::vec3(0.0f, 0.0f, 1.0f), 0.0f, kInf}});
    ASSERT_EQ(gpu.size(), 1u);
    EXPECT_EQ(gpu[0].w, 0u);
}

}  // namespace
}  // namespace cubeao
