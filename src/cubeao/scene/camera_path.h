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

// Throws cubeao::Error naming the file and the field that is missing or wrong.
CameraPath readCameraPath(const std::filesystem::path& file);
CameraPath parseCameraPath(const std::string& json, const std::string& sourceName);
void writeCameraPath(const std::filesystem::path& file, const CameraPath& path);

// "A:B", "A:", ":B" or "" (all); negative numbers count from the end as in Python. Throws
// cubeao::UsageError when the text is malformed or the range is empty.
FrameRange parseFrameRange(const std::string& text, std::size_t frameCount);

}  // namespace cubeao
