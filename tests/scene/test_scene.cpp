// Scene arrays, hashing, vertex normals, validation and repair (src/cubeao/scene/scene.h, repair.h):
// small hand-built meshes with answers worked out by hand, and a seeded random mesh whose triangles
// must survive repair unchanged as a multiset of corner positions.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include "cubeao/core/error.h"
#include "cubeao/scene/builtin.h"
#include "cubeao/scene/repair.h"
#include "cubeao/scene/scene.h"
#include "test_util.h"

using namespace cubeao;
using namespace cubeao::test;

namespace {

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
constexpr float kInf = std::numeric_limits<float>::infinity();

Scene makeScene(const std::string& source, std::vector<glm::vec3> positions, std::vector<std::uint32_t> indices,
                std::vector<glm::vec3> normals = {}) {
    Scene s;
    s.source = source;
    s.positions = std::move(positions);
    s.indices = std::move(indices);
    s.normals = std::move(normals);
    return s;
}

// A triangle as its three corners (position, and optionally normal), rotated so the smallest corner
// comes first: that keeps the winding but forgets which corner the index list started at.
using Corner = std::array<float, 6>;
using Triangle = std::array<Corner, 3>;

std::vector<Triangle> triangleMultiset(const std::vector<glm::vec3>& positions, const std::vector<glm::vec3>& normals,
                                       const std::vector<std::uint32_t>& indices, bool withNormals) {
    std::vector<Triangle> out;
    for (std::size_t t = 0; t + 2 < indices.size(); t += 3) {
        Triangle tri;
        for (int k = 0; k < 3; ++k) {
            const glm::vec3 p = positions.at(indices[t + k]);
            const glm::vec3 n = withNormals ? normals.at(indices[t + k]) : glm::vec3(0.0f);
            tri[k] = {p.x, p.y, p.z, n.x, n.y, n.z};
        }
        const auto first = std::min_element(tri.begin(), tri.end()) - tri.begin();
        std::rotate(tri.begin(), tri.begin() + first, tri.end());
        out.push_back(tri);
    }
    std::sort(out.begin(), out.end());
    return out;
}

std::vector<Triangle> triangleMultiset(const Scene& s, bool withNormals = false) {
    return triangleMultiset(s.positions, s.normals, s.indices, withNormals);
}

void expectUnitNormals(const Scene& s) {
    ASSERT_EQ(s.normals.size(), s.positions.size());
    for (std::size_t i = 0; i < s.normals.size(); ++i)
        EXPECT_NEAR(glm::length(s.normals[i]), 1.0f, 1e-6f) << "vertex " << i;
}

void expectVec3Near(const glm::vec3& actual, const glm::vec3& expected, float tol) {
    EXPECT_NEAR(actual.x, expected.x, tol);
    EXPECT_NEAR(actual.y, expected.y, tol);
    EXPECT_NEAR(actual.z, expected.z, tol);
}

// Unit square in z = 0 as two counter-clockwise triangles (normal +z).
Scene unitQuad(const std::string& source = "test:quad") {
    return makeScene(source, {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}}, {0, 1, 2, 0, 2, 3});
}

}  // namespace

// ---- geometryHash / finalizeScene --------------------------------------------------------------

// Caches store the scene hash and refuse another scene's ("baked for scene 0x…"): a change to the hash
// (its byte order, its fields, the hasher, or a built-in scene's triangles) makes every cache users
// have baked unusable, so the values are pinned. Change them only with a cache format version.
TEST(SceneHash, IsPinnedBecauseCachesStoreIt) {
    const Scene a = unitQuad();
    EXPECT_EQ(hashToString(geometryHash(a.positions, a.indices)), "0x353c09e1925297e9");
    // A recentred scene hashes its origin too (a shifted model is another scene).
    const glm::dvec3 origin(5500000256.0, -1024.0, 0.0);
    EXPECT_EQ(hashToString(geometryHash(a.positions, a.indices, origin)), "0xcf172d9df9e56f4d");
    EXPECT_EQ(hashToString(makeBuiltinScene("builtin:box-room").hash), "0x7ce9a00d576baa53");
}

TEST(SceneHash, EqualInputGivesEqualHash) {
    const Scene a = unitQuad(), b = unitQuad();
    EXPECT_EQ(geometryHash(a.positions, a.indices), geometryHash(b.positions, b.indices));
}

