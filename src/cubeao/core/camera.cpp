#include "cubeao/core/camera.h"

#include <cmath>

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

namespace cubeao {

PinholeCamera::PinholeCamera(const CameraPath& path, std::size_t frame, int w, int h)
    : width(w), height(h) {
    const CameraFrame& f = path.frames.at(frame);
    eye = f.eye;
    forward = glm::normalize(f.target - f.eye);
    right = glm::normalize(glm::cross(forward, path.up));
    up = glm::cross(right, forward);
    tanHalfFovY = std::tan(glm::radians(path.fovYDeg) * 0.5f);
}

glm::vec3 PinholeCamera::rayDirection(int x, int y) const {
    const float aspect = float(width) / float(height);
    const float sx = (2.0f * (float(x) + 0.5f) / float(width) - 1.0f) * tanHalfFovY * aspect;
    const float sy = (1.0f - 2.0f * (float(y) + 0.5f) / float(height)) * tanHalfFovY;
    return glm::normalize(forward + sx * right + sy * up);
}

}  // namespace cubeao
