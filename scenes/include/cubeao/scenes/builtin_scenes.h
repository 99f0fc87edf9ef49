// The procedural scenes behind "builtin:NAME", each with a short camera path of its own.
#pragma once

#include "cubeao/scene/camera_path.h"
#include "cubeao/scene/scene.h"

namespace cubeao::scenes {

// Registers builtin:sphere-plane, builtin:box-room and builtin:cloister with scene/builtin.h, so
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

// A small cloister: a square garth with a fountain, four arcaded walks under a lean-to roof and an
// outer wall; tens of thousands of triangles. The default scene of the README's main command.
Scene makeCloister();
CameraPath cloisterPath();

}  // namespace cubeao::scenes
