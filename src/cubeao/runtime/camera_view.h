// One camera frame as the run-time passes see it: the view transform, the pinhole intrinsics and the
// pixel <-> view-space maps every screen-space pass shares. Pure (no GL), unit-tested on the CPU.
//
// Conventions:
//  - View space is right-handed, camera at the origin looking down −z, x right, y up; the basis is
//    PinholeCamera's (right, up, −forward), so a view-space ray equals PinholeCamera::rayDirection.
//  - Pixel (x, y) has y = 0 at the TOP row, as Image, EXR/PNG and `cubeao reference` use; pixel
//    centres sit at (x + 0.5, y + 0.5). Camera G-buffer texels use the same indices (texel row 0 =
//    image top), so no pass ever flips rows.
//  - "View depth" z is the distance along the view axis (−view.z > 0); 0 marks "no geometry".
// pixelRay, viewPosition and focalPixels are the shared kernels of shaders/common/camera.h, which the
// screen-space shaders compile too; projectToPixel and the matrices are C++ only.
#pragma once

#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>
#include <glm/mat4x4.hpp>
#include <glm/matrix.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "common/camera.h"
#include "cubeao/core/camera.h"

namespace cubeao {

struct CameraView {
    glm::mat4 viewFromWorld{1.0f};
    float tanHalfFovY = 0.5773503f;  // tan(30°)
    int width = 1, height = 1;
    float nearPlane = 0.05f;  // the G-buffer clips nearer geometry; there is no far plane (reversed-Z)

    // From PinholeCamera's public fields only (its basis is already orthonormal).
    static CameraView fromPinhole(const PinholeCamera& camera, float nearPlane) {
        CameraView v;
        const glm::vec3 back = -camera.forward;
        // Columns of a glm::mat4 are indexed first: m[col][row]. Rows are right, up, back.
        for (int c = 0; c < 3; ++c) {
            v.viewFromWorld[c][0] = camera.right[c];
            v.viewFromWorld[c][1] = camera.up[c];
            v.viewFromWorld[c][2] = back[c];
            v.viewFromWorld[c][3] = 0.0f;
        }
        v.viewFromWorld[3] = glm::vec4(-glm::dot(camera.right, camera.eye), -glm::dot(camera.up, camera.eye),
                                       -glm::dot(back, camera.eye), 1.0f);
        v.tanHalfFovY = camera.tanHalfFovY;
        v.width = camera.width;
        v.height = camera.height;
        v.nearPlane = nearPlane;
        return v;
    }
    // Frame `frame` of a camera path at width × height, clipped at the path's near plane.
    static CameraView fromPath(const CameraPath& path, std::size_t frame, int width, int height) {
        return fromPinhole(PinholeCamera(path, frame, width, height), path.nearPlane);
    }

    float aspect() const { return float(width) / float(height); }
    // Pixels per view-space unit at view depth 1 (the focal length in pixels).
    float focalPixels() const { return kernel::cameraFocalPixels({width, height}, tanHalfFovY); }
    glm::mat3 viewFromWorldRotation() const { return glm::mat3(viewFromWorld); }
    // What a per-pixel pass over a frameWidth × frameHeight image reads of this camera (camera.h).
    kernel::CameraBlock block(int frameWidth, int frameHeight, std::uint32_t frameKey = 0) const {
        return {worldFromView(), {frameWidth, frameHeight}, tanHalfFovY, frameKey};
    }
    glm::mat4 worldFromView() const { return glm::inverse(viewFromWorld); }

    // View-space ray through the centre of pixel (x, y) with z = −1 (so viewPosition = ray · depth).
    glm::vec3 pixelRay(float x, float y) const {
        return kernel::cameraPixelRay({width, height}, tanHalfFovY, {x + 0.5f, y + 0.5f});
    }
    glm::vec3 viewPosition(int x, int y, float depth) const {
        return kernel::cameraViewPosition({width, height}, tanHalfFovY, {x, y}, depth);
    }
    // Continuous pixel coordinates (centre of pixel (x, y) = (x + 0.5, y + 0.5)) of a view-space
    // point in front of the camera.
    glm::vec2 projectToPixel(const glm::vec3& v) const {
        const float d = -v.z;
        return {(v.x / (d * tanHalfFovY * aspect()) + 1.0f) * 0.5f * float(width),
                (1.0f - v.y / (d * tanHalfFovY)) * 0.5f * float(height)};
    }
    // A world length at view depth z, in pixels (DESIGN.md §4: the AO radius R projected to screen).
    float projectedPixels(float worldLength, float depth) const { return worldLength * focalPixels() / depth; }

    // Reversed-Z, infinite far plane, depth range [0, 1] (glClipControl(..., GL_ZERO_TO_ONE)):
    // window depth = near / viewDepth, 1 at the near plane, → 0 far away. Clear depth to 0 and test
    // with GL_GREATER. Float depth then keeps ~7 significant digits at every distance.
    glm::mat4 clipFromView() const {
        glm::mat4 m(0.0f);
        m[0][0] = 1.0f / (tanHalfFovY * aspect());
        m[1][1] = 1.0f / tanHalfFovY;
        m[3][2] = nearPlane;  // clip.z = near
        m[2][3] = -1.0f;      // clip.w = −view.z
        return m;
    }
};

}  // namespace cubeao
