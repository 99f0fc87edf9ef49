// Camera paths in the JSON format of ../shared/scenes/README.md, and the pinhole camera they define.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

namespace cubeao {

struct CameraFrame {
    glm::vec3 eye{0.0f};
    glm::vec3 target{0.0f, 0.0f, -1.0f};
};

struct CameraPath {
    std::string scene;  // informative: the model the path was made for
    glm::vec3 up{0.0f, 1.0f, 0.0f};
    float fovYDeg = 60.0f;
    int width = 1280;
    int height = 720;
    float nearPlane = 0.05f;
    float farPlane = 200.0f;
    std::vector<CameraFrame> frames;
};

// One view: the basis of the README (forward = normalize(target − eye), right = normalize(forward × up),
// camera up = right × forward) and primary ray directions through pixel centres.
struct PinholeCamera {
    glm::vec3 eye, forward, right, up;
    float tanHalfFovY;
    int width, height;

    PinholeCamera(const CameraPath& path, std::size_t frame, int width, int height);
    // Unit direction through the centre of pixel (x, y); y = 0 is the top row.
    glm::vec3 rayDirection(int x, int y) const;
};

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
