// Probe placement (placement/, issue 12): voting against the grid and the camera path on small scenes
// whose answer is known by construction, the free-space guarantee, monotone coverage, the budget,
// determinism, and coverage feedback on a builtin scene.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <vector>

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/vec2.hpp>

#include "cubeao/placement/probe_set.h"
#include "cubeao/core/camera.h"
#include "cubeao/core/error.h"
#include "cubeao/placement/coverage.h"
#include "cubeao/placement/coverage_feedback.h"
#include "cubeao/placement/error_feedback.h"
#include "cubeao/placement/free_space.h"
#include "cubeao/placement/place.h"
#include "cubeao/placement/placement.h"
#include "cubeao/placement/walk_scatter.h"
#include "cubeao/reference/embree_scene.h"
#include "cubeao/scene/builtin.h"
#include "cubeao/scene/import.h"
#include "cubeao/scene/scene.h"
#include "cubeao/scenes/mesh_builder.h"
#include "site_greedy.h"

namespace cubeao::placement {
namespace {

using scenes::MeshBuilder;

// An axis-aligned rectangle from `lo` to `hi` (equal in exactly one coordinate, the plane's axis),
// facing `normal` (±1 on that axis): the corners are ordered counter-clockwise seen from that side.
void rect(MeshBuilder& b, const glm::vec3& lo, const glm::vec3& hi, const glm::vec3& normal) {
    int axis = 0;
    for (int a = 0; a < 3; ++a)
        if (lo[a] == hi[a]) axis = a;
    const int u = (axis + 1) % 3, v = (axis + 2) % 3;  // e_u × e_v = e_axis
    auto corner = [&](float cu, float cv) {
        glm::vec3 p = lo;
        p[u] = cu;
        p[v] = cv;
        return p;
    };
    const glm::vec3 a = corner(lo[u], lo[v]), b1 = corner(hi[u], lo[v]), c = corner(hi[u], hi[v]),
                    d = corner(lo[u], hi[v]);
    if (normal[axis] > 0.0f)
        b.addQuad(a, b1, c, d);
    else
        b.addQuad(d, c, b1, a);
}

Scene finish(MeshBuilder& b, const char* name) {
    Scene scene = b.take();
    scene.source = name;
    finalizeScene(scene);
    return scene;
}

PlaceSettings coarse(const Scene& scene, double target) {
    PlaceSettings s;
    const glm::vec3 extent = scene.bounds.max - scene.bounds.min;
    s.voxel = std::max({extent.x, extent.y, extent.z}) / 25.0f;
    s.samples = 2000;
    s.votingRays = 16;
    // A coarse bake (64² faces) and a lenient texel (radius / 2): a probe covers out to a few metres,
    // so distance decides as much as visibility.
    s.res = 64;
    s.texelsPerRadius = 2.0f;
    s.target = target;
    s.seed = 7;
    return s;
}

std::vector<glm::vec3> positionsOf(const Placement& r) {
    std::vector<glm::vec3> p;
    for (const PlacedProbe& probe : r.probes) p.push_back(probe.position);
    return p;
}

bool inBox(const glm::vec3& p, const glm::vec3& lo, const glm::vec3& hi) {
    return glm::all(glm::greaterThanEqual(p, lo)) && glm::all(glm::lessThanEqual(p, hi));
}

// Relevant area, and the part of it that `probes` cover, of the relevant samples `select` picks.
std::pair<double, double> coveredArea(const PlacementScene& ps, const std::vector<glm::vec3>& probes, auto select) {
    std::vector<std::uint8_t> hit(ps.samples().size(), 0);
    for (const glm::vec3& p : probes)
        for (const std::uint32_t i : ps.covered(p)) hit[i] = 1;
    double relevant = 0.0, covered = 0.0;
    for (std::size_t i = 0; i < ps.samples().size(); ++i) {
        if (!ps.relevant()[i] || !select(ps.samples()[i])) continue;
        relevant += ps.samples()[i].area;
        if (hit[i]) covered += ps.samples()[i].area;
    }
    return {relevant, covered};
}

// ---- Two rooms joined by a door ---------------------------------------------------------------------

constexpr float kH = 2.5f;                   // ceiling height of both rooms
constexpr float kAx1 = 3.0f, kBx0 = 3.2f;    // room A x ∈ [0, 3], the wall, room B x ∈ [3.2, 10.2]
constexpr float kBx1 = 10.2f, kDepth = 4.0f;  // both z ∈ [0, 4]
constexpr float kDoorZ0 = 1.6f, kDoorZ1 = 2.4f, kDoorH = 2.0f;

// One room's five plain faces, its inner wall (at x = wallX, facing `wallNormal`) with the door cut out.
void roomWithDoor(MeshBuilder& b, float x0, float x1, float wallX, float wallNormal) {
    rect(b, {x0, 0, 0}, {x1, 0, kDepth}, {0, 1, 0});     // floor
    rect(b, {x0, kH, 0}, {x1, kH, kDepth}, {0, -1, 0});  // ceiling
    rect(b, {x0, 0, 0}, {x1, kH, 0}, {0, 0, 1});
    rect(b, {x0, 0, kDepth}, {x1, kH, kDepth}, {0, 0, -1});
    const float outerX = wallX == x0 ? x1 : x0;
    rect(b, {outerX, 0, 0}, {outerX, kH, kDepth}, {-wallNormal, 0, 0});
    rect(b, {wallX, 0, 0}, {wallX, kH, kDoorZ0}, {wallNormal, 0, 0});
    rect(b, {wallX, 0, kDoorZ1}, {wallX, kH, kDepth}, {wallNormal, 0, 0});
    rect(b, {wallX, kDoorH, kDoorZ0}, {wallX, kH, kDoorZ1}, {wallNormal, 0, 0});
}

Scene twoRooms() {
    MeshBuilder b;
    roomWithDoor(b, 0.0f, kAx1, kAx1, -1.0f);
    roomWithDoor(b, kBx0, kBx1, kBx0, 1.0f);
    // The door's reveal through the wall's thickness.
    rect(b, {kAx1, 0, kDoorZ0}, {kBx0, kDoorH, kDoorZ0}, {0, 0, 1});
    rect(b, {kAx1, 0, kDoorZ1}, {kBx0, kDoorH, kDoorZ1}, {0, 0, -1});
    rect(b, {kAx1, kDoorH, kDoorZ0}, {kBx0, kDoorH, kDoorZ1}, {0, -1, 0});
    rect(b, {kAx1, 0, kDoorZ0}, {kBx0, 0, kDoorZ1}, {0, 1, 0});
    return finish(b, "test:two-rooms");
}

TEST(Placement, TwoRoomsVotingBeatsGrid) {
    const Scene scene = twoRooms();
    PlaceSettings s = coarse(scene, 0.95);
    s.texelsPerRadius = 3.0f;  // reach 2.4: room B (7 long) needs several probes; the doorway sees neither far wall
    const PlacementScene ps(scene, s, nullptr);
    // The threshold keeps a probe from covering both rooms: from the middle of the doorway the far
    // walls of both rooms lie beyond the criterion's reach.
    const float reach = ps.criterion().maxDistance();
    const glm::vec3 door(0.5f * (kAx1 + kBx0), 1.0f, 0.5f * (kDoorZ0 + kDoorZ1));
    ASSERT_LT(reach, door.x);
    ASSERT_LT(reach, kBx1 - door.x);

    // The grid searches the coarsest lattice that reaches the coverage target; voting (issue 31) then
    // gets exactly as many probes and must predict less error with them, and cover at least as much.
    const Placement grid = placeGrid(ps);
    ASSERT_GE(grid.probes.size(), 2u);
    PlaceSettings equal = s;
    equal.budget = int(grid.probes.size());
    const PlacementScene ps2(scene, equal, nullptr);
    const Placement voting = placeVoting(ps2);
    const Placement gridAgain = evaluate(ps2, positionsOf(grid), "grid");
    std::printf("two rooms: reach %.2f, grid %zu probes coverage %.4f predicted MAE %.4f; voting %zu probes "
                "coverage %.4f predicted MAE %.4f\n", reach, grid.probes.size(), gridAgain.coverage,
                gridAgain.predictedMae, voting.probes.size(), voting.coverage, voting.predictedMae);
    EXPECT_EQ(voting.probes.size(), grid.probes.size());
    EXPECT_LT(voting.predictedMae, gridAgain.predictedMae);
    EXPECT_GE(voting.coverage, s.target);

    int inA = 0, inB = 0;
    for (const PlacedProbe& p : voting.probes) {
        inA += p.position.x < kAx1 ? 1 : 0;
        inB += p.position.x > kBx0 ? 1 : 0;
    }
    EXPECT_GE(inA, 1);
    EXPECT_GE(inB, 1);
    // Both rooms' relevant samples are covered, each on its own: neither room is left behind.
    auto inRoom = [&](float x0, float x1) {
        return [=](const SurfaceSample& smp) { return smp.position.x >= x0 && smp.position.x <= x1; };
    };
    const auto [areaA, coveredA] = coveredArea(ps2, positionsOf(voting), inRoom(0.0f, kAx1));
    const auto [areaB, coveredB] = coveredArea(ps2, positionsOf(voting), inRoom(kBx0, kBx1));
    ASSERT_GT(areaA, 0.0);
    ASSERT_GT(areaB, 0.0);
    EXPECT_GE(coveredA / areaA, 0.9) << "room A";
    EXPECT_GE(coveredB / areaB, 0.9) << "room B";
}

// ---- An L-shaped corridor -----------------------------------------------------------------------

constexpr float kCorridorH = 2.4f, kLeg = 6.0f, kWidth = 1.2f;
// Plan (x, z): leg 1 is [0, 6] × [0, 1.2], leg 2 is [4.8, 6] × [0, 6].
const glm::vec2 kLOutline[6] = {{0, 0}, {kLeg, 0}, {kLeg, kLeg}, {kLeg - kWidth, kLeg},
                                {kLeg - kWidth, kWidth}, {0, kWidth}};

Scene lCorridor() {
    MeshBuilder b;
    const float x1 = kLeg - kWidth;
    for (const float y : {0.0f, kCorridorH}) {
        const glm::vec3 n(0, y == 0.0f ? 1.0f : -1.0f, 0);
        rect(b, {0, y, 0}, {kLeg, y, kWidth}, n);
        rect(b, {x1, y, kWidth}, {kLeg, y, kLeg}, n);
    }
    rect(b, {0, 0, 0}, {kLeg, kCorridorH, 0}, {0, 0, 1});
    rect(b, {kLeg, 0, 0}, {kLeg, kCorridorH, kLeg}, {-1, 0, 0});
    rect(b, {x1, 0, kLeg}, {kLeg, kCorridorH, kLeg}, {0, 0, -1});
    // The inner walls are the faces of a solid core: left open, the quarter of the bounding box outside
    // the L would be free space too (rays from it escape), and probes would go there to cover the
    // walls' outer sides, as the library's definition of free space intends.
    b.addBox({0, 0, kWidth}, {x1, kCorridorH, kLeg}, /*inward=*/false, /*bottom=*/true);
    rect(b, {0, 0, 0}, {0, kCorridorH, kWidth}, {1, 0, 0});
    return finish(b, "test:l-corridor");
}

// Distance from p to the outside of the corridor (0 or less when p is not inside it), computed from
// the plan, not from the mesh: the corridor is a prism over the L outline.
float depthInCorridor(const glm::vec3& p) {
    const glm::vec2 q(p.x, p.z);
    const bool leg1 = q.x > 0 && q.x < kLeg && q.y > 0 && q.y < kWidth;
    const bool leg2 = q.x > kLeg - kWidth && q.x < kLeg && q.y > 0 && q.y < kLeg;
    if (!(leg1 || leg2) || p.y <= 0 || p.y >= kCorridorH) return 0.0f;
    float d = std::min(p.y, kCorridorH - p.y);
    for (int k = 0; k < 6; ++k) {
        const glm::vec2 a = kLOutline[k], e = kLOutline[(k + 1) % 6] - a;
        const float t = glm::clamp(glm::dot(q - a, e) / glm::dot(e, e), 0.0f, 1.0f);
        d = std::min(d, glm::distance(q, a + t * e));
    }
    return d;
}

TEST(Placement, LCorridorProbesKeepClearance) {
    const Scene scene = lCorridor();
    const PlaceSettings s = coarse(scene, 0.95);
    const PlacementScene ps(scene, s, nullptr);
    const Placement voting = placeVoting(ps);
    std::printf("L corridor: clearance %.3f, voting %zu probes coverage %.4f\n", ps.freeSpace().clearance(),
                voting.probes.size(), voting.coverage);
    EXPECT_GE(voting.coverage, s.target);
    ASSERT_FALSE(voting.probes.empty());
    const float clearance = ps.freeSpace().clearance();
    EXPECT_GT(clearance, 0.0f);
    for (const PlacedProbe& p : voting.probes)
        EXPECT_GE(depthInCorridor(p.position), clearance - 1e-4f)
            << "probe at " << p.position.x << ", " << p.position.y << ", " << p.position.z;
}

// ---- An alcove seen from one spot ---------------------------------------------------------------

// Room [0, 8] × [0, 3] × [0, 5]; in its far wall (z = 5) an alcove 1 wide, 2.4 high, 3 deep.
constexpr float kRoomW = 8.0f, kRoomH = 3.0f, kRoomD = 5.0f;
constexpr float kAlcX0 = 3.5f, kAlcX1 = 4.5f, kAlcH = 2.4f, kAlcBack = 8.0f;

Scene alcoveRoom() {
    MeshBuilder b;
    rect(b, {0, 0, 0}, {kRoomW, 0, kRoomD}, {0, 1, 0});
    rect(b, {0, kRoomH, 0}, {kRoomW, kRoomH, kRoomD}, {0, -1, 0});
    rect(b, {0, 0, 0}, {kRoomW, kRoomH, 0}, {0, 0, 1});
    rect(b, {0, 0, 0}, {0, kRoomH, kRoomD}, {1, 0, 0});
    rect(b, {kRoomW, 0, 0}, {kRoomW, kRoomH, kRoomD}, {-1, 0, 0});
    rect(b, {0, 0, kRoomD}, {kAlcX0, kRoomH, kRoomD}, {0, 0, -1});
    rect(b, {kAlcX1, 0, kRoomD}, {kRoomW, kRoomH, kRoomD}, {0, 0, -1});
    rect(b, {kAlcX0, kAlcH, kRoomD}, {kAlcX1, kRoomH, kRoomD}, {0, 0, -1});
    rect(b, {kAlcX0, 0, kRoomD}, {kAlcX1, 0, kAlcBack}, {0, 1, 0});
    rect(b, {kAlcX0, kAlcH, kRoomD}, {kAlcX1, kAlcH, kAlcBack}, {0, -1, 0});
    rect(b, {kAlcX0, 0, kRoomD}, {kAlcX0, kAlcH, kAlcBack}, {1, 0, 0});
    rect(b, {kAlcX1, 0, kRoomD}, {kAlcX1, kAlcH, kAlcBack}, {-1, 0, 0});
    rect(b, {kAlcX0, 0, kAlcBack}, {kAlcX1, kAlcH, kAlcBack}, {0, 0, -1});
    return finish(b, "test:alcove");
}

// A walk along z = 1.5 looking at the near wall (z = 0); the one frame in the middle turns round and
// looks straight into the alcove, 6.5 from its back wall.
CameraPath alcoveWalk() {
    CameraPath path;
    path.width = 64;
    path.height = 36;
    path.fovYDeg = 60.0f;
    for (int i = 0; i < 9; ++i) {
        const float x = 0.8f + 0.8f * float(i);
        const glm::vec3 eye(x, 1.6f, 1.5f);
        if (i == 4)
            path.frames.push_back({eye, {0.5f * (kAlcX0 + kAlcX1), 1.2f, kAlcBack}});
        else
            path.frames.push_back({eye, {x, 1.4f, -1.0f}});
    }
    return path;
}

// place(): one entry to every method, by name; the path method is the walk's eyes spread evenly.
TEST(Placement, PlaceByNameRunsTheMethodAndPathSpreadsTheWalksEyes) {
    for (const Method m : {Method::Voting, Method::Live, Method::Coverage, Method::Grid, Method::Path})
        EXPECT_EQ(parseMethod(methodName(m)), m);
    EXPECT_THROW(parseMethod("nearest"), UsageError);
    EXPECT_TRUE(needsWalk(Method::Path) && needsWalk(Method::Live) && needsWalk(Method::Coverage));
    EXPECT_FALSE(needsWalk(Method::Voting) || needsWalk(Method::Grid));
    EXPECT_THROW(checkMethodSettings(Method::Path, PlaceSettings{}), UsageError);  // path needs a budget

    const Scene scene = alcoveRoom();
    const CameraPath path = alcoveWalk();
    PlaceSettings s = coarse(scene, 0.95);
    s.budget = 3;
    const PlacementScene ps(scene, s, &path);
    const Placement along = place(Method::Path, ps, &path);
    ASSERT_EQ(along.probes.size(), 3u);
    const std::vector<ProbeSpec> eyes = probesAlongPath(path, 3);
    for (std::size_t i = 0; i < 3; ++i) EXPECT_EQ(along.probes[i].position, eyes[i].position) << i;
    EXPECT_EQ(place(Method::Voting, ps, &path).probes.size(), 3u);
    EXPECT_THROW(place(Method::Live, ps, nullptr), Error);  // live walks a camera path
}

// The benchmarks' scatter: `count` points, each within reach of the eye polyline (here a bent walk,
// reach 0.5, so a point off the polyline's segments by more than that is wrong), the same every run.
TEST(Placement, ScatterAroundWalkStaysWithinReachOfTheWalk) {
    CameraPath walk;
    for (const glm::vec3 eye : {glm::vec3(0, 1, 0), glm::vec3(4, 1, 0), glm::vec3(4, 1, 3)})
        walk.frames.push_back({eye, eye + glm::vec3(0, 0, -1)});
    const auto reach = [](const glm::vec3&, const glm::vec3&) { return 0.5f; };
    const std::vector<glm::vec3> points = scatterAroundWalk(walk, 200, reach);
    ASSERT_EQ(points.size(), 200u);
    float farthest = 0.0f, spanX = 0.0f, spanZ = 0.0f;
    for (const glm::vec3& p : points) {
        float nearest = 1e9f;
        for (std::size_t i = 0; i + 1 < walk.frames.size(); ++i) {
            const glm::vec3 a = walk.frames[i].eye, b = walk.frames[i + 1].eye;
            const float t = std::clamp(glm::dot(p - a, b - a) / glm::dot(b - a, b - a), 0.0f, 1.0f);
            nearest = std::min(nearest, glm::distance(p, a + t * (b - a)));
        }
        farthest = std::max(farthest, nearest);
        spanX = std::max(spanX, p.x), spanZ = std::max(spanZ, p.z);
    }
    EXPECT_LE(farthest, 0.5f + 1e-4f);
    EXPECT_GT(spanX, 3.5f);  // both legs of the walk are visited
    EXPECT_GT(spanZ, 2.5f);
    EXPECT_EQ(scatterAroundWalk(walk, 200, reach), points);
}

TEST(Placement, AlcoveSeenOnceVotingServesItPathCannot) {
    const Scene scene = alcoveRoom();
    const CameraPath path = alcoveWalk();
    PlaceSettings s = coarse(scene, 0.95);
    // The alcove fills little of the walk's images (one frame in nine looks in, its back wall 6.5 away,
    // 0.3 % of the pixels): by the error people see (issue 31) the first probes belong in the room, and
    // the automatic stop spends none on the back wall. Given probes enough, voting reaches into the
    // alcove, which no probe on the walk's line can.
    s.budget = 24;
    const PlacementScene ps(scene, s, &path);
    // Physically true by construction: every path probe stands at z = 1.5, beyond reach of the back wall.
    ASSERT_LT(ps.criterion().maxDistance(), kAlcBack - 1.5f);

    const Placement voting = placeVoting(ps);
    std::vector<glm::vec3> along;
    for (const ProbeSpec& p : probesAlongPath(path, voting.probes.size())) along.push_back(p.position);
    const Placement walk = evaluate(ps, along, "path");
    std::printf("alcove: reach %.2f, voting %zu probes coverage %.4f predicted %.4f; path %zu probes coverage %.4f "
                "predicted %.4f\n", ps.criterion().maxDistance(), voting.probes.size(), voting.coverage,
                voting.predictedMae, walk.probes.size(), walk.coverage, walk.predictedMae);

    EXPECT_EQ(voting.probes.size(), 24u);
    EXPECT_LT(voting.predictedMae, walk.predictedMae);
    EXPECT_LT(walk.coverage, voting.coverage);
    auto backWall = [](const SurfaceSample& smp) {
        return smp.position.z > kAlcBack - 1e-3f && smp.normal.z < -0.5f;
    };
    auto alcove = [](const SurfaceSample& smp) { return smp.position.z > kRoomD + 1e-3f; };
    const auto [backArea, backByVoting] = coveredArea(ps, positionsOf(voting), backWall);
    const auto [backArea2, backByPath] = coveredArea(ps, along, backWall);
    const auto [alcoveArea, alcoveByVoting] = coveredArea(ps, positionsOf(voting), alcove);
    const auto [alcoveArea2, alcoveByPath] = coveredArea(ps, along, alcove);
    std::printf("alcove: back wall relevant %.3f, voting %.3f, path %.3f; alcove relevant %.3f, voting %.3f, "
                "path %.3f\n", backArea, backByVoting, backByPath, alcoveArea, alcoveByVoting, alcoveByPath);
    ASSERT_GT(backArea, 0.0) << "the frame looking in must make the back wall relevant";
    EXPECT_GT(backByVoting, 0.0);
    EXPECT_EQ(backByPath, 0.0);
    EXPECT_GE(alcoveByVoting / alcoveArea, 0.25);
    EXPECT_EQ(alcoveByPath, 0.0);
}

// ---- A closed box in a room ---------------------------------------------------------------------

TEST(Placement, ClosedBoxInsideIsNotRelevant) {
    const glm::vec3 boxLo(2.0f, 0.0f, 2.0f), boxHi(3.5f, 1.2f, 3.5f);
    MeshBuilder b;
    b.addBox({0, 0, 0}, {6, 3, 6}, /*inward=*/true);
    b.addBox(boxLo, boxHi, /*inward=*/false, /*bottom=*/true);
    const Scene scene = finish(b, "test:box-in-room");
    const PlaceSettings s = coarse(scene, 0.99);
    const PlacementScene ps(scene, s, nullptr);

    // A sample stands for the side its normal points to: just off the surface on that side.
    std::size_t insideRelevant = 0, insideAll = 0;
    for (std::size_t i = 0; i < ps.samples().size(); ++i) {
        const SurfaceSample& smp = ps.samples()[i];
        const glm::vec3 side = smp.position + 1e-3f * smp.normal;
        if (!(glm::all(glm::greaterThan(side, boxLo)) && glm::all(glm::lessThan(side, boxHi)))) continue;
        ++insideAll;
        if (ps.relevant()[i]) ++insideRelevant;
    }
    EXPECT_GT(insideAll, 50u);  // the box's inner faces and the floor under it are sampled
    EXPECT_EQ(insideRelevant, 0u);

    const Placement voting = placeVoting(ps);
    std::printf("box in room: %zu inner samples, voting %zu probes coverage %.4f\n", insideAll,
                voting.probes.size(), voting.coverage);
    EXPECT_GE(voting.coverage, 0.99);
    for (const PlacedProbe& p : voting.probes) EXPECT_FALSE(inBox(p.position, boxLo, boxHi));
}

// ---- Monotone coverage, budget, determinism -----------------------------------------------------

TEST(Placement, CoverageGrowsBudgetHoldsSameSeedSameProbes) {
    const Scene scene = twoRooms();
    const PlaceSettings s = coarse(scene, 0.95);
    const PlacementScene ps(scene, s, nullptr);
    const Placement voting = placeVoting(ps);
    ASSERT_GE(voting.probes.size(), 2u);
    for (const PlacedProbe& p : voting.probes) {
        EXPECT_GE(p.gain, 0.0);
        EXPECT_GE(p.gain2, 0.0);
    }
    const std::vector<glm::vec3> all = positionsOf(voting);
    double last = 0.0;
    for (std::size_t k = 0; k <= all.size(); ++k) {
        const Placement prefix = evaluate(ps, std::vector<glm::vec3>(all.begin(), all.begin() + std::ptrdiff_t(k)),
                                          "prefix");
        EXPECT_GE(prefix.coverage, last) << k << " probes";
        // probes.json's gain of probe k is what it adds to the probes before it.
        if (k > 0) {
            EXPECT_NEAR(voting.probes[k - 1].gain, prefix.coverage - last, 1e-9) << k << " probes";
        }
        last = prefix.coverage;
    }
    EXPECT_DOUBLE_EQ(last, voting.coverage);

    PlaceSettings budget = s;
    budget.budget = 2;
    budget.target = 1.0;
    const PlacementScene ps2(scene, budget, nullptr);
    const Placement limited = placeVoting(ps2);
    EXPECT_LE(limited.probes.size(), 2u);
    EXPECT_GE(limited.probes.size(), 1u);
    const Placement limitedGrid = placeGrid(ps2);
    EXPECT_LE(limitedGrid.probes.size(), 2u);

    // Same seed, same probes, bit for bit (a second scene of its own: nothing cached is shared).
    const PlacementScene again(scene, s, nullptr);
    const Placement repeat = placeVoting(again);
    ASSERT_EQ(repeat.probes.size(), voting.probes.size());
    for (std::size_t k = 0; k < all.size(); ++k) {
        EXPECT_EQ(std::memcmp(&repeat.probes[k].position, &voting.probes[k].position, sizeof(glm::vec3)), 0) << k;
        EXPECT_EQ(repeat.probes[k].gain, voting.probes[k].gain) << k;
    }
    EXPECT_EQ(repeat.coverage, voting.coverage);
    EXPECT_EQ(repeat.coverage2, voting.coverage2);
}

// ---- Coverage feedback on a builtin scene -------------------------------------------------------

// builtin:box-room with its own walk, settings under which a probe covers a few metres, and the
// placement scene they make.
PlaceSettings boxRoomSettings(const Scene& scene) {
    PlaceSettings s = coarse(scene, 0.95);
    s.samples = 1500;
    s.votingRays = 12;
    s.res = 128;
    s.texelsPerRadius = 4.0f;
    return s;
}

struct BoxRoomWalk {
    Scene scene = loadScene("builtin:box-room");
    CameraPath path = resolveCameraPath("", "builtin:box-room");
    PlaceSettings settings = boxRoomSettings(scene);
    PlacementScene ps{scene, settings, &path};
};

TEST(Placement, CoverageFeedbackReachesTargetOnBoxRoom) {
    const BoxRoomWalk room;
    const auto& [scene, path, s, ps] = room;
    ASSERT_FALSE(path.frames.empty());
    const Placement r = placeCoverage(ps, path);
    std::printf("box-room feedback: reach %.2f, %zu probes, coverage %.4f\n", ps.criterion().maxDistance(),
                r.probes.size(), r.coverage);
    ASSERT_FALSE(r.probes.empty());
    EXPECT_GE(r.coverage, s.target);
}

// ---- Free space whichever way faces point; the expected-error objective (issue 31) ---------------

// A copy of `scene` with the triangles `flip` picks wound the other way, every triangle on vertices of
// its own whose normal follows its (new) winding: what a CAD export with reversed faces and no
// normals imports as.
Scene withFlipped(const Scene& scene, auto flip) {
    Scene out;
    out.source = scene.source + " (flipped)";
    for (std::size_t t = 0; t < scene.triangleCount(); ++t) {
        glm::vec3 p[3];
        for (int k = 0; k < 3; ++k) p[k] = scene.positions[scene.indices[3 * t + std::size_t(k)]];
        if (flip(t)) std::swap(p[1], p[2]);
        const glm::vec3 n = glm::normalize(glm::cross(p[1] - p[0], p[2] - p[0]));
        for (int k = 0; k < 3; ++k) {
            out.indices.push_back(std::uint32_t(out.positions.size()));
            out.positions.push_back(p[k]);
            out.normals.push_back(n);
        }
    }
    finalizeScene(out);
    return out;
}

// A walk from room A through the door into room B and back, eyes at 1.6 m looking ahead.
CameraPath twoRoomsWalk() {
    CameraPath path;
    path.width = 64;
    path.height = 36;
    path.fovYDeg = 60.0f;
    const float z = 0.5f * (kDoorZ0 + kDoorZ1);
    for (int i = 0; i < 24; ++i) {
        const float u = float(i) / 23.0f, x = 0.6f + u * (kBx1 - 1.2f);
        const glm::vec3 eye(x, 1.6f, z + 0.8f * std::sin(6.2831853f * u));
        path.frames.push_back({eye, eye + glm::vec3(1.0f, -0.1f, i % 2 ? 0.4f : -0.4f)});
    }
    return path;
}

// Settings at the bake's real scale for the error model: a 128² bake, texels judged against R.
PlaceSettings errorSettings(const Scene& scene) {
    PlaceSettings s = coarse(scene, 0.95);
    s.res = 128;
    s.texelsPerRadius = 16.0f;
    s.radius = 0.5f;
    return s;
}

TEST(PlacementError, ModelGrowsWithTheTexelAndOcclusionAndStopsAtTheFallback) {
    const ErrorModel m;
    const float l = 0.5f;  // the occluders' mean distance
    for (const float o : {0.0f, 0.3f, 1.0f}) {
        EXPECT_FLOAT_EQ(m.expected(INFINITY, l, o), m.fallback(o)) << o;
        EXPECT_NEAR(m.expected(0.0f, l, o), std::min(m.fallback(o), m.occluded * o), 1e-7f) << o;
        float last = 0.0f;
        for (const float side : {0.0f, 0.001f, 0.01f, 0.05f, 0.2f, 1.0f, 10.0f}) {
            const float e = m.expected(side * side, l, o);
            EXPECT_GE(e, last) << side << " at occlusion " << o;
            EXPECT_LE(e, m.fallback(o)) << side << " at occlusion " << o;
            last = e;
        }
        EXPECT_FLOAT_EQ(last, m.fallback(o)) << "a texel 20 L wide is no better than screen space, occlusion " << o;
    }
    // Open surface (nothing within R): every texel gets it right, as screen space does.
    EXPECT_FLOAT_EQ(m.expected(1.0f, l, 0.0f), 0.0f);
    EXPECT_FLOAT_EQ(m.fallback(0.0f), 0.0f);
    // At equal texels the more occluded sample, and the one with nearer occluders, expects more error.
    EXPECT_LT(m.expected(0.01f * 0.01f, l, 0.2f), m.expected(0.01f * 0.01f, l, 0.8f));
    EXPECT_LT(m.expected(0.01f * 0.01f, l, 0.5f), m.expected(0.01f * 0.01f, 0.5f * l, 0.5f));
}

// A probe serves what the projection's depth test accepts, not all it sees: the distance cube keeps
// the nearest of each coarse texel's fine texels, so a far wall seen just past the edge of a near plate
// in the same coarse texel is hidden at run time, and placement must not count it as served.
TEST(PlacementError, ServedIsWhatTheDepthTestAcceptsBesideASilhouette) {
    MeshBuilder b;
    rect(b, {-20, -20, 10}, {20, 20, 10}, {0, 0, -1});  // the far wall, facing the probe at the origin
    rect(b, {-5, -5, 2}, {0.1f, 5, 2}, {0, 0, -1});     // a near plate whose edge is at tan 0.05
    const Scene scene = finish(b, "silhouette");
    const EmbreeScene embree(scene);
    // 64² faces: the distance cube is 16², a coarse texel spans tan 0.125 and holds 4 × 4 fine texels
    // of tan 1/32; the plate's edge (tan 0.05) cuts the coarse texel [0, 0.125) between them.
    const CoverageCriterion criterion{64, 100.0f, 0.05f};
    const glm::vec3 probe(0.0f);
    const glm::vec3 toProbe(0, 0, -1);
    const std::vector<SurfaceSample> samples = {
        {{0.8f, 0.3f, 10.0f}, toProbe, 1.0f, 0},   // tan 0.08: past the edge, in its coarse texel
        {{2.0f, 0.3f, 10.0f}, toProbe, 1.0f, 0},   // tan 0.2: a coarse texel of the far wall alone
        {{-2.0f, 0.3f, 10.0f}, toProbe, 1.0f, 0},  // behind the plate: not even seen
        {{-2.0f, 0.3f, 2.0f}, toProbe, 1.0f, 1},   // on the plate: seen and served
    };
    const std::vector<std::uint8_t> relevant(samples.size(), 1);
    const std::vector<SampleView> seen = visibleSamples(embree, samples, relevant, criterion, probe);
    std::vector<std::uint32_t> seenIds, servedIds;
    for (const SampleView& v : seen) seenIds.push_back(v.sample);
    EXPECT_EQ(seenIds, (std::vector<std::uint32_t>{0, 1, 3}));
    for (const SampleView& v : servedSamples(embree, samples, criterion, probe, seen)) servedIds.push_back(v.sample);
    EXPECT_EQ(servedIds, (std::vector<std::uint32_t>{1, 3})) << "the wall beside the plate's silhouette is hidden";
}

TEST(PlacementError, GainIsWhatThePredictedErrorFalls) {
    const Scene scene = twoRooms();
    const CameraPath walk = twoRoomsWalk();
    const PlacementScene ps(scene, errorSettings(scene), &walk);
    ExpectedError e(ps);
    // Nothing served: screen space everywhere, the image-weighted mean of each sample's fallback.
    double fallback = 0.0, weight = 0.0;
    for (std::size_t i = 0; i < ps.samples().size(); ++i) {
        fallback += double(ps.weights()[i]) * double(ps.errorModel().fallback(ps.occlusion()[i]));
        weight += double(ps.weights()[i]);
    }
    ASSERT_GT(weight, 0.0);
    EXPECT_NEAR(e.mae(), fallback / weight, 1e-6);
    double last = e.mae();
    for (const glm::vec3& p : {walk.frames[3].eye, walk.frames[20].eye, walk.frames[4].eye}) {
        const std::vector<SampleView> views = ps.views(p);
        ASSERT_FALSE(views.empty());
        const double gain = e.gain(views);
        e.add(views);
        EXPECT_NEAR(last - e.mae(), gain, 1e-9);
        EXPECT_GE(gain, 0.0);
        last = e.mae();
    }
    EXPECT_LT(last, 0.5 * fallback / weight);
}

TEST(PlacementError, ReversedFacesGiveTheSameFreeSpaceAndProbesOfTheSameQuality) {
    const Scene original = twoRooms();
    const CameraPath walk = twoRoomsWalk();
    std::uint32_t state = 12345u;  // a fixed "random" half
    std::vector<std::uint8_t> half(original.triangleCount());
    for (auto& h : half) state = state * 1664525u + 1013904223u, h = std::uint8_t(state >> 31);
    const Scene all = withFlipped(original, [](std::size_t) { return true; });
    const Scene some = withFlipped(original, [&](std::size_t t) { return half[t] != 0; });
    const Scene same = withFlipped(original, [](std::size_t) { return false; });

    const PlaceSettings s = errorSettings(original);
    const PlacementScene base(same, s, &walk);
    const Placement reference = placeVoting(base);
    ASSERT_FALSE(reference.probes.empty());
    for (const Scene* scene : {&all, &some}) {
        for (const CameraPath* path : {&walk, static_cast<const CameraPath*>(nullptr)}) {
            const PlacementScene ps(*scene, s, path);
            SCOPED_TRACE(std::string(scene == &all ? "all" : "half") + " reversed, " + (path ? "walk" : "no walk"));
            if (path) {
                // Reached from the walk's eyes: the very same voxels, whatever the winding.
                EXPECT_EQ(ps.freeSpace().stats().candidates, base.freeSpace().stats().candidates);
                EXPECT_EQ(ps.freeSpace().stats().reached, base.freeSpace().stats().reached);
            }
            EXPECT_GT(ps.freeSpace().stats().candidates, base.freeSpace().stats().candidates / 2);
            const Placement r = placeVoting(ps);
            ASSERT_FALSE(r.probes.empty());
            for (const PlacedProbe& p : r.probes) {
                const bool inRoom = inBox(p.position, {0, 0, 0}, {kAx1, kH, kDepth}) ||
                                    inBox(p.position, {kBx0, 0, 0}, {kBx1, kH, kDepth});
                EXPECT_TRUE(inRoom) << p.position.x << ", " << p.position.y << ", " << p.position.z;
            }
            if (path) {
                std::printf("two rooms %s: %zu probes, predicted MAE %.4f (as wound: %zu, %.4f)\n",
                            scene == &all ? "all reversed" : "half reversed", r.probes.size(), r.predictedMae,
                            reference.probes.size(), reference.predictedMae);
                // The same samples, free space, votes and eyes whatever the winding: the same probes.
                EXPECT_EQ(r.probes.size(), reference.probes.size());
                EXPECT_NEAR(r.predictedMae, reference.predictedMae, 1e-9);
            }
        }
    }
}

TEST(PlacementError, EveryMethodPlacesProbesForAWalkThroughAReversedModel) {
    const Scene scene = withFlipped(twoRooms(), [](std::size_t) { return true; });
    const CameraPath walk = twoRoomsWalk();
    PlaceSettings s = errorSettings(scene);
    s.budget = 6;  // grid: at most; path: how many
    const PlacementScene ps(scene, s, &walk);
    std::vector<glm::vec3> along;
    for (const ProbeSpec& p : probesAlongPath(walk, 6)) along.push_back(p.position);
    const Placement voting = placeVoting(ps), grid = placeGrid(ps), coverage = placeCoverage(ps, walk),
                    live = placeFeedback(ps, walk, 1), path = evaluate(ps, along, "path");
    for (const Placement* r : {&voting, &grid, &coverage, &live, &path}) {
        EXPECT_FALSE(r->probes.empty()) << r->method;
        for (const PlacedProbe& p : r->probes) EXPECT_TRUE(ps.freeSpace().isFree(p.position) || r == &path) << r->method;
    }
    EXPECT_EQ(voting.probes.size(), 6u);  // --budget is exact
    EXPECT_EQ(voting.stop, "budget");
    // The walk's eyes are candidates and the path set is the fallback: never worse than it.
    EXPECT_LE(voting.predictedMae, path.predictedMae + 1e-9);
}

TEST(PlacementError, SealedReversedModelWithoutAWalkStillFindsItsRooms) {
    const Scene scene = withFlipped(twoRooms(), [](std::size_t) { return true; });
    const PlacementScene ps(scene, errorSettings(scene), nullptr);
    EXPECT_TRUE(ps.freeSpace().stats().roomiestSeed);
    const Placement r = placeVoting(ps);
    ASSERT_FALSE(r.probes.empty());
    int inA = 0, inB = 0;
    for (const PlacedProbe& p : r.probes) {
        inA += inBox(p.position, {0, 0, 0}, {kAx1, kH, kDepth});
        inB += inBox(p.position, {kBx0, 0, 0}, {kBx1, kH, kDepth});
    }
    EXPECT_GE(inA, 1);  // the flood went through the door
    EXPECT_GE(inB, 1);
    EXPECT_EQ(inA + inB, int(r.probes.size()));
}

// Live placement on the predicted error (error_feedback.h), frame by frame along the walk, comes near
// offline voting, which sees the whole walk at once, at the same probe count; it is as blind to the
// winding as voting, and says why when it cannot place.
TEST(PlacementError, LiveErrorFeedbackComesNearVotingAtEqualCount) {
    const Scene scene = twoRooms();
    const CameraPath walk = twoRoomsWalk();
    PlaceSettings s = errorSettings(scene);
    const PlacementScene ps(scene, s, &walk);
    const Placement live = placeFeedback(ps, walk, 1);
    ASSERT_FALSE(live.probes.empty());
    const double fallback = ExpectedError(ps).mae();
    s.budget = int(live.probes.size());
    const PlacementScene same(scene, s, &walk);
    const Placement voting = placeVoting(same);
    std::printf("two rooms: live %zu probes, predicted MAE %.4f; voting at the same count %.4f; screen space %.4f\n",
                live.probes.size(), live.predictedMae, voting.predictedMae, fallback);
    EXPECT_LT(live.predictedMae, 0.5 * fallback);
    EXPECT_LE(live.predictedMae, 1.2 * voting.predictedMae);
    // Every probe removed error when it came (gains of the probes in their order, over the whole walk).
    for (const PlacedProbe& p : live.probes) EXPECT_GE(p.errorRemoved, 0.0);
    // With every frame counted the walk so far is the whole walk at the end: the weights are the
    // frames' image shares summed where the scene's are averaged, so the same MAE as evaluate()'s.
    ASSERT_EQ(live.figures.back().first, "predicted_mae_walk_so_far");
    EXPECT_NEAR(live.figures.back().second, live.predictedMae, 1e-3 * live.predictedMae);

    const Scene reversed = withFlipped(scene, [](std::size_t) { return true; });
    const PlacementScene rps(reversed, errorSettings(scene), &walk);
    const Placement mirrored = placeFeedback(rps, walk, 1);
    ASSERT_EQ(mirrored.probes.size(), live.probes.size());
    for (std::size_t i = 0; i < live.probes.size(); ++i) EXPECT_EQ(mirrored.probes[i].position, live.probes[i].position);
}

// The automatic stop (no --budget, no --target-error) is a promise about the set, not only about the
// order the greedy found it in: given all the others, each probe removes at least kAutomaticStop of the
// predicted error, so no probe is paid for (bytes, bake time) that the picture does not need.
TEST(PlacementError, AutomaticStopKeepsOnlyProbesThatRemoveTheirShare) {
    for (const bool alcove : {false, true}) {
        const Scene scene = alcove ? alcoveRoom() : twoRooms();
        const CameraPath walk = alcove ? alcoveWalk() : twoRoomsWalk();
        const PlacementScene ps(scene, errorSettings(scene), &walk);
        const Placement voting = placeVoting(ps);
        ASSERT_EQ(voting.stop, "automatic") << alcove;
        ASSERT_GT(voting.probes.size(), 1u) << alcove;
        std::vector<std::vector<SampleView>> views;
        for (const PlacedProbe& p : voting.probes) views.push_back(ps.views(p.position));
        double pruned = -1.0;
        for (const auto& [name, value] : voting.figures)
            if (name == "pruned") pruned = value;
        std::printf("%s: %zu probes, %g pruned, predicted %.5f\n", alcove ? "alcove" : "two rooms",
                    voting.probes.size(), pruned, voting.predictedMae);
        // Both scenes hold a probe the greedy took that later ones made worth under the share (2 and 4
        // of them today): without the prune the loop below fails.
        EXPECT_GE(pruned, 1.0) << "the scene exercises the prune, and the figures say how many it dropped";
        for (std::size_t j = 0; j < views.size(); ++j) {
            ExpectedError others(ps);
            for (std::size_t i = 0; i < views.size(); ++i)
                if (i != j) others.add(views[i]);
            EXPECT_GE(others.gain(views[j]), kAutomaticStop * others.mae())
                << (alcove ? "alcove" : "two rooms") << ": probe " << j << " of " << views.size();
        }
    }
}

// The lazy greedy's pick against every site priced exactly: within kSlack of the best exact gain in
// every round, before and after weights that raise gains (a second walk's frames) and rank() again.
// The lazy order must not change what the objective says is best by more than the slack.
TEST(PlacementError, LazyGreedyPicksWithinTheSlackOfTheBestExactGain) {
    const Scene scene = twoRooms();
    const CameraPath walk = twoRoomsWalk();
    const PlacementScene ps(scene, errorSettings(scene), &walk);
    std::vector<Site> sites;
    for (std::size_t c = 0; c < ps.freeSpace().candidates().size(); ++c)
        sites.push_back({ps.freeSpace().candidatePosition(c), ps.votes().offsets[c + 1] > ps.votes().offsets[c]
                                                                   ? std::int64_t(c) : -1});
    for (const glm::vec3& eye : ps.eyes()) sites.push_back({eye, -1});
    SiteGreedy lazy(ps, sites);
    SiteGreedy all(ps, sites);  // every site priced exactly, by brute force
    ASSERT_GT(lazy.sites().size(), 20u);
    // Half the walk's weight first (a live walk so far), then all of it.
    ExpectedError error(ps, /*fromWalk=*/false);
    std::vector<float> half = ps.weights();
    for (float& w : half) w *= 0.5f;
    error.addWeights(half);
    std::size_t picks = 0;
    for (int pass = 0; pass < 2; ++pass) {
        lazy.rank(error);
        for (int round = 0; round < 4; ++round) {
            const std::optional<SiteGreedy::Pick> pick = lazy.next(error);
            ASSERT_TRUE(pick.has_value());
            double best = 0.0;
            std::size_t bestSite = 0;
            for (std::size_t k = 0; k < all.sites().size(); ++k) {
                const double g = error.gain(all.served(k));
                if (g > best) best = g, bestSite = k;
            }
            EXPECT_NEAR(pick->gain, error.gain(all.served(pick->site)), 1e-12) << "a pick's gain is exact";
            EXPECT_GE(pick->gain, (1.0 - SiteGreedy::kSlack) * best)
                << "pass " << pass << ", round " << round << ": site " << pick->site << " against " << bestSite;
            // The bounded-cost pick: its gain exact, and, pricing every site, the best there is.
            const std::optional<SiteGreedy::Pick> few = all.bestOfFew(error, 16, 3);
            ASSERT_TRUE(few.has_value());
            EXPECT_NEAR(few->gain, error.gain(all.served(few->site)), 1e-12);
            const std::optional<SiteGreedy::Pick> every = all.bestOfFew(error, all.sites().size(), all.sites().size());
            ASSERT_TRUE(every.has_value());
            EXPECT_NEAR(every->gain, best, 1e-12 * best);
            const std::optional<SiteGreedy::Pick> again = lazy.next(error);
            ASSERT_TRUE(again.has_value());
            EXPECT_EQ(again->site, pick->site) << "asking again without take() gives the same site";
            error.add(lazy.served(pick->site));
            lazy.take(pick->site);
            all.take(pick->site);
            ++picks;
        }
        error.addWeights(half);
    }
    std::printf("lazy greedy: %zu picks over %zu sites, %zu bounds and %zu exact gains (brute force %zu)\n", picks,
                lazy.sites().size(), lazy.boundEvaluations(), lazy.exactEvaluations(), all.exactEvaluations());
    EXPECT_LT(lazy.exactEvaluations(), all.exactEvaluations() / 2) << "lazy: most sites are never priced exactly";
}

// Live placement, on either objective, says why a frame that needs a probe got none (issue 31: the
// viewer's panel and log show it), and says nothing when it placed one.
TEST(PlacementError, LiveFeedbackSaysWhyItCannotPlace) {
    const Scene scene = twoRooms();
    const CameraPath walk = twoRoomsWalk();
    const PinholeCamera camera(walk, 3, 64, 36);
    PlaceSettings s = errorSettings(scene);
    const PlacementScene ps(scene, s, nullptr);
    s.clearance = 2.0f;  // more than half of every room's height: no voxel is clear
    const PlacementScene none(scene, s, nullptr);
    ASSERT_TRUE(none.freeSpace().candidates().empty());
    auto expectNoFreeSpace = [](const char* stalled) {
        ASSERT_NE(stalled, nullptr);
        EXPECT_NE(std::string(stalled).find("no free space"), std::string::npos) << stalled;
    };

    CoverageFeedback coverage(ps, {});
    const CoverageFeedback::FrameResult covered = coverage.addFrame(camera);
    EXPECT_GT(covered.added, 0);
    EXPECT_EQ(covered.stalled, nullptr);
    const CoverageFeedback::FrameResult uncovered = CoverageFeedback(none, {}).addFrame(camera);
    EXPECT_EQ(uncovered.added, 0);
    expectNoFreeSpace(uncovered.stalled);

    ErrorFeedback error(ps);
    const ErrorFeedback::FrameResult placed = error.addFrame(camera, walk.nearPlane, walk.farPlane, 4);
    EXPECT_GT(placed.added, 0);
    EXPECT_LT(placed.after, placed.before);
    EXPECT_EQ(placed.stalled, nullptr);
    // The same view again: the walk so far weighs it twice, and what it needed is there already.
    EXPECT_EQ(error.addFrame(camera, walk.nearPlane, walk.farPlane, 4).stalled, nullptr);
    ErrorFeedback blocked(none);
    const ErrorFeedback::FrameResult r = blocked.addFrame(camera, walk.nearPlane, walk.farPlane, 4);
    EXPECT_EQ(r.added, 0);
    expectNoFreeSpace(r.stalled);
}

TEST(PlacementError, AWalkWhoseEyesAreAllInsideWallsIsRefused) {
    const Scene scene = twoRooms();
    CameraPath walk = twoRoomsWalk();
    for (CameraFrame& f : walk.frames) f.eye.x = 0.5f * (kAx1 + kBx0), f.eye.z = 0.5f, f.target = f.eye + glm::vec3(0, 0, 1);
    try {
        const PlacementScene ps(scene, errorSettings(scene), &walk);
        FAIL() << "a walk inside the wall was accepted";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("eyes"), std::string::npos) << e.what();
    }
}

}  // namespace
}  // namespace cubeao::placement

