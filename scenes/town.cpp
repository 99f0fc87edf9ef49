// builtin:town — a town of copies of the two shared real models, any size. All sizes in metres, +y up.
//
// Lots of kBlockX × kBlockZ on a grid (columns along +x, rows along +z) with kStreet between them; each
// block lays its own half of the surrounding streets (sidewalk, kerb, half the road), so neighbours meet
// on the road's centre line. Blocks alternate like a chequerboard: a Sibenik block (one copy, its west door
// opening onto a plaza and the street, inside a low wall) and an FZK-Haus block (16 walled garden slots
// around a courtyard, each house turned by a quarter turn of its own, a gate onto the street). The blocks
// are filled in order until the next copy would pass the target; small street furniture whose size is
// chosen to match makes up the rest. Block 0 (Sibenik) and the first slot of block 1 exist for every
// target: the camera path goes through them.
//
// Speed and memory: each model is imported once; copies are index ranges with an offset and positions
// under a quarter turn (exact in float, winding kept). The counts are planned first and the arrays reserved
// once, so 10 M triangles take positions, normals and indices only.
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/gtc/constants.hpp>
#include <glm/vec2.hpp>

#include "cubeao/core/error.h"
#include "cubeao/scene/import.h"
#include "cubeao/scenes/builtin_scenes.h"
#include "cubeao/scenes/mesh_builder.h"

