// The procedural scenes behind "builtin:NAME", each with a short camera path of its own.
#pragma once

#include <cstddef>
#include <string>

#include "cubeao/scene/camera_path.h"
#include "cubeao/scene/scene.h"

namespace cubeao::scenes {

// Registers builtin:sphere-plane, builtin:box-room, builtin:two-rooms, builtin:cloister and builtin:town with scene/builtin.h, so
// loadScene, makeBuiltinScene and resolveCameraPath find them. Call once at program start (the CLI's
// main and the tests' main do); later calls do nothing. Thread-safe.
void registerBuiltinScenes();

// Sphere of radius kSphereRadius centred kSphereHeight above a large plane y = 0 (centre over the
// origin): the point under the centre has unbounded AO 1 − (r/h)², the analytic answer of DESIGN.md §6.
inline constexpr float kSphereRadius = 1.0f;
inline constexpr float kSphereHeight = 2.0f;
Scene makeSpherePlane();
CameraPath spherePlanePath();

// A closed room [0, 8] × [0, 3] × [0, 6] (x, y, z; metres) with a table, a cabinet and a crate. The
// corner at the origin is kept free, so AO falls monotonically towards it along the floor diagonal.
inline constexpr float kRoomX = 8.0f, kRoomY = 3.0f, kRoomZ = 6.0f;
Scene makeBoxRoom();
CameraPath boxRoomPath();

// Two closed rooms [0, 4] × [0, 3] × [0, 4] and [4.02, 8.02] × [0, 3] × [0, 4] (metres) that share a
// 2 cm wall, with a cabinet in room A and a table in room B; its walk stays in room B. The thin-wall case of the depth test
// (issue 34 item 4): a probe in room A must serve nothing of room B, at any level of detail.
inline constexpr float kTwoRoomsX = 4.0f, kTwoRoomsY = 3.0f, kTwoRoomsZ = 4.0f, kTwoRoomsWall = 0.02f;
Scene makeTwoRooms();
CameraPath twoRoomsPath();

// A small cloister: a square garth with a fountain, four arcaded walks under a lean-to roof and an
// outer wall; tens of thousands of triangles. The default scene of the README's main command.
Scene makeCloister();
CameraPath cloisterPath();

// A town of copies of the two shared real models: blocks with a Sibenik copy (its west door left open) and
// blocks of FZK-Haus copies in walled gardens (quarter turns) around a courtyard, on a street grid with
// sidewalks, kerbs, lamps and benches. `arg` is the triangle count: "" = kDefaultTownTriangles, else a number
// with an optional k or m suffix ("500k", "10m", "2.5m", "2000000"), from kMinTownTriangles to
// kMaxTownTriangles; the result is within a few hundred triangles of it. Needs
// $CUBEAO_SHARED_DIR/scenes/sibenik/ (else the source tree's ../shared) and the Debian package
// assimp-testmodels; throws cubeao::Error naming what is missing or what is wrong with `arg`.
inline constexpr std::size_t kDefaultTownTriangles = 2'000'000;
inline constexpr std::size_t kMinTownTriangles = 150'000;      // a Sibenik and an FZK-Haus copy: the walk's
inline constexpr std::size_t kMaxTownTriangles = 100'000'000;  // some 5 GB while it is prepared
Scene makeTown(const std::string& arg);
// Along a street, in through the Sibenik copy's west door and down its nave (the shared Sibenik walk),
// back out, across the street and once around an FZK-Haus copy in its garden; eyes 1.7 m above the
// ground. Needs the shared Sibenik walk (walk.json beside the model).
CameraPath townPath(const std::string& arg);
// The triangle count `arg` asks for (see makeTown); throws cubeao::Error for anything else.
std::size_t parseTownTriangles(const std::string& arg);

}  // namespace cubeao::scenes
