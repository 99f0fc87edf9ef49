// Procedural scenes addressable as "builtin:NAME" (their geometry lives in scenes/).
#pragma once

#include <string>
#include <vector>

#include "cubeao/scene/camera_path.h"
#include "cubeao/scene/scene.h"

namespace cubeao {

bool isBuiltinSpec(const std::string& spec);            // starts with "builtin:"
std::vector<std::string> builtinSceneNames();           // "sphere-plane", "box-room", "cloister"
Scene makeBuiltinScene(const std::string& spec);        // "builtin:NAME"; Error listing the names if unknown
CameraPath builtinCameraPath(const std::string& spec);  // the scene's own short walk

// The camera path a command should use: the file `cameraArg`, or "builtin:NAME", or, when `cameraArg`
// is empty and the scene is built in, the scene's own path. Error when neither applies.
CameraPath resolveCameraPath(const std::string& cameraArg, const std::string& sceneSpec);

}  // namespace cubeao
