#include "cubeao/core/camera.h"

#include <cmath>

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include "common/camera.h"

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

glm::vec3 PinholeCamera::rayDirection(int x, int y) const { return rayDirectionAt(float(x) + 0.5f, float(y) + 0.5f); }

glm::vec3 PinholeCamera::rayDirectionAt(float x, float y) const {
    // The view-space ray of the run time's passes (view space looks down −z), turned into the world.
    const glm::vec3 r = kernel::cameraPixelRay({width, height}, tanHalfFovY, {x, y});
    return glm::normalize(forward + r.x * right + r.y * up);
}

}  // namespace cubeao
