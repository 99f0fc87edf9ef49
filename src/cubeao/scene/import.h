// Loading a SCENE argument: a model file (OBJ/PLY/OFF/STL through OpenMesh; every other format the
// installed assimp reads: IFC, glTF, FBX, DXF, X3D, BLEND, 3MF, LWO, ...) or "builtin:NAME" (scenes/). Every path ends in validation and repair (repair.h).
#pragma once

#include <string>
#include <vector>

#include "cubeao/scene/scene.h"

namespace cubeao {

// Throws cubeao::Error naming the file and the problem (missing, unknown format, empty, bad data).
Scene loadScene(const std::string& spec);

// File extensions (lower case, with dot) loadScene understands: OpenMesh's four, then the installed
// assimp's, sorted.
std::vector<std::string> supportedExtensions();

}  // namespace cubeao
