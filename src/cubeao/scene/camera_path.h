// Camera paths in the JSON format of ../shared/scenes/README.md. The types themselves (CameraPath,
// PinholeCamera) live in core/camera.h, which the run time uses too.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "cubeao/core/camera.h"

namespace cubeao {

// A half-open range of frame indices [begin, end), from "--frames A:B" (Python slice syntax).
struct FrameRange {
    std::size_t begin = 0, end = 0;
    std::size_t size() const { return end - begin; }
};

// Throws cubeao::Error naming the file and the field that is missing or wrong. The file holds file
// coordinates; eyes and targets are read in double and stored relative to `origin` (the scene's,
// Scene::origin: pass it so a path of a georeferenced model keeps its precision), path.origin = origin.
CameraPath readCameraPath(const std::filesystem::path& file, const glm::dvec3& origin = glm::dvec3(0.0));
CameraPath parseCameraPath(const std::string& json, const std::string& sourceName,
                           const glm::dvec3& origin = glm::dvec3(0.0));
// Writes file coordinates (frames + path.origin, in double).
void writeCameraPath(const std::filesystem::path& file, const CameraPath& path);
// Makes the frames relative to `origin` instead of path.origin (the difference in double), e.g. a
// built-in path (origin 0) used with a re-centred scene.
void rebaseCameraPath(CameraPath& path, const glm::dvec3& origin);

// "A:B", "A:", ":B" or "" (all); negative numbers count from the end as in Python. Throws
// cubeao::UsageError when the text is malformed or the range is empty.
FrameRange parseFrameRange(const std::string& text, std::size_t frameCount);

}  // namespace cubeao