namespace cubeao::scenes {
namespace {

namespace fs = std::filesystem;

constexpr const char* kFzkFile = "/usr/share/assimp/models/IFC/AC14-FZK-Haus.ifc";

// ---- layout -----------------------------------------------------------------------------------
constexpr float kBlockX = 144.0f, kBlockZ = 96.0f;  // a lot
constexpr float kStreet = 12.0f;                    // 2 m sidewalk, 8 m road, 2 m sidewalk
constexpr float kPitchX = kBlockX + kStreet, kPitchZ = kBlockZ + kStreet;
constexpr float kSidewalk = 2.0f, kSidewalkTop = 0.15f, kKerb = 0.2f, kKerbTop = 0.17f;
constexpr float kEye = 1.7f;

// Sibenik (file coordinates: nave along −x from the west door at x = 27.24, floor y = 0, bbox x −58..68,
// z −35..45) goes into its lot shifted by kSibenikAt, its plaza (x 27..68) towards the lot's +x street.
constexpr float kSibenikAtX = 74.0f, kSibenikAtZ = 43.0f;
const glm::vec3 kSibenikAt{kSibenikAtX, 0.0f, kSibenikAtZ};
constexpr float kSibenikMinX = -58.0f, kSibenikMaxX = 68.0f, kSibenikMinZ = -35.0f, kSibenikMaxZ = 45.0f;
// The west door's two leaves and the trumeau between them (vertical faces within this box, file
// coordinates): left out so the walk can go in; the door frame, threshold and floor stay.
constexpr float kDoorX0 = 27.1f, kDoorX1 = 27.4f, kDoorHalfZ = 1.5f, kDoorTop = 4.0f;
// The line the walk follows through the door and across the street (lot z): the shared walk's z = 0.3.
constexpr float kPathZ = kSibenikAtZ + 0.3f;
constexpr float kPlazaGate = 10.0f;  // gap in the lot wall and the sidewalk, centred on kPathZ

// FZK-Haus (as assimp imports it: terrain slab x −3..15, z −13..3, y −1..0; the house within x −0.5..12.5,
// z −10.5..0.5) turns about the terrain's centre kFzkPivot and goes to the middle of a kSlot square.
const glm::vec3 kFzkPivot{6.0f, 0.0f, -5.0f};
constexpr float kFzkHalfX = 9.0f, kFzkHalfZ = 8.0f;     // terrain half sizes
constexpr float kHouseHalfX = 6.5f, kHouseHalfZ = 5.5f;  // house half sizes
constexpr float kSlot = 24.0f;
constexpr float kGardenWall = 0.25f, kGardenWallTop = 1.1f, kGate = 3.0f;
// Gates sit this far along the slot's street side, so the first slot's gate faces the Sibenik door.
constexpr float kGateAt = kPathZ - kSlot;
constexpr float kLotWall = 0.3f, kLotWallTop = 1.2f;

// Sides of a lot: 0 = −z, 1 = +x, 2 = +z, 3 = −x. Along a side runs the coordinate u (x on 0 and 2, z on
// 1 and 3) from 0 to sideLength.
float sideLength(int side) { return side % 2 == 0 ? kBlockX : kBlockZ; }
// The lot point (x, z) at u along `side` and `d` outside it (d < 0: inside the lot).
glm::vec2 sidePoint(int side, float u, float d) {
    switch (side) {
        case 0: return {u, -d};
        case 1: return {kBlockX + d, u};
        case 2: return {u, kBlockZ + d};
        default: return {-d, u};
    }
}

struct Interval {
    float a, b;
};

// A garden slot of an FZK block: its corner in the lot, the street side its gate is on.
struct Slot {
    float x, z;
    int street;
};
// Slot 0 first: it faces block 0's Sibenik door across the street, and the walk goes round its house.
std::vector<Slot> fzkSlots() {
    std::vector<Slot> s{{0, 24, 3}, {0, 48, 3}};
    for (int i = 0; i < 6; ++i) s.push_back({kSlot * float(i), 0, 0});
    s.push_back({120, 24, 1});
    s.push_back({120, 48, 1});
    for (int i = 5; i >= 0; --i) s.push_back({kSlot * float(i), 72, 2});
    return s;
}
// The gate's interval along the slot's street side, in the lot's u of that side.
Interval slotGate(const Slot& s) {
    const float u0 = s.street % 2 == 0 ? s.x : s.z;
    return {u0 + kGateAt - 0.5f * kGate, u0 + kGateAt + 0.5f * kGate};
}
int slotTurns(std::size_t slot, std::size_t block) { return int((slot + block + 1) % 4); }

// ---- the grid ---------------------------------------------------------------------------------
// Its shape only (not what fills it) follows from the target, so townPath knows where block 0 and 1 are
// without importing anything: roughly square, centred on the origin (a whole-metre shift, so float
// coordinates stay small and exact offsets stay exact).
struct Grid {
    int cols = 2;
    glm::vec2 origin{0.0f};  // lot corner of block 0
    glm::vec2 lot(std::size_t block) const {
        const auto n = std::size_t(cols);
        return origin + glm::vec2(kPitchX * float(block % n), kPitchZ * float(block / n));
    }
    bool sibenik(std::size_t block) const { return (block % std::size_t(cols) + block / std::size_t(cols)) % 2 == 0; }
};

Grid gridFor(std::size_t target) {
    constexpr double kNominalPair = 80e3 + 16 * 36e3 + 6e3;  // a Sibenik and a full FZK block, roughly
    const double blocks = std::max(2.0, std::ceil(2.0 * double(target) / kNominalPair));
    Grid g;
    g.cols = std::max(2, int(std::lround(std::sqrt(blocks * kPitchZ / kPitchX))));
    const double rows = std::ceil(blocks / g.cols);
    g.origin = -glm::vec2(std::round(0.5 * (g.cols * kPitchX - kStreet)), std::round(0.5 * (rows * kPitchZ - kStreet)));
    return g;
}

// ---- arguments and models -----------------------------------------------------------------------
std::string townSpec(const std::string& arg) { return arg.empty() ? "builtin:town" : "builtin:town:" + arg; }

fs::path sharedDir() {
    if (const char* env = std::getenv("CUBEAO_SHARED_DIR"); env != nullptr && *env != '\0') return env;
#ifdef CUBEAO_SHARED_DIR
    return CUBEAO_SHARED_DIR;
#else
    return "../shared";
#endif
}

fs::path sibenikFile(const std::string& spec, const char* name) {
    const fs::path file = sharedDir() / "scenes/sibenik" / name;
    std::error_code ec;
    if (!fs::is_regular_file(file, ec))
        throw Error(spec + ": " + file.string() + " is missing (the shared scenes directory lives beside the " +
                    "repository as ../shared; set CUBEAO_SHARED_DIR to the directory that holds scenes/)");
    return file;
}

// Leaves out the west door's leaves and trumeau, then drops the vertices only they used.
void openSibenikDoor(Scene& s) {
    auto inDoor = [](const glm::vec3& p) {
        return p.x > kDoorX0 && p.x < kDoorX1 && std::abs(p.z) < kDoorHalfZ && p.y > -0.01f && p.y < kDoorTop;
    };
    std::size_t out = 0;
    for (std::size_t t = 0; t < s.indices.size(); t += 3) {
        const glm::vec3 &a = s.positions[s.indices[t]], &b = s.positions[s.indices[t + 1]],
                        &c = s.positions[s.indices[t + 2]];
        const glm::vec3 n = glm::normalize(glm::cross(b - a, c - a));
        if (inDoor(a) && inDoor(b) && inDoor(c) && std::abs(n.y) < 0.5f) continue;  // vertical: door, not floor
        for (int k = 0; k < 3; ++k) s.indices[out++] = s.indices[t + k];
    }
    s.indices.resize(out);
    std::vector<std::uint32_t> remap(s.positions.size(), ~0u);
    std::vector<glm::vec3> positions, normals;
    for (std::uint32_t& i : s.indices) {
        if (remap[i] == ~0u) {
            remap[i] = std::uint32_t(positions.size());
            positions.push_back(s.positions[i]);
            normals.push_back(s.normals[i]);
        }
        i = remap[i];
    }
    s.positions = std::move(positions);
    s.normals = std::move(normals);
}

// ---- building ---------------------------------------------------------------------------------
glm::vec3 turn(const glm::vec3& v, int k) {
    switch (k) {
        case 1: return {v.z, v.y, -v.x};
        case 2: return {-v.x, v.y, -v.z};
        case 3: return {-v.z, v.y, v.x};
        default: return v;
    }
}

// One model copy: turned by `turns` quarter turns about `pivot`, which goes to `at`.
struct Copy {
    const Scene* model;
    int turns;
    glm::vec3 pivot, at;
};

struct Plan {
    std::vector<Scene> parts;  // procedural geometry, a few per block
    std::vector<Copy> copies;
    std::vector<glm::vec3> spots;  // free places on the sidewalks for the filler, in block order
    std::size_t triangles = 0;