// ---- The GPU coverage count against the CPU count ------------------------------------------------

#include <chrono>
#include <memory>
#include <span>
#include <thread>

#include "cubeao/core/error.h"
#include "cubeao/placement/gpu_coverage.h"
#include "gl_fixture.h"

namespace cubeao::placement {
namespace {

class PlacementGl : public GlTest {};

// The CPU count for any probe list: frameCoverage's loop (probeCovers over tracePixels' points).
double cpuCoverage(const PlacementScene& ps, const FramePixels& pixels, std::span<const glm::vec3> probes) {
    if (pixels.points.empty()) return 1.0;
    std::size_t covered = 0;
    for (const SurfaceSample& s : pixels.points)
        for (const glm::vec3& p : probes)
            if (probeCovers(ps.embree(), ps.criterion(), p, s)) {
                ++covered;
                break;
            }
    return double(covered) / double(pixels.points.size());
}

// The GPU rasterises primary rays and traces the probe rays through its own BVH; the CPU uses Embree
// for both. A pixel on a silhouette or a triangle edge may land on a different surface (another
// depth, another normal), and a ray grazing an edge on the way to a probe may be judged differently:
// a few pixels in 64 × 36 = 2304, so 2 % (46 pixels) leaves room for those and none for a wrong
// criterion, which moves whole walls.
constexpr double kCoverageTolerance = 0.02;

TEST_F(PlacementGl, GpuCountAgreesWithCpuCount) {
    const BoxRoomWalk room;
    const auto& [scene, path, s, ps] = room;
    ASSERT_FALSE(path.frames.empty());
    // The probes of a coverage-feedback walk, held by the CoverageFeedback whose frameCoverage is the
    // CPU count.
    CoverageFeedback feedback(ps, {});
    for (std::size_t f = 0; f < path.frames.size(); ++f) feedback.addFrame(PinholeCamera(path, f, 64, 36));
    const std::vector<glm::vec3>& probes = feedback.probes();
    ASSERT_GE(probes.size(), 2u);
    const std::span<const glm::vec3> firstOnly(probes.data(), 1);

    GpuCoverageCount gpu(scene, path.nearPlane);
    const float eps = ps.embree().surfaceEpsilon();
    int framesWithUncovered = 0;
    for (std::size_t f = 0; f < path.frames.size(); f += 4) {
        const PinholeCamera camera(path, f, 64, 36);
        const FramePixels pixels = tracePixels(ps.embree(), camera);
        gpu.submit(camera, probes, ps.criterion(), eps);
        gpu.submit(camera, firstOnly, ps.criterion(), eps);
        const GpuCoverageCount::Result all = gpu.wait(), first = gpu.wait();
        const double cpuAll = feedback.frameCoverage(pixels), cpuFirst = cpuCoverage(ps, pixels, firstOnly);
        std::printf("frame %2zu: pixels cpu %zu gpu %llu; %zu probes cpu %.4f gpu %.4f; "
                    "first probe cpu %.4f gpu %.4f\n",
                    f, pixels.points.size(), static_cast<unsigned long long>(all.pixels), probes.size(), cpuAll,
                    all.coverage(), cpuFirst, first.coverage());
        EXPECT_EQ(all.pixels, first.pixels) << f;
        EXPECT_NEAR(double(all.pixels), double(pixels.points.size()), 0.02 * double(pixels.points.size())) << f;
        EXPECT_NEAR(all.coverage(), cpuAll, kCoverageTolerance) << f;
        EXPECT_NEAR(first.coverage(), cpuFirst, kCoverageTolerance) << f;
        if (first.uncovered > 0 && cpuFirst < 1.0) ++framesWithUncovered;
    }
    // One probe cannot cover the room: the comparison must have seen uncovered pixels to mean anything.
    EXPECT_GT(framesWithUncovered, 0);
}

TEST_F(PlacementGl, GpuCountReturnsEveryTicketInOrder) {
    const Scene scene = loadScene("builtin:box-room");
    const CameraPath path = resolveCameraPath("", "builtin:box-room");
    ASSERT_GE(path.frames.size(), 5u);
    CoverageCriterion criterion;
    criterion.res = 128;
    criterion.maxTexel = 0.05f;
    const std::vector<glm::vec3> probes = {0.5f * (scene.bounds.min + scene.bounds.max)};
    GpuCoverageCount gpu(scene, path.nearPlane);
    EXPECT_FALSE(gpu.poll().has_value());
    // Five frames: more than kSlots, so submit() also waits for the oldest and keeps its result.
    std::vector<std::uint64_t> tickets;
    for (std::size_t f = 0; f < 5; ++f)
        tickets.push_back(gpu.submit(PinholeCamera(path, f, 64, 36), probes, criterion, 1e-4f));
    for (std::size_t k = 0; k < tickets.size(); ++k) EXPECT_EQ(tickets[k], std::uint64_t(k));
    EXPECT_EQ(gpu.pending(), tickets.size());
    // poll() alone must return them all (submit flushes, so every fence signals without a wait);
    // 10 s is far beyond five 64 × 36 frames on llvmpipe.
    std::vector<std::uint64_t> returned;
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
    while (gpu.pending() > 0 && std::chrono::steady_clock::now() < deadline)
        if (const auto r = gpu.poll())
            returned.push_back(r->ticket);
        else
            std::this_thread::sleep_for(std::chrono::milliseconds(1));
    EXPECT_EQ(returned, tickets);
    EXPECT_FALSE(gpu.poll().has_value());
    EXPECT_THROW(gpu.wait(), Error);
}

// The walk with the counts on the GPU (what `place --method coverage` does by default) places the
// same probes as the CPU walk: a frame the GPU finds covered is skipped without tracing, one below
// the target is traced and voted on as on the CPU, and the two counts agree (test above).
TEST_F(PlacementGl, CoverageFeedbackWithGpuCountPlacesTheSameProbes) {
    const BoxRoomWalk room;
    const auto& [scene, path, s, ps] = room;
    ASSERT_FALSE(path.frames.empty());
    const Placement cpu = placeCoverage(ps, path);
    GpuCoverageCount gpu(scene, path.nearPlane);
    const Placement onGpu = placeCoverage(ps, path, {}, nullptr, &gpu);
    ASSERT_EQ(onGpu.probes.size(), cpu.probes.size());
    for (std::size_t k = 0; k < cpu.probes.size(); ++k)
        EXPECT_EQ(onGpu.probes[k].position, cpu.probes[k].position) << k;
    EXPECT_EQ(onGpu.coverage, cpu.coverage);
    double traced = -1.0, frames = -1.0;
    for (const auto& [name, value] : onGpu.figures) {
        if (name == "frames_traced_on_cpu") traced = value;
        if (name == "frames") frames = value;
    }
    EXPECT_GT(frames, 0.0);
    EXPECT_GE(traced, 1.0);      // the first frames need probes
    EXPECT_LT(traced, frames);  // and the covered ones were never traced
}

}  // namespace
}  // namespace cubeao::placement
