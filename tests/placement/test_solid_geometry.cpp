// SolidGeometry (placement/src/solid_geometry.h): component classification, exact inside test and
// distance on small hand-built scenes whose answers are worked out by hand. Boxes from MeshBuilder carry
// their own vertices per face, so these tests also cover the merge by position.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>

#include <glm/vec3.hpp>

#include "cubeao/scene/scene.h"
#include "cubeao/scenes/mesh_builder.h"
#include "solid_geometry.h"

using cubeao::Scene;
using cubeao::placement::SolidGeometry;
using cubeao::scenes::MeshBuilder;
using glm::vec3;

namespace {

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

Scene boxScene(const vec3& lo, const vec3& hi, bool inward = false, bool bottom = true) {
    MeshBuilder b;
    b.addBox(lo, hi, inward, bottom);
    return b.take();
}

// Unit cube [0,1]^3 with its 8 corners shared by all 12 triangles, wound counter-clockwise from outside.
Scene sharedCornerCube() {
    Scene s;
    for (int i = 0; i < 8; ++i) s.positions.emplace_back(i & 1 ? 1.0f : 0.0f, i & 2 ? 1.0f : 0.0f, i & 4 ? 1.0f : 0.0f);
    const std::uint32_t faces[6][4] = {{0, 4, 6, 2}, {1, 3, 7, 5}, {0, 1, 5, 4},
                                       {2, 6, 7, 3}, {0, 2, 3, 1}, {4, 5, 7, 6}};
    for (const auto& q : faces) s.indices.insert(s.indices.end(), {q[0], q[1], q[2], q[0], q[2], q[3]});
    cubeao::finalizeScene(s);
    return s;
}

void expectCounts(const SolidGeometry& g, std::size_t solids, std::size_t rooms, std::size_t open) {
    EXPECT_EQ(g.closedSolids(), solids);
    EXPECT_EQ(g.closedRooms(), rooms);
    EXPECT_EQ(g.openComponents(), open);
}

}  // namespace

TEST(SolidGeometry, OutwardBoxIsSolid) {
    const Scene s = boxScene(vec3(0.0f), vec3(1.0f));
    ASSERT_EQ(s.triangleCount(), 12u);
    ASSERT_EQ(s.vertexCount(), 24u);  // own vertices per face: connectivity must come from positions
    const SolidGeometry g(s);
    expectCounts(g, 1, 0, 0);

    EXPECT_TRUE(g.insideClosedSolid(vec3(0.5f)));
    EXPECT_TRUE(g.insideClosedSolid(vec3(0.5f, 0.5f, 1e-6f)));  // just inside the -z face
    EXPECT_TRUE(g.insideClosedSolid(vec3(0.999f, 0.001f, 0.5f)));
    EXPECT_FALSE(g.insideClosedSolid(vec3(0.5f, 0.5f, -1e-6f)));  // just outside it
    EXPECT_FALSE(g.insideClosedSolid(vec3(1.5f, 0.5f, 0.5f)));
    EXPECT_FALSE(g.insideClosedSolid(vec3(-3.0f)));
    // On the boundary counts as not inside.
    EXPECT_FALSE(g.insideClosedSolid(vec3(0.5f, 0.5f, 0.0f)));
    EXPECT_FALSE(g.insideClosedSolid(vec3(1.0f, 0.5f, 0.5f)));
    EXPECT_FALSE(g.insideClosedSolid(vec3(1.0f, 1.0f, 0.5f)));  // on an edge
    EXPECT_FALSE(g.insideClosedSolid(vec3(kNaN, 0.5f, 0.5f)));

    EXPECT_FLOAT_EQ(g.distance(vec3(0.5f)), 0.5f);                     // inside: to the nearest face
    EXPECT_FLOAT_EQ(g.distance(vec3(0.5f, 0.25f, 0.5f)), 0.25f);
    EXPECT_FLOAT_EQ(g.distance(vec3(3.0f, 0.5f, 0.5f)), 2.0f);         // outside, facing +x
    EXPECT_FLOAT_EQ(g.distance(vec3(2.0f, 2.0f, 1.0f)), std::sqrt(2.0f));  // nearest to the edge x=y=1
    EXPECT_FLOAT_EQ(g.distance(vec3(2.0f, 3.0f, -1.0f)), std::sqrt(6.0f)); // nearest to corner (1,1,0)
    EXPECT_EQ(g.distance(vec3(1.0f, 0.5f, 0.5f)), 0.0f);
}

