// Procedural scenes addressable as "builtin:NAME". scene/ keeps only the table; the geometry lives in
// scenes/ (library cubeao_scenes, one layer above this one), which fills the table through
// registerBuiltinScene when a program calls cubeao::scenes::registerBuiltinScenes() at start (the
// CLI's main, the tests' main). An explicit call, not a static registrar: a registrar object in a
// static library is dropped by the linker when nothing references its translation unit.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "cubeao/scene/camera_path.h"
#include "cubeao/scene/scene.h"

namespace cubeao {

// A spec is "builtin:NAME" or "builtin:NAME:ARG": everything after the name's ':' is ARG, handed to the
// scene's two functions (e.g. builtin:town:10m, a triangle count). A scene registered with functions that
// take no argument refuses a non-empty ARG with an Error; "builtin:NAME:" is the same as "builtin:NAME".
struct BuiltinScene {
    using MakeScene = std::function<Scene(const std::string& arg)>;
    using MakePath = std::function<CameraPath(const std::string& arg)>;

    MakeScene makeScene;   // the raw geometry; makeBuiltinScene prepares it
    MakePath cameraPath;   // the scene's own short walk
    bool takesArgument = false;

    BuiltinScene() = default;
    // A scene without an argument (the functions are wrapped; a null function stays null).
    BuiltinScene(std::function<Scene()> scene, std::function<CameraPath()> path);
    // A scene whose functions read ARG ("" when the spec has none).
    BuiltinScene(MakeScene scene, MakePath path);
};
// Adds "builtin:NAME"; Error when NAME is empty, has a ':' or is already registered. Thread-safe.
void registerBuiltinScene(const std::string& name, BuiltinScene scene);

bool isBuiltinSpec(const std::string& spec);            // starts with "builtin:"
std::vector<std::string> builtinSceneNames();           // sorted: "box-room", "cloister", ..., "two-rooms"
// "builtin:NAME[:ARG]"; Error listing the names if unknown, or when NAME takes no ARG and one is given.
Scene makeBuiltinScene(const std::string& spec);
CameraPath builtinCameraPath(const std::string& spec);  // the scene's own short walk (for the same ARG)

// The camera path a command should use: the file `cameraArg`, or "builtin:NAME", or, when `cameraArg`
// is empty and the scene is built in, the scene's own path. Error when neither applies.
CameraPath resolveCameraPath(const std::string& cameraArg, const std::string& sceneSpec);
// The same for a loaded scene, with the frames relative to scene.origin (camera path files hold file
// coordinates; the scene is local): the one place where a command's camera path meets its scene.
CameraPath resolveCameraPath(const std::string& cameraArg, const Scene& scene);

}  // namespace cubeao