TEST(SceneHash, ChangesWhenOneCoordinateChanges) {
    const Scene a = unitQuad();
    Scene b = unitQuad();
    b.positions[2].y = std::nextafter(1.0f, 2.0f);  // the smallest possible change
    EXPECT_NE(geometryHash(a.positions, a.indices), geometryHash(b.positions, b.indices));
}

TEST(SceneHash, ChangesWhenOneIndexChanges) {
    const Scene a = unitQuad();
    Scene b = unitQuad();
    b.indices[5] = 1;
    EXPECT_NE(geometryHash(a.positions, a.indices), geometryHash(b.positions, b.indices));
    Scene c = unitQuad();
    std::swap(c.indices[1], c.indices[2]);  // same numbers, other order (flipped winding)
    EXPECT_NE(geometryHash(a.positions, a.indices), geometryHash(c.positions, c.indices));
}

TEST(SceneHash, IndependentOfNormalsAndSource) {
    Scene a = unitQuad("a.obj");
    Scene b = unitQuad("b.obj");
    a.normals.assign(4, glm::vec3(0, 0, 1));
    b.normals.assign(4, glm::vec3(1, 0, 0));
    finalizeScene(a);
    finalizeScene(b);
    EXPECT_EQ(a.hash, b.hash);
    EXPECT_EQ(a.hash, geometryHash(a.positions, a.indices));
}

TEST(SceneHash, HashToStringIsZeroPaddedHex) {
    EXPECT_EQ(hashToString(0x1234u), "0x0000000000001234");
    EXPECT_EQ(hashToString(0xfedcba9876543210ull), "0xfedcba9876543210");
}

TEST(SceneFinalize, BoundsCoverAllPositions) {
    Scene s = makeScene("test:bounds", {{1, -2, 3}, {-4, 5, 0.5f}, {2, 0, -6}}, {0, 1, 2});
    finalizeScene(s);
    EXPECT_FALSE(s.bounds.empty());
    EXPECT_EQ(s.bounds.min, glm::vec3(-4, -2, -6));
    EXPECT_EQ(s.bounds.max, glm::vec3(2, 5, 3));
    expectVec3Near(s.bounds.center(), glm::vec3(-1, 1.5f, -1.5f), 1e-6f);
    const float diag = std::sqrt(6.0f * 6.0f + 7.0f * 7.0f + 9.0f * 9.0f);
    EXPECT_NEAR(s.bounds.diagonal(), diag, 1e-5f);
    EXPECT_NEAR(s.defaultRadius(), 0.02f * diag, 1e-6f);
}

TEST(SceneFinalize, RecomputesBoundsAfterChange) {
    Scene s = unitQuad();
    finalizeScene(s);
    const std::uint64_t before = s.hash;
    s.positions[1] = {0.5f, 0, 0};  // shrinks the box in x only
    finalizeScene(s);
    EXPECT_EQ(s.bounds.max, glm::vec3(1, 1, 0));
    s.positions[2] = {0.5f, 1, 0};
    finalizeScene(s);
    EXPECT_EQ(s.bounds.max, glm::vec3(0.5f, 1, 0));
    EXPECT_NE(s.hash, before);
}

TEST(SceneFinalize, EmptyBounds) {
    const Bounds b;
    EXPECT_TRUE(b.empty());
    EXPECT_EQ(b.diagonal(), 0.0f);
}

// ---- computeVertexNormals ----------------------------------------------------------------------

TEST(SceneNormals, AreaWeightedTowardsTheBiggerTriangle) {
    // Vertex 0 is shared by a big triangle in z = 0 (area 50, normal +z) and a small one in x = 0
    // (area 0.5, normal +x). Cross products are 2 × area × normal, so vertex 0 gets (1, 0, 100)/|…|.
    const std::vector<glm::vec3> p = {{0, 0, 0}, {10, 0, 0}, {0, 10, 0}, {0, 1, 0}, {0, 0, 1}};
    const std::vector<std::uint32_t> idx = {0, 1, 2, 0, 3, 4};
    std::vector<glm::vec3> n;
    EXPECT_EQ(computeVertexNormals(p, idx, n, glm::vec3(0, 1, 0)), 0u);
    ASSERT_EQ(n.size(), p.size());
    expectVec3Near(n[0], glm::vec3(1, 0, 100) / std::sqrt(10001.0f), 1e-6f);
    EXPECT_GT(n[0].z, 0.99f);  // leans to the big triangle's normal
    expectVec3Near(n[1], glm::vec3(0, 0, 1), 1e-6f);
    expectVec3Near(n[2], glm::vec3(0, 0, 1), 1e-6f);
    expectVec3Near(n[3], glm::vec3(1, 0, 0), 1e-6f);
    expectVec3Near(n[4], glm::vec3(1, 0, 0), 1e-6f);
}