    void add(MeshBuilder& b) {
        triangles += b.triangleCount();
        parts.push_back(b.take());
        b = MeshBuilder();
    }
    void add(const Copy& c) {
        triangles += c.model->triangleCount();
        copies.push_back(c);
    }
};

void addBox2(MeshBuilder& b, glm::vec2 p, glm::vec2 q, float y0, float y1) {
    b.addBox({std::min(p.x, q.x), y0, std::min(p.y, q.y)}, {std::max(p.x, q.x), y1, std::max(p.y, q.y)}, false,
             false);
}
void addFloor2(MeshBuilder& b, glm::vec2 p, glm::vec2 q, float y) {
    b.addFloor(std::min(p.x, q.x), std::min(p.y, q.y), std::max(p.x, q.x), std::max(p.y, q.y), y);
}

// The pieces of [from, to] outside the gaps (sorted, disjoint).
std::vector<Interval> subtract(float from, float to, const std::vector<Interval>& gaps) {
    std::vector<Interval> out;
    float a = from;
    for (const Interval& g : gaps) {
        if (g.b <= a || g.a >= to) continue;
        if (g.a > a) out.push_back({a, g.a});
        a = std::max(a, g.b);
    }
    if (a < to) out.push_back({a, to});
    return out;
}

void addLamp(MeshBuilder& b, glm::vec3 p) {
    b.addCylinder(p, 0.08f, 4.5f, 8, 1, false);
    b.addBox(p + glm::vec3(-0.3f, 4.5f, -0.15f), p + glm::vec3(0.3f, 4.65f, 0.15f));
}
void addBench(MeshBuilder& b, glm::vec3 p, bool alongX) {
    const glm::vec3 h = alongX ? glm::vec3(0.8f, 0.0f, 0.22f) : glm::vec3(0.22f, 0.0f, 0.8f);
    const glm::vec3 leg = alongX ? glm::vec3(0.06f, 0.0f, 0.2f) : glm::vec3(0.2f, 0.0f, 0.06f);
    b.addBox(p - h + glm::vec3(0, 0.42f, 0), p + h + glm::vec3(0, 0.48f, 0));  // seat
    for (float s : {-0.7f, 0.7f}) {
        const glm::vec3 c = p + (alongX ? glm::vec3(s, 0, 0) : glm::vec3(0, 0, s));
        b.addBox(c - leg, c + leg + glm::vec3(0, 0.42f, 0), false, false);
    }
}
void addTree(MeshBuilder& b, glm::vec3 p) {
    b.addCylinder(p, 0.18f, 2.6f, 12, 2, false);
    b.addBox(p + glm::vec3(-1.3f, 2.6f, -1.3f), p + glm::vec3(1.3f, 5.0f, 1.3f));
}

// Half the street round a lot at `lot`, with the sidewalk (and its kerb) broken where `gaps` open onto
// the road; lamps and benches along it; filler spots recorded in the plan.
void addStreets(Plan& plan, MeshBuilder& b, glm::vec2 lot, const std::vector<Interval> (&gaps)[4]) {
    const float road = 0.5f * kStreet;
    for (int side = 0; side < 4; ++side) {
        const float len = sideLength(side);
        // Sides along x take the corners (−2 .. len + 2), so the sidewalk runs round without a seam.
        const float ext = side % 2 == 0 ? kSidewalk : 0.0f;
        const float roadExt = side % 2 == 0 ? road : kSidewalk;  // the corners' road squares come with x sides
        auto P = [&](float u, float d) { return lot + sidePoint(side, u, d); };
        addFloor2(b, P(-roadExt, kSidewalk), P(len + roadExt, road), 0.0f);  // road
        for (const Interval& piece : subtract(-ext, len + ext, gaps[side])) {
            addBox2(b, P(piece.a, 0.0f), P(piece.b, kSidewalk - kKerb), 0.0f, kSidewalkTop);
            addBox2(b, P(piece.a, kSidewalk - kKerb), P(piece.b, kSidewalk), 0.0f, kKerbTop);
        }
        for (const Interval& g : gaps[side]) addFloor2(b, P(g.a, 0.0f), P(g.b, kSidewalk), 0.0f);  // driveways
        // Every 4 m: lamp, spot, bench, spot; none within 2.5 m of a gap (the walk crosses there).
        for (int i = 0;; ++i) {
            const float u = 2.0f + 4.0f * float(i);
            if (u > len - 2.0f) break;
            bool nearGap = false;
            for (const Interval& g : gaps[side]) nearGap |= u > g.a - 2.5f && u < g.b + 2.5f;
            if (nearGap) continue;
            const glm::vec2 kerbSide = P(u, kSidewalk - kKerb - 0.45f), lotSide = P(u, 0.5f);
            if (i % 4 == 0) addLamp(b, {kerbSide.x, kSidewalkTop, kerbSide.y});
            if (i % 4 == 2) addBench(b, {lotSide.x, kSidewalkTop, lotSide.y}, side % 2 == 0);
            if (i % 2 == 1) plan.spots.push_back({kerbSide.x, kSidewalkTop, kerbSide.y});
        }
    }
}

// A low wall along `side` of the rectangle [p0, p1] (lot coordinates), inside it, `t` thick, with `gaps`
// (in the side's u, measured from p0's coordinate).
void addWall(MeshBuilder& b, glm::vec2 p0, glm::vec2 p1, int side, float t, float top,
             const std::vector<Interval>& gaps) {
    const bool alongX = side % 2 == 0;
    const float from = alongX ? p0.x : p0.y + t, to = alongX ? p1.x : p1.y - t;  // x walls take the corners
    for (const Interval& piece : subtract(from, to, gaps)) {
        if (side == 0) addBox2(b, {piece.a, p0.y}, {piece.b, p0.y + t}, 0.0f, top);
        if (side == 2) addBox2(b, {piece.a, p1.y - t}, {piece.b, p1.y}, 0.0f, top);
        if (side == 1) addBox2(b, {p1.x - t, piece.a}, {p1.x, piece.b}, 0.0f, top);
        if (side == 3) addBox2(b, {p0.x, piece.a}, {p0.x + t, piece.b}, 0.0f, top);
    }
}

// The ground of the rectangle [p0, p1] at y = 0 except the hole [h0, h1] inside it.
void addGroundAround(MeshBuilder& b, glm::vec2 p0, glm::vec2 p1, glm::vec2 h0, glm::vec2 h1) {
    addFloor2(b, p0, {p1.x, h0.y}, 0.0f);
    addFloor2(b, {p0.x, h1.y}, p1, 0.0f);
    addFloor2(b, {p0.x, h0.y}, {h0.x, h1.y}, 0.0f);
    addFloor2(b, {h1.x, h0.y}, {p1.x, h1.y}, 0.0f);
}

void addSibenikBlock(Plan& plan, glm::vec2 lot, const Scene& sibenik) {
    MeshBuilder b;
    std::vector<Interval> gaps[4];
    gaps[1] = {{kPathZ - 0.5f * kPlazaGate, kPathZ + 0.5f * kPlazaGate}};
    addStreets(plan, b, lot, gaps);
    const glm::vec2 l0 = lot, l1 = lot + glm::vec2(kBlockX, kBlockZ);
    for (int side = 0; side < 4; ++side) {
        std::vector<Interval> wallGaps;
        const float base = side % 2 ? l0.y : l0.x;  // the wall takes lot coordinates, the gaps are along the side
        for (const Interval& g : gaps[side]) wallGaps.push_back({base + g.a, base + g.b});
        addWall(b, l0, l1, side, kLotWall, kLotWallTop, wallGaps);
    }
    // Level ground round the model's box; a little below its own (irregular) ground inside it, so no
    // hole shows where the model's ground ends and nothing is coplanar with it.
    const glm::vec2 m0 = lot + glm::vec2(kSibenikAt.x + kSibenikMinX, kSibenikAt.z + kSibenikMinZ);
    const glm::vec2 m1 = lot + glm::vec2(kSibenikAt.x + kSibenikMaxX, kSibenikAt.z + kSibenikMaxZ);
    addGroundAround(b, l0, l1, m0, m1);
    addFloor2(b, m0, m1, -0.05f);
    plan.add(b);
    plan.add({&sibenik, 0, glm::vec3(0.0f), glm::vec3(lot.x, 0.0f, lot.y) + kSibenikAt});
}

// An FZK block with as many houses (slots in order) as `budget` triangles allow after its own streets
// and walls; at least one (the caller checks the budget; block 1's first house is the walk's, always there).
void addFzkBlock(Plan& plan, glm::vec2 lot, std::size_t block, const Scene& fzk, std::size_t budget) {
    MeshBuilder b;
    const std::vector<Slot> slots = fzkSlots();
    std::vector<Interval> gaps[4];
    for (const Slot& s : slots) gaps[s.street].push_back(slotGate(s));
    for (auto& g : gaps) std::sort(g.begin(), g.end(), [](const Interval& x, const Interval& y) { return x.a < y.a; });
    addStreets(plan, b, lot, gaps);
    // The courtyard in the middle: ground, a fountain, trees and benches.
    const glm::vec2 c0 = lot + glm::vec2(kSlot, kSlot), c1 = lot + glm::vec2(kBlockX - kSlot, kBlockZ - kSlot);
    const glm::vec2 cc = 0.5f * (c0 + c1);
    addFloor2(b, c0, c1, 0.0f);
    b.addCylinder({cc.x, 0.0f, cc.y}, 3.0f, 0.6f, 48, 1, true);
    b.addCylinder({cc.x, 0.6f, cc.y}, 0.3f, 1.2f, 16, 1, true);
    for (float dx : {-30.0f, -15.0f, 15.0f, 30.0f})
        for (float dz : {-12.0f, 12.0f}) {
            addTree(b, {cc.x + dx, 0.0f, cc.y + dz});
            addBench(b, {cc.x + dx, 0.0f, cc.y + 0.5f * dz}, true);
        }
    // Garden walls with a gate on the street side, and the garden's ground round the house's terrain.
    for (const Slot& s : slots) {
        const glm::vec2 p0 = lot + glm::vec2(s.x, s.z), p1 = p0 + glm::vec2(kSlot);
        for (int side = 0; side < 4; ++side) {
            std::vector<Interval> wallGaps;
            if (side == s.street) {
                const Interval g = slotGate(s);
                const float base = side % 2 == 0 ? lot.x : lot.y;
                wallGaps.push_back({base + g.a, base + g.b});
            }
            addWall(b, p0, p1, side, kGardenWall, kGardenWallTop, wallGaps);
        }
    }
    std::size_t used = plan.triangles + b.triangleCount();
    const std::size_t start = plan.triangles;
    for (std::size_t i = 0; i < slots.size(); ++i) {
        const Slot& s = slots[i];
        const glm::vec2 c = lot + glm::vec2(s.x, s.z) + glm::vec2(0.5f * kSlot);
        const int k = slotTurns(i, block);
        const glm::vec2 half = k % 2 == 0 ? glm::vec2(kFzkHalfX, kFzkHalfZ) : glm::vec2(kFzkHalfZ, kFzkHalfX);
        addGroundAround(b, c - glm::vec2(0.5f * kSlot), c + glm::vec2(0.5f * kSlot), c - half, c + half);
        used += 8;
        if (used + fzk.triangleCount() <= start + budget || (block == 1 && i == 0)) {  // the walk's house
            plan.add({&fzk, k, kFzkPivot, {c.x, 0.0f, c.y}});
            used += fzk.triangleCount();
        } else {
            addFloor2(b, c - half, c + half, 0.0f);  // an empty garden
            used += 2;
        }
    }
    plan.add(b);
}

// Triangles of a capped cylinder with `segments` and `rings`.
std::size_t cylinderTriangles(int segments, int rings) { return std::size_t(segments) * std::size_t(2 * rings + 1); }

// Fills up to `target` with planters (capped cylinders) of a size that spreads the rest over the spots.
void addFiller(Plan& plan, std::size_t target) {
    MeshBuilder b;
    constexpr int kSegments = 12, kMaxRings = 40;
    std::size_t left = target > plan.triangles ? target - plan.triangles : 0;
    for (std::size_t i = 0; i < plan.spots.size(); ++i) {
        const std::size_t want = left / (plan.spots.size() - i);
        if (want < cylinderTriangles(kSegments, 1)) {
            if (left < cylinderTriangles(kSegments, 1)) break;
            continue;  // fewer, larger planters further on
        }
        const int rings = std::clamp(int((want / kSegments - 1) / 2), 1, kMaxRings);
        b.addCylinder(plan.spots[i], 0.35f, 0.9f, kSegments, rings, true);
        left -= cylinderTriangles(kSegments, rings);
    }
    plan.add(b);
}

Plan planTown(std::size_t target, const Scene& sibenik, const Scene& fzk, const std::string& spec) {
    const Grid grid = gridFor(target);
    Plan plan;
    constexpr std::size_t kBlockBase = 6000;  // a block's own streets, walls and courtyard, at most
    for (std::size_t block = 0;; ++block) {
        const std::size_t left = target > plan.triangles ? target - plan.triangles : 0;
        // Block 0 is the walk's Sibenik, block 1 its FZK block; further on a Sibenik only where one fits.
        const bool sib =
            block == 0 || (block != 1 && grid.sibenik(block) && left >= kBlockBase + sibenik.triangleCount());
        if (block >= 2 && left < kBlockBase + fzk.triangleCount()) break;
        if (sib)
            addSibenikBlock(plan, grid.lot(block), sibenik);
        else
            addFzkBlock(plan, grid.lot(block), block, fzk, left);
    }
    if (plan.triangles > target + target / 10)
        throw Error(spec + ": " + std::to_string(target) + " triangles are too few for the two copies the walk " +
                    "needs (" + std::to_string(plan.triangles) + ")");
    addFiller(plan, target);
    return plan;
}

Scene buildTown(const Plan& plan) {
    std::size_t vertices = 0, indices = 0;
    for (const Scene& p : plan.parts) {
        vertices += p.positions.size();
        indices += p.indices.size();
    }
    for (const Copy& c : plan.copies) {
        vertices += c.model->positions.size();
        indices += c.model->indices.size();
    }
    if (vertices > std::size_t(UINT32_MAX)) throw Error("builtin:town: too many vertices for 32-bit indices");
    Scene town;
    town.positions.reserve(vertices);
    town.normals.reserve(vertices);
    town.indices.reserve(indices);
    auto append = [&](const Scene& m, int turns, const glm::vec3& pivot, const glm::vec3& at) {
        const auto base = std::uint32_t(town.positions.size());
        for (std::size_t i = 0; i < m.positions.size(); ++i) {
            town.positions.push_back(turn(m.positions[i] - pivot, turns) + at);
            town.normals.push_back(turn(m.normals[i], turns));
        }
        for (const std::uint32_t i : m.indices) town.indices.push_back(base + i);
    };
    for (const Scene& p : plan.parts) append(p, 0, glm::vec3(0.0f), glm::vec3(0.0f));
    for (const Copy& c : plan.copies) append(*c.model, c.turns, c.pivot, c.at);
    finalizeScene(town);
    return town;
}

// ---- the walk ---------------------------------------------------------------------------------
// A walker on the ground plane: heading h looks along (cos h, 0, sin h), so a negative turn is to the
// left; pitch tilts the view up. Each move appends frames at most `step` apart.
class Walker {
public:
    Walker(CameraPath& path, glm::vec2 pos, float heading, float pitch)
        : path_(path), pos_(pos), heading_(heading), pitch_(pitch) {}

