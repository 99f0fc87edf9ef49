// Camera paths as data, and the pinhole camera they define. Lives in core/ because the run time
// (runtime/camera_view.h) builds its CameraView from a PinholeCamera and must not depend on scene/;
// reading and writing the JSON format of ../shared/scenes/README.md stays in scene/camera_path.h.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include <glm/ext/vector_double3.hpp>
#include <glm/vec3.hpp>

namespace cubeao {

struct CameraFrame {
    glm::vec3 eye{0.0f};
    glm::vec3 target{0.0f, 0.0f, -1.0f};
};

struct CameraPath {
    std::string scene;  // informative: the model the path was made for
    // File coordinates of the point the frames' eyes and targets are relative to: the scene's origin
    // (scene.h, Scene::origin) once the path is read against a scene, 0 for a path near its file's origin.
    glm::dvec3 origin{0.0};
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

    // Throws std::out_of_range when `frame` is not in the path.
    PinholeCamera(const CameraPath& path, std::size_t frame, int width, int height);
    // Unit direction through the centre of pixel (x, y); y = 0 is the top row.
    glm::vec3 rayDirection(int x, int y) const;
    // Unit direction through image position (x, y) in pixels: (0, 0) the top-left corner of the image,
    // (x + 0.5, y + 0.5) the centre of pixel (x, y).
    glm::vec3 rayDirectionAt(float x, float y) const;
};

}  // namespace cubeao