TEST(SolidGeometry, SharedCornerBoxIsSolid) {
    const Scene s = sharedCornerCube();
    ASSERT_EQ(s.vertexCount(), 8u);
    const SolidGeometry g(s);
    expectCounts(g, 1, 0, 0);
    EXPECT_TRUE(g.insideClosedSolid(vec3(0.5f)));
    EXPECT_TRUE(g.insideClosedSolid(vec3(0.1f, 0.9f, 0.1f)));
    EXPECT_FALSE(g.insideClosedSolid(vec3(0.5f, 1.0f, 0.5f)));
    EXPECT_FALSE(g.insideClosedSolid(vec3(0.5f, 1.1f, 0.5f)));
    EXPECT_FLOAT_EQ(g.distance(vec3(0.5f, 0.5f, 0.2f)), 0.2f);
    EXPECT_FLOAT_EQ(g.distance(vec3(0.5f, -2.0f, 0.5f)), 2.0f);
}

TEST(SolidGeometry, InwardBoxIsRoomWithNothingInside) {
    const SolidGeometry g(boxScene(vec3(0.0f), vec3(1.0f), true));
    expectCounts(g, 0, 1, 0);
    EXPECT_FALSE(g.insideClosedSolid(vec3(0.5f)));
    EXPECT_FALSE(g.insideClosedSolid(vec3(0.5f, 0.5f, 1e-6f)));
    EXPECT_FALSE(g.insideClosedSolid(vec3(2.0f)));
    // Distance does not care about winding.
    EXPECT_FLOAT_EQ(g.distance(vec3(0.5f)), 0.5f);
    EXPECT_FLOAT_EQ(g.distance(vec3(3.0f, 0.5f, 0.5f)), 2.0f);
}

TEST(SolidGeometry, RoomAroundOutwardBox) {
    MeshBuilder b;
    b.addBox(vec3(-5.0f), vec3(5.0f), true);
    b.addBox(vec3(1.0f), vec3(2.0f), false);
    const SolidGeometry g(b.take());
    expectCounts(g, 1, 1, 0);
    EXPECT_TRUE(g.insideClosedSolid(vec3(1.5f)));
    EXPECT_TRUE(g.insideClosedSolid(vec3(1.9f, 1.1f, 1.5f)));
    EXPECT_FALSE(g.insideClosedSolid(vec3(0.0f)));    // in the room, outside the box
    EXPECT_FALSE(g.insideClosedSolid(vec3(-4.0f)));
    EXPECT_FALSE(g.insideClosedSolid(vec3(2.5f, 1.5f, 1.5f)));
    EXPECT_FALSE(g.insideClosedSolid(vec3(20.0f)));   // outside both
    EXPECT_FLOAT_EQ(g.distance(vec3(0.0f)), std::sqrt(3.0f));  // to the box corner (1,1,1)
    EXPECT_FLOAT_EQ(g.distance(vec3(-4.0f, 0.0f, 0.0f)), 1.0f);  // to the room wall x=-5
    EXPECT_FLOAT_EQ(g.distance(vec3(1.5f, 1.5f, 1.25f)), 0.25f);  // inside the box
}

