// The camera of a run-time frame, for every screen-space pass and its CPU twin: pixel ↔ view-space
// maps of a pinhole camera. Conventions (src/cubeao/runtime/camera_view.h, the C++ face, says more):
// view space looks down −z, x right, y up; pixel row 0 is the TOP row and the centre of pixel (x, y)
// is (x + 0.5, y + 0.5); a camera G-buffer texel is the pixel with the same indices; view depth z > 0
// is the distance along the view axis, 0 = no geometry.
// Shaders get the kernels bound to the frame's CameraBlock (GLSL-only block at the end).
#pragma once

#include "glsl_cpp.h"
#include "runtime_layout.h"

CUBEAO_KERNEL_BEGIN

// View-space ray through continuous pixel position `pixel` with z = −1, so a surface at view depth z is
// at cameraPixelRay(...) · z. PinholeCamera::rayDirection (src/cubeao/core/camera.cpp) turns the same
// ray into the world, so the reference's primary rays and the camera G-buffer's pixels agree.
CUBEAO_FN vec3 cameraPixelRay(ivec2 frameSize, float tanHalfFovY, vec2 pixel) {
    float aspect = float(frameSize.x) / float(frameSize.y);
    return vec3((2.0f * pixel.x / float(frameSize.x) - 1.0f) * tanHalfFovY * aspect,
                (1.0f - 2.0f * pixel.y / float(frameSize.y)) * tanHalfFovY, -1.0f);
}

// The view-space point at view depth `depth` seen through the centre of pixel `texel`.
CUBEAO_FN vec3 cameraViewPosition(ivec2 frameSize, float tanHalfFovY, ivec2 texel, float depth) {
    return cameraPixelRay(frameSize, tanHalfFovY, vec2(texel) + 0.5f) * depth;
}

// Pixels per view-space unit at view depth 1 (the focal length in pixels).
CUBEAO_FN float cameraFocalPixels(ivec2 frameSize, float tanHalfFovY) { return 0.5f * float(frameSize.y) / tanHalfFovY; }

// A per-pixel pass's frame: one std140 uniform block at kCameraBlock that the pass fills from its
// CameraView each frame (CameraView::block, src/cubeao/runtime/camera_view.h).
struct CameraBlock {
    mat4 worldFromView;  // view space to the world (project, coverage_count)
    ivec2 frameSize;     // width, height in pixels
    float tanHalfFovY;
    uint frameKey;       // frame index ^ seed: the screen-space estimators' noise (ssao_pixel.glsl)
};

CUBEAO_KERNEL_END

#ifdef __cplusplus
#include <cstddef>  // offsetof

static_assert(offsetof(cubeao::kernel::CameraBlock, frameSize) == 64 &&
                  offsetof(cubeao::kernel::CameraBlock, tanHalfFovY) == 72 &&
                  offsetof(cubeao::kernel::CameraBlock, frameKey) == 76 && sizeof(cubeao::kernel::CameraBlock) == 80,
              "CameraBlock must keep std140 offsets (the per-pixel passes read it as a uniform block)");
#else
layout(std140, binding = kCameraBlock) uniform CameraUniforms { CameraBlock camera; };

vec3 pixelRay(vec2 pixel) { return cameraPixelRay(camera.frameSize, camera.tanHalfFovY, pixel); }
vec3 viewPosition(ivec2 texel, float depth) {
    return cameraViewPosition(camera.frameSize, camera.tanHalfFovY, texel, depth);
}
float focalPixels() { return cameraFocalPixels(camera.frameSize, camera.tanHalfFovY); }
bool onScreen(ivec2 texel) { return all(greaterThanEqual(texel, ivec2(0))) && all(lessThan(texel, camera.frameSize)); }
#endif