TEST(SceneNormals, UnitLength) {
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> u(-100.0f, 100.0f);
    std::vector<glm::vec3> p(60);
    for (auto& v : p) v = {u(rng), u(rng), u(rng)};
    std::vector<std::uint32_t> idx;
    for (std::uint32_t i = 0; i + 2 < p.size(); ++i) idx.insert(idx.end(), {i, i + 1, i + 2});
    std::vector<glm::vec3> n;
    EXPECT_EQ(computeVertexNormals(p, idx, n, glm::vec3(0, 1, 0)), 0u);
    ASSERT_EQ(n.size(), p.size());
    for (std::size_t i = 0; i < n.size(); ++i) EXPECT_NEAR(glm::length(n[i]), 1.0f, 1e-6f) << "vertex " << i;
}

TEST(SceneNormals, CancellingTwoSidedPairUsesFallback) {
    // Triangle 0-1-2 written twice with opposite winding: its vertices' normals sum to zero.
    // Vertices 3-4-5 form an ordinary triangle; vertex 6 is used by nothing (no normal either).
    const std::vector<glm::vec3> p = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {5, 0, 0}, {6, 0, 0}, {5, 0, -1}, {9, 9, 9}};
    const std::vector<std::uint32_t> idx = {0, 1, 2, 0, 2, 1, 3, 4, 5};
    const glm::vec3 fallback(0, 0, -1);
    std::vector<glm::vec3> n;
    EXPECT_EQ(computeVertexNormals(p, idx, n, fallback), 4u);
    ASSERT_EQ(n.size(), p.size());
    for (int i : {0, 1, 2, 6}) EXPECT_EQ(n[i], fallback) << "vertex " << i;
    for (int i : {3, 4, 5}) expectVec3Near(n[i], glm::vec3(0, 1, 0), 1e-6f);
}

// ---- validateMesh ------------------------------------------------------------------------------

TEST(SceneValidate, GoodMeshPasses) {
    Scene s = unitQuad();
    EXPECT_NO_THROW(validateMesh(s));
    s.normals.assign(4, glm::vec3(0, 0, 1));
    EXPECT_NO_THROW(validateMesh(s));
}