TEST(SolidGeometry, OpenQuad) {
    MeshBuilder b;
    // Square in y=0 facing +y.
    b.addQuad(vec3(0, 0, 0), vec3(0, 0, 1), vec3(1, 0, 1), vec3(1, 0, 0));
    const SolidGeometry g(b.take());
    expectCounts(g, 0, 0, 1);
    EXPECT_FALSE(g.insideClosedSolid(vec3(0.5f, -1.0f, 0.5f)));
    EXPECT_FALSE(g.insideClosedSolid(vec3(0.5f, 1.0f, 0.5f)));
    EXPECT_FLOAT_EQ(g.distance(vec3(0.5f, 2.0f, 0.5f)), 2.0f);
    EXPECT_FLOAT_EQ(g.distance(vec3(0.5f, -0.75f, 0.5f)), 0.75f);
    EXPECT_FLOAT_EQ(g.distance(vec3(2.0f, 0.0f, 0.5f)), 1.0f);
    EXPECT_FLOAT_EQ(g.distance(vec3(2.0f, 3.0f, 2.0f)), std::sqrt(11.0f));  // to corner (1,0,1)
}

TEST(SolidGeometry, BoxMissingFaceIsOpen) {
    const Scene s = boxScene(vec3(0.0f), vec3(1.0f), false, false);  // no -y face
    ASSERT_EQ(s.triangleCount(), 10u);
    const SolidGeometry g(s);
    expectCounts(g, 0, 0, 1);
    EXPECT_FALSE(g.insideClosedSolid(vec3(0.5f)));
    EXPECT_FALSE(g.insideClosedSolid(vec3(0.5f, 0.9f, 0.5f)));
    EXPECT_FLOAT_EQ(g.distance(vec3(0.5f)), 0.5f);
    // Below the missing face the nearest points are the bottom edges of the side faces, not the face.
    EXPECT_FLOAT_EQ(g.distance(vec3(0.5f, -0.5f, 0.5f)), std::sqrt(0.5f));
}

TEST(SolidGeometry, DoubleSidedQuadIsOpen) {
    {
        // MeshBuilder splits a-b-c-d along a-c; the reversed quad d-c-b-a splits along d-b.
        MeshBuilder b;
        const vec3 a(0, 0, 0), bb(0, 0, 1), c(1, 0, 1), d(1, 0, 0);
        b.addQuad(a, bb, c, d);
        b.addQuad(d, c, bb, a);
        const SolidGeometry g(b.take());
        expectCounts(g, 0, 0, 1);  // closed by edges but flat: encloses nothing
        EXPECT_FALSE(g.insideClosedSolid(vec3(0.5f, 0.0f, 0.5f)));
        EXPECT_FALSE(g.insideClosedSolid(vec3(0.5f, 1e-6f, 0.5f)));
        EXPECT_FLOAT_EQ(g.distance(vec3(0.5f, 1.5f, 0.5f)), 1.5f);
    }
    {
        // Same diagonal on both sides: four triangles on one edge (non-manifold).
        Scene s;
        s.positions = {{0, 0, 0}, {0, 0, 1}, {1, 0, 1}, {1, 0, 0}};
        s.indices = {0, 1, 2, 0, 2, 3, 0, 2, 1, 0, 3, 2};
        cubeao::finalizeScene(s);
        const SolidGeometry g(s);
        EXPECT_EQ(g.closedSolids(), 0u);
        EXPECT_EQ(g.closedRooms(), 0u);
        EXPECT_FALSE(g.insideClosedSolid(vec3(0.5f, 0.0f, 0.5f)));
        EXPECT_FLOAT_EQ(g.distance(vec3(0.5f, -1.5f, 0.5f)), 1.5f);
    }
}