    void frame() {
        const glm::vec3 eye(pos_.x, kEye, pos_.y);
        const glm::vec3 dir(std::cos(pitch_) * std::cos(heading_), std::sin(pitch_),
                            std::cos(pitch_) * std::sin(heading_));
        path_.frames.push_back({eye, eye + 10.0f * dir});
    }
    void straight(float length, float step) {
        const int n = std::max(1, int(std::ceil(length / step)));
        const glm::vec2 d(std::cos(heading_), std::sin(heading_));
        const glm::vec2 start = pos_;
        for (int i = 1; i <= n; ++i) {
            pos_ = start + (length * float(i) / float(n)) * d;
            frame();
        }
    }
    // Along a circle of `radius`, turning the heading by `angle` (radians, signed).
    void arc(float angle, float radius, float step) {
        const float length = std::abs(angle) * radius, k = angle / length;  // signed curvature
        const int n = std::max(1, int(std::ceil(length / step)));
        const float h0 = heading_;
        const glm::vec2 start = pos_;
        for (int i = 1; i <= n; ++i) {
            const float s = length * float(i) / float(n);
            heading_ = h0 + k * s;
            pos_ = start + glm::vec2(std::sin(heading_) - std::sin(h0), std::cos(h0) - std::cos(heading_)) / k;
            frame();
        }
    }
    // Standing, turning the view to `heading` and `pitch` in `frames` even steps.
    void look(float heading, float pitch, int frames) {
        const float h0 = heading_, p0 = pitch_;
        for (int i = 1; i <= frames; ++i) {
            const float t = float(i) / float(frames);
            heading_ = h0 + t * (heading - h0);
            pitch_ = p0 + t * (pitch - p0);
            frame();
        }
    }
    glm::vec2 pos() const { return pos_; }

private:
    CameraPath& path_;
    glm::vec2 pos_;
    float heading_, pitch_;
};

}  // namespace

std::size_t parseTownTriangles(const std::string& arg) {
    if (arg.empty()) return kDefaultTownTriangles;
    const std::string spec = townSpec(arg);
    const std::string usage = spec + ": the argument is a triangle count such as 500k, 2m, 2.5m or 2000000, from " +
                              std::to_string(kMinTownTriangles / 1000) + "k to " +
                              std::to_string(kMaxTownTriangles / 1000000) + "m";
    std::size_t digits = 0, dots = 0, i = 0;
    for (; i < arg.size() && (std::isdigit(static_cast<unsigned char>(arg[i])) || arg[i] == '.'); ++i)
        (arg[i] == '.' ? dots : digits) += 1;
    const std::string number = arg.substr(0, i), suffix = arg.substr(i);
    double scale = 1.0;
    if (suffix == "k" || suffix == "K")
        scale = 1e3;
    else if (suffix == "m" || suffix == "M")
        scale = 1e6;
    else if (!suffix.empty())
        throw Error(usage + " (got '" + arg + "')");
    if (digits == 0 || dots > 1 || (dots == 1 && suffix.empty()) || number.size() > 12)
        throw Error(usage + " (got '" + arg + "')");
    const double value = std::strtod(number.c_str(), nullptr) * scale;
    if (value < double(kMinTownTriangles) || value > double(kMaxTownTriangles))
        throw Error(usage + " (got '" + arg + "')");
    return std::size_t(std::llround(value));
}

Scene makeTown(const std::string& arg) {
    const std::size_t target = parseTownTriangles(arg);
    const std::string spec = townSpec(arg);
    Scene sibenik = loadScene(sibenikFile(spec, "sibenik.obj").string());
    std::error_code ec;
    if (!fs::is_regular_file(kFzkFile, ec))
        throw Error(spec + ": " + kFzkFile + " is missing (install the Debian package assimp-testmodels, as " +
                    "tools/install-deps.sh does)");
    const Scene fzk = loadScene(kFzkFile);
    openSibenikDoor(sibenik);
    return buildTown(planTown(target, sibenik, fzk, spec));
}

CameraPath townPath(const std::string& arg) {
    const std::size_t target = parseTownTriangles(arg);
    const std::string spec = townSpec(arg);
    const CameraPath walk = readCameraPath(sibenikFile(spec, "walk.json"));
    if (walk.frames.size() < 2) throw Error(spec + ": the shared Sibenik walk has no frames");
    const Grid grid = gridFor(target);
    const glm::vec2 lot0 = grid.lot(0), lot1 = grid.lot(1);
    const glm::vec3 sibenikAt = glm::vec3(lot0.x, 0.0f, lot0.y) + kSibenikAt;
    const float pi = glm::pi<float>(), pitch = std::atan2(0.5234f, 9.9863f);  // the shared walk's first view

    CameraPath p;
    p.scene = spec;
    p.width = 1280;
    p.height = 720;
    p.fovYDeg = 60.0f;
    p.nearPlane = 0.05f;
    p.farPlane = 300.0f;
    // Down the street between block 0 and 1, turning into the Sibenik plaza and up to its west door.
    const float streetX = lot0.x + kBlockX + 0.5f * kStreet, pathZ = lot0.y + kPathZ;
    const float firstX = walk.frames.front().eye.x + sibenikAt.x;
    constexpr float kTurn = 6.0f;
    Walker w(p, {streetX, pathZ + kTurn + 20.0f}, -0.5f * pi, pitch);
    w.frame();
    w.straight(20.0f, 0.2f);
    w.arc(-0.5f * pi, kTurn, 0.2f);
    w.straight(streetX - kTurn - firstX - 0.15f, 0.2f);
    // In through the door and down the nave: the shared walk, moved into the copy.
    for (const CameraFrame& f : walk.frames) p.frames.push_back({f.eye + sibenikAt, f.target + sibenikAt});
    // Look down again and about, turn round in the nave and walk back out onto the line through the door.
    const CameraFrame last = walk.frames.back();
    const glm::vec3 d = glm::normalize(last.target - last.eye);
    Walker back(p, {last.eye.x + sibenikAt.x, last.eye.z + sibenikAt.z}, std::atan2(d.z, d.x), std::asin(d.y));
    back.look(pi, pitch, 10);
    constexpr float kUTurn = 1.3f;
    back.arc(-pi, kUTurn, 0.06f);  // towards +z, ending 2.6 m off the walk's line, heading +x
    back.straight(1.0f, 0.1f);
    const float off = back.pos().y - pathZ;  // S-bend back onto the line: two arcs of angle a, radius r
    constexpr float kS = 8.0f;
    const float a = std::acos(1.0f - off / (2.0f * kS));
    back.arc(-a, kS, 0.18f);
    back.arc(a, kS, 0.18f);
    // Out across the plaza and the street, in at the garden gate of block 1's first slot, round the house.
    const glm::vec2 slot = lot1 + glm::vec2(fzkSlots().front().x, fzkSlots().front().z);
    const glm::vec2 house = slot + glm::vec2(0.5f * kSlot);
    const int k = slotTurns(0, 1);
    const glm::vec2 half = k % 2 == 0 ? glm::vec2(kHouseHalfX, kHouseHalfZ) : glm::vec2(kHouseHalfZ, kHouseHalfX);
    constexpr float kAround = 2.2f, kCorner = 4.0f;
    const float east = house.x + half.x + kAround, west = house.x - half.x - kAround;
    const float south = house.y - half.y - kAround;
    back.straight(east - kCorner - back.pos().x, 0.2f);
    back.arc(-0.5f * pi, kCorner, 0.18f);
    back.straight(back.pos().y - (south + kCorner), 0.2f);
    back.arc(-0.5f * pi, kCorner, 0.18f);
    back.straight(back.pos().x - (west + kCorner), 0.2f);
    back.arc(-0.5f * pi, kCorner, 0.18f);
    back.straight(pathZ - kCorner - back.pos().y, 0.2f);
    back.arc(0.5f * pi, kCorner, 0.18f);  // out through the gate, heading −x
    // Back onto the street and along it.
    back.straight(back.pos().x - (streetX + kCorner), 0.2f);
    back.arc(0.5f * pi, kCorner, 0.18f);
    back.straight(25.0f, 0.2f);
    return p;
}

}  // namespace cubeao::scenes