TEST(SceneValidate, NoTriangles) {
    const Scene s = makeScene("empty.obj", {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {});
    const std::string msg = errorMessage([&] { validateMesh(s); });
    EXPECT_NE(msg.find("empty.obj"), std::string::npos) << msg;
    EXPECT_NE(msg.find("no triangles"), std::string::npos) << msg;
}

TEST(SceneValidate, IndexCountNotMultipleOfThree) {
    const Scene s = makeScene("four.obj", {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {0, 1, 2, 0});
    const std::string msg = errorMessage([&] { validateMesh(s); });
    EXPECT_NE(msg.find("four.obj"), std::string::npos) << msg;
    EXPECT_NE(msg.find("index count 4 is not a multiple of 3"), std::string::npos) << msg;
}

TEST(SceneValidate, IndexOutOfRange) {
    const Scene s = makeScene("range.obj", {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {0, 1, 2, 0, 2, 9});
    const std::string msg = errorMessage([&] { validateMesh(s); });
    EXPECT_NE(msg.find("range.obj"), std::string::npos) << msg;
    EXPECT_NE(msg.find("1 indices are out of range"), std::string::npos) << msg;
    EXPECT_NE(msg.find("triangle 1 refers to vertex 9 of 3"), std::string::npos) << msg;
}

TEST(SceneValidate, NaNAndInfCoordinates) {
    const Scene nan = makeScene("nan.obj", {{0, 0, 0}, {kNaN, 0, 0}, {0, 1, 0}}, {0, 1, 2});
    std::string msg = errorMessage([&] { validateMesh(nan); });
    EXPECT_NE(msg.find("nan.obj"), std::string::npos) << msg;
    EXPECT_NE(msg.find("1 vertices have NaN/Inf coordinates (first: vertex 1)"), std::string::npos) << msg;

    const Scene inf = makeScene("inf.obj", {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, -kInf}}, {0, 1, 2});
    msg = errorMessage([&] { validateMesh(inf); });
    EXPECT_NE(msg.find("inf.obj"), std::string::npos) << msg;
    EXPECT_NE(msg.find("NaN/Inf"), std::string::npos) << msg;
    EXPECT_NE(msg.find("first: vertex 3"), std::string::npos) << msg;
}

TEST(SceneValidate, NormalsCountMismatch) {
    const Scene s = makeScene("normals.obj", {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {0, 1, 2}, {{0, 0, 1}, {0, 0, 1}});
    const std::string msg = errorMessage([&] { validateMesh(s); });
    EXPECT_NE(msg.find("normals.obj"), std::string::npos) << msg;
    EXPECT_NE(msg.find("2 normals for 3 vertices"), std::string::npos) << msg;
}

TEST(SceneValidate, ReportsEveryProblemAtOnce) {
    const Scene s = makeScene("many.obj", {{0, 0, 0}, {kNaN, 0, 0}, {0, 1, 0}}, {0, 1, 2, 7}, {{0, 0, 1}});
    const std::string msg = errorMessage([&] { validateMesh(s); });
    EXPECT_NE(msg.find("many.obj"), std::string::npos) << msg;
    EXPECT_NE(msg.find("not a multiple of 3"), std::string::npos) << msg;
    EXPECT_NE(msg.find("NaN/Inf"), std::string::npos) << msg;
    EXPECT_NE(msg.find("out of range"), std::string::npos) << msg;
    EXPECT_NE(msg.find("1 normals for 3 vertices"), std::string::npos) << msg;
}

// ---- repairMesh / prepareScene -----------------------------------------------------------------

TEST(RepairMesh, MergesExactDuplicatesOnly) {
    // A quad written STL-style: every triangle repeats its corners (6 vertices, 4 distinct), plus a
    // third triangle whose corner is one ulp away from a quad corner: close is not identical.
    const float nearOne = std::nextafter(1.0f, 2.0f);
    Scene s = makeScene("dup.stl",
                        {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 0, 0}, {1, 1, 0}, {0, 1, 0},  //
                         {nearOne, 0, 0}, {2, 0, 0}, {2, 1, 0}},
                        {0, 1, 2, 3, 4, 5, 6, 7, 8});
    const auto before = triangleMultiset(s);
    prepareScene(s, false);
    EXPECT_EQ(s.problems.duplicateVertices, 2u);
    EXPECT_EQ(s.problems.degenerateTriangles, 0u);
    EXPECT_EQ(s.problems.unusedVertices, 2u);  // the two copies the merge left unreferenced
    EXPECT_EQ(s.vertexCount(), 7u);
    EXPECT_EQ(s.triangleCount(), 3u);
    EXPECT_EQ(triangleMultiset(s), before);
}

TEST(RepairMesh, SamePositionDifferentNormalIsNotADuplicate) {
    // A hard edge: two faces meet at x = 1 with their own normals; merging would smooth the edge.
    Scene s = makeScene("hard.obj", {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {1, 0, 0}, {1, 0, -1}, {1, 1, 0}},
                        {0, 1, 2, 3, 4, 5}, {{0, 0, 1}, {0, 0, 1}, {0, 0, 1}, {1, 0, 0}, {1, 0, 0}, {1, 0, 0}});
    const auto before = triangleMultiset(s, true);
    prepareScene(s, true);
    EXPECT_EQ(s.problems.duplicateVertices, 0u);
    EXPECT_EQ(s.vertexCount(), 6u);
    EXPECT_FALSE(s.problems.normalsComputed);
    EXPECT_EQ(triangleMultiset(s, true), before);
}

TEST(RepairMesh, RemovesZeroAreaTriangles) {
    // Vertices 4 and 5 share a position but not a normal, so they stay two vertices and the triangle
    // 4-5-1 is degenerate by position, not by index.
    Scene s = makeScene("degenerate.obj",
                        {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {2, 0, 0}, {5, 5, 5}, {5, 5, 5}, {0, 0, 1e-3f}},
                        {0, 1, 2,    // good
                         0, 0, 1,    // repeated index
                         4, 5, 1,    // repeated position
                         0, 1, 3,    // collinear along x
                         0, 1, 6},   // thin but not zero area: kept
                        {{0, 0, 1}, {0, 0, 1}, {0, 0, 1}, {0, 0, 1}, {0, 1, 0}, {1, 0, 0}, {0, -1, 0}});
    prepareScene(s, true);
    EXPECT_EQ(s.problems.degenerateTriangles, 3u);
    EXPECT_EQ(s.triangleCount(), 2u);
    const auto expected = triangleMultiset(std::vector<glm::vec3>{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1e-3f}}, {},
                                           {0, 1, 2, 0, 1, 3}, false);
    EXPECT_EQ(triangleMultiset(s), expected);
    // Vertices 3, 4 and 5 were used only by degenerate triangles.
    EXPECT_EQ(s.problems.unusedVertices, 3u);
    EXPECT_EQ(s.vertexCount(), 4u);
}

TEST(RepairMesh, RemovesUnusedVertices) {
    Scene s = makeScene("unused.obj", {{7, 7, 7}, {0, 0, 0}, {1, 0, 0}, {8, 8, 8}, {0, 1, 0}, {9, 9, 9}}, {1, 2, 4});
    prepareScene(s, false);
    EXPECT_EQ(s.problems.unusedVertices, 3u);
    EXPECT_EQ(s.vertexCount(), 3u);
    EXPECT_EQ(s.normals.size(), 3u);
    EXPECT_EQ(s.bounds.min, glm::vec3(0, 0, 0));  // the unused (7..9) corners no longer count
    EXPECT_EQ(s.bounds.max, glm::vec3(1, 1, 0));
    for (std::uint32_t i : s.indices) EXPECT_LT(i, s.vertexCount());
}

TEST(RepairMesh, KeepsGeometryWithUnusedVerticesFirstAndScrambledIndices) {
    // Unused vertices before the used ones, indices visiting vertices out of order and reusing them,
    // a duplicate of a used vertex and a degenerate triangle: the surviving triangles, as corner
    // positions with their winding, must be exactly the input's non-degenerate ones.
    Scene s = makeScene("scrambled.obj",
                        {{100, 100, 100}, {200, 200, 200},               // 0, 1 unused
                         {0, 0, 0}, {3, 0, 0}, {3, 2, 0}, {0, 2, 0},     // 2..5 a rectangle
                         {300, 300, 300},                                 // 6 unused
                         {1.5f, 1, 4}, {3, 0, 0}},                        // 7 apex, 8 duplicate of 3
                        {7, 4, 5,  // apex triangles, highest index first
                         5, 2, 7,  //
                         8, 4, 7,  // uses the duplicate of 3
                         2, 8, 7,  //
                         4, 3, 2,  // rectangle, reversed order
                         5, 2, 4,  //
                         3, 8, 7}, // degenerate: 3 and 8 are the same vertex
                        {});
    std::vector<std::uint32_t> good(s.indices.begin(), s.indices.end() - 3);
    const auto expected = triangleMultiset(s.positions, {}, good, false);
    prepareScene(s, false);
    EXPECT_EQ(s.problems.duplicateVertices, 1u);
    EXPECT_EQ(s.problems.degenerateTriangles, 1u);
    EXPECT_EQ(s.problems.unusedVertices, 4u);  // 0, 1, 6 and the merged copy 8
    EXPECT_EQ(s.vertexCount(), 5u);
    EXPECT_EQ(s.triangleCount(), 6u);
    EXPECT_EQ(triangleMultiset(s), expected);
    EXPECT_EQ(s.hash, geometryHash(s.positions, s.indices));
    EXPECT_EQ(s.bounds.min, glm::vec3(0, 0, 0));
    EXPECT_EQ(s.bounds.max, glm::vec3(3, 2, 4));
}

TEST(RepairMesh, KeepsGeometryOfRandomSoup) {
    // 400 random triangles over a shuffled vertex array with unused vertices spread through it,
    // every vertex written twice (exact duplicates), plus degenerate triangles of each kind.
    std::mt19937 rng(12345);
    std::uniform_real_distribution<float> u(-10.0f, 10.0f);
    const std::size_t kUsed = 300, kUnused = 50;
    std::vector<glm::vec3> distinct(kUsed + kUnused);
    for (auto& p : distinct) p = {u(rng), u(rng), u(rng)};
    // Axis-aligned unit normals: exactly unit length, so repair's normalisation leaves their bits alone.
    const std::array<glm::vec3, 6> axes = {{{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}}};
    std::uniform_int_distribution<int> pickAxis(0, 5);
    std::vector<glm::vec3> normals(distinct.size());
    for (auto& n : normals) n = axes[pickAxis(rng)];
    // Array layout: every distinct vertex twice, shuffled.
    std::vector<std::uint32_t> slot(2 * distinct.size());
    for (std::size_t i = 0; i < slot.size(); ++i) slot[i] = std::uint32_t(i % distinct.size());
    std::shuffle(slot.begin(), slot.end(), rng);
    std::vector<std::vector<std::uint32_t>> where(distinct.size());
    Scene s;
    s.source = "random.obj";
    for (std::size_t i = 0; i < slot.size(); ++i) {
        s.positions.push_back(distinct[slot[i]]);
        s.normals.push_back(normals[slot[i]]);
        where[slot[i]].push_back(std::uint32_t(i));
    }
    std::uniform_int_distribution<std::uint32_t> pickUsed(0, kUsed - 1);
    std::uniform_int_distribution<int> pickCopy(0, 1);
    auto idx = [&](std::uint32_t v) { return where[v][pickCopy(rng)]; };
    std::vector<std::uint32_t> good;
    for (int t = 0; t < 400; ++t) {
        std::uint32_t a = pickUsed(rng), b = pickUsed(rng), c = pickUsed(rng);
        if (a == b || b == c || a == c) continue;
        good.insert(good.end(), {idx(a), idx(b), idx(c)});
    }
    s.indices = good;
    std::size_t degenerate = 0;
    for (int t = 0; t < 30; ++t) {
        const std::uint32_t a = pickUsed(rng), b = pickUsed(rng);
        if (a == b) continue;
        s.indices.insert(s.indices.end(), {idx(a), idx(a), idx(b)});                // same vertex twice
        s.indices.insert(s.indices.end(), {where[a][0], idx(b), where[a][1]});     // a and its copy
        degenerate += 2;
    }
    const auto expected = triangleMultiset(s.positions, s.normals, good, true);
    prepareScene(s, true);
    EXPECT_EQ(s.problems.duplicateVertices, distinct.size());
    EXPECT_EQ(s.problems.degenerateTriangles, degenerate);
    EXPECT_EQ(s.triangleCount(), good.size() / 3);
    EXPECT_LE(s.vertexCount(), kUsed);
    EXPECT_EQ(s.problems.unusedVertices, 2 * distinct.size() - s.vertexCount());
    EXPECT_EQ(triangleMultiset(s, true), expected);
    expectUnitNormals(s);
}

TEST(RepairMesh, OnlyDegenerateTrianglesIsAnError) {
    Scene s = makeScene("flat.obj", {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {4, 4, 4}}, {0, 1, 2, 3, 3, 0});
    const std::string msg = errorMessage([&] { prepareScene(s, false); });
    EXPECT_NE(msg.find("flat.obj"), std::string::npos) << msg;
    EXPECT_NE(msg.find("all 2 triangles have zero area"), std::string::npos) << msg;
}

TEST(RepairMesh, PrepareValidatesBeforeRepair) {
    Scene s = makeScene("bad.obj", {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {0, 1, 5});
    const std::string msg = errorMessage([&] { prepareScene(s, false); });
    EXPECT_NE(msg.find("bad.obj"), std::string::npos) << msg;
    EXPECT_NE(msg.find("out of range"), std::string::npos) << msg;
}

TEST(RepairMesh, NormalsMadeUnitAndBadOnesReplaced) {
    // Two triangles in z = 0 (area-weighted normal +z everywhere). File normals: one too long, one
    // zero, one NaN, one tiny, and a good one slanted away from +z that must be kept as written.
    const glm::vec3 slanted = glm::normalize(glm::vec3(1, 0, 1));
    Scene s = makeScene("normals.obj", {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0.5f, 0.5f, 0}},
                        {0, 1, 4, 1, 2, 4, 2, 3, 4, 3, 0, 4},
                        {{0, 0, 5}, {0, 0, 0}, {kNaN, 0, 1}, {0, 1e-9f, 0}, slanted});
    prepareScene(s, true);
    EXPECT_FALSE(s.problems.normalsComputed);
    EXPECT_EQ(s.problems.zeroNormals, 0u);
    EXPECT_EQ(s.vertexCount(), 5u);
    expectUnitNormals(s);
    for (std::size_t i = 0; i < s.vertexCount(); ++i) {
        const glm::vec3 expected = s.positions[i] == glm::vec3(0.5f, 0.5f, 0) ? slanted : glm::vec3(0, 0, 1);
        expectVec3Near(s.normals[i], expected, 1e-6f);
    }
}

TEST(RepairMesh, ComputedNormalsWhenFileHasNone) {
    Scene s = unitQuad("computed.obj");
    prepareScene(s, false);
    EXPECT_TRUE(s.problems.normalsComputed);
    EXPECT_EQ(s.problems.zeroNormals, 0u);
    ASSERT_EQ(s.normals.size(), 4u);
    for (const glm::vec3& n : s.normals) expectVec3Near(n, glm::vec3(0, 0, 1), 1e-6f);

    // "hasNormals" with the wrong number of normals cannot be trusted either.
    Scene t = unitQuad("mismatch.obj");
    t.normals = {{1, 0, 0}};
    repairMesh(t, true);
    EXPECT_TRUE(t.problems.normalsComputed);
    ASSERT_EQ(t.normals.size(), 4u);
    for (const glm::vec3& n : t.normals) expectVec3Near(n, glm::vec3(0, 0, 1), 1e-6f);
}

TEST(RepairMesh, UndefinedNormalsBecomeUpAndAreCounted) {
    // A two-sided pair (same triangle, both windings) has cancelling area-weighted normals.
    Scene s = makeScene("twosided.obj", {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {0, 1, 2, 0, 2, 1});
    s.up = glm::vec3(0, 0, 1);
    prepareScene(s, false);
    EXPECT_EQ(s.triangleCount(), 2u);
    EXPECT_EQ(s.problems.zeroNormals, 3u);
    for (const glm::vec3& n : s.normals) EXPECT_EQ(n, glm::vec3(0, 0, 1));
}

// ---- checkWinding -------------------------------------------------------------------------------

namespace {

// A closed tetrahedron, every face counter-clockwise seen from outside: 6 edges, each run both ways.
Scene tetrahedron(bool flipLast, bool splitCorners) {
    const std::vector<glm::vec3> p{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    std::vector<std::array<std::uint32_t, 3>> faces{{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
    if (flipLast) std::swap(faces[3][1], faces[3][2]);
    std::vector<glm::vec3> positions;
    std::vector<std::uint32_t> indices;
    for (const auto& f : faces)
        for (std::uint32_t v : f) {
            // Split corners: every face its own copy of each position (as a file with face normals has it).
            if (splitCorners) {
                indices.push_back(std::uint32_t(positions.size()));
                positions.push_back(p[v]);
            } else {
                indices.push_back(v);
            }
        }
    return makeScene("tet.obj", splitCorners ? positions : p, indices);
}

}  // namespace

TEST(SceneWinding, ClosedConsistentMeshHasNoFlippedEdge) {
    const WindingCheck w = checkWinding(tetrahedron(false, false));
    EXPECT_EQ(w.sharedEdges, 6u);
    EXPECT_EQ(w.flippedEdges, 0u);
}

TEST(SceneWinding, OneFlippedFaceFlipsItsThreeEdges) {
    const WindingCheck w = checkWinding(tetrahedron(true, false));
    EXPECT_EQ(w.sharedEdges, 6u);
    EXPECT_EQ(w.flippedEdges, 3u);
    EXPECT_DOUBLE_EQ(w.flippedShare(), 0.5);
}

TEST(SceneWinding, CornersSplitByNormalsAreStillOneEdge) {
    EXPECT_EQ(checkWinding(tetrahedron(false, true)).flippedEdges, 0u);
    const WindingCheck w = checkWinding(tetrahedron(true, true));
    EXPECT_EQ(w.sharedEdges, 6u);
    EXPECT_EQ(w.flippedEdges, 3u);
}

TEST(SceneWinding, BoundaryAndNonManifoldEdgesAreNotCounted) {
    // Three triangles on one edge (a fin) and one lone triangle: no edge is shared by exactly two.
    const Scene s = makeScene("fin.obj", {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {5, 5, 5}, {6, 5, 5}, {5, 6, 5}},
                              {0, 1, 2, 1, 0, 3, 0, 1, 4, 5, 6, 7});
    EXPECT_EQ(checkWinding(s).sharedEdges, 0u);
}