TEST(SolidGeometry, TwoDisjointBoxes) {
    MeshBuilder b;
    b.addBox(vec3(0.0f), vec3(1.0f));
    b.addBox(vec3(3.0f), vec3(4.0f));
    const SolidGeometry g(b.take());
    expectCounts(g, 2, 0, 0);
    EXPECT_TRUE(g.insideClosedSolid(vec3(0.5f)));
    EXPECT_TRUE(g.insideClosedSolid(vec3(3.5f)));
    EXPECT_FALSE(g.insideClosedSolid(vec3(2.0f)));                 // between them
    EXPECT_FALSE(g.insideClosedSolid(vec3(0.5f, 0.5f, 3.5f)));     // inside the union of their bounds only
    EXPECT_FALSE(g.insideClosedSolid(vec3(3.5f, 3.5f, 0.5f)));
    EXPECT_FLOAT_EQ(g.distance(vec3(2.0f)), std::sqrt(3.0f));       // both corners equally far
    EXPECT_FLOAT_EQ(g.distance(vec3(3.5f, 3.5f, 2.5f)), 0.5f);      // 0.5 below the second box
}

TEST(SolidGeometry, BoxFarFromOrigin) {
    const float o = 1e5f;
    const SolidGeometry g(boxScene(vec3(o), vec3(o + 1.0f)));
    expectCounts(g, 1, 0, 0);
    EXPECT_TRUE(g.insideClosedSolid(vec3(o + 0.5f)));
    EXPECT_FALSE(g.insideClosedSolid(vec3(o + 1.5f, o + 0.5f, o + 0.5f)));
    EXPECT_FLOAT_EQ(g.distance(vec3(o + 0.5f, o + 0.5f, o + 3.0f)), 2.0f);
}

TEST(SolidGeometry, EmptyScene) {
    const Scene s;
    const SolidGeometry g(s);
    expectCounts(g, 0, 0, 0);
    const float d = g.distance(vec3(0.0f));
    EXPECT_TRUE(std::isinf(d));
    EXPECT_GT(d, 0.0f);
    EXPECT_FALSE(g.insideClosedSolid(vec3(0.0f)));
}

TEST(SolidGeometry, DegenerateNaNAndOutOfRangeTrianglesDoNotCrash) {
    {
        // Only unusable triangles: a non-finite corner, an out-of-range index. Nothing is left for distance.
        SCOPED_TRACE("only unusable triangles");
        Scene s;
        s.positions = {{0, 0, 0}, {1, 0, 0}, {kNaN, 0, 0}, {0, std::numeric_limits<float>::infinity(), 0}};
        s.indices = {0, 1, 2, 0, 1, 3, 0, 1, 99, 0, 1};  // the trailing 2 indices are no triangle
        const SolidGeometry g(s);
        expectCounts(g, 0, 0, 0);
        EXPECT_TRUE(std::isinf(g.distance(vec3(0.5f))));
        EXPECT_FALSE(g.insideClosedSolid(vec3(0.5f, 0.0f, 0.0f)));
    }
    {
        // Zero-area triangles stay for distance. One that repeats an index is no polygon at all; a collinear
        // one with three distinct corners is an open component. A box alongside them is still a solid.
        SCOPED_TRACE("degenerate triangles beside a box");
        MeshBuilder b;
        b.addBox(vec3(10.0f), vec3(11.0f));
        Scene s = b.take();
        const auto base = static_cast<std::uint32_t>(s.positions.size());
        s.positions.insert(s.positions.end(), {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {kNaN, 0, 0}});
        s.indices.insert(s.indices.end(), {base, base + 1, base + 2,   // collinear
                                           base, base, base + 1,       // repeated index
                                           base, base + 1, base + 3,   // NaN corner
                                           base, base + 1, 1000000u}); // out of range
        const SolidGeometry g(s);
        expectCounts(g, 1, 0, 1);
        EXPECT_TRUE(g.insideClosedSolid(vec3(10.5f)));
        EXPECT_FALSE(g.insideClosedSolid(vec3(1.0f, 0.0f, 0.0f)));
        EXPECT_FLOAT_EQ(g.distance(vec3(1.0f, 1.0f, 0.0f)), 1.0f);   // to the collinear segment
        EXPECT_FLOAT_EQ(g.distance(vec3(-1.0f, 0.0f, 0.0f)), 1.0f);  // to its end point (0,0,0)
    }
}
