// The camera of a run-time frame, for every screen-space pass and its CPU twin: pixel ↔ view-space
// maps of a pinhole camera. Conventions (src/cubeao/runtime/camera_view.h, the C++ face, says more):
// view space looks down −z, x right, y up; pixel row 0 is the TOP row and the centre of pixel (x, y)
// is (x + 0.5, y + 0.5); a camera G-buffer texel is the pixel with the same indices; view depth z > 0
// is the distance along the view axis, 0 = no geometry.
// Shaders get the kernels bound to the uniforms frameSize and tanHalfFovY (GLSL-only block at the end).
#pragma once

#include "glsl_cpp.h"

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

CUBEAO_KERNEL_END

#ifndef __cplusplus
uniform ivec2 frameSize;  // width, height in pixels
uniform float tanHalfFovY;

vec3 pixelRay(vec2 pixel) { return cameraPixelRay(frameSize, tanHalfFovY, pixel); }
vec3 viewPosition(ivec2 texel, float depth) { return cameraViewPosition(frameSize, tanHalfFovY, texel, depth); }
float focalPixels() { return cameraFocalPixels(frameSize, tanHalfFovY); }
bool onScreen(ivec2 texel) { return all(greaterThanEqual(texel, ivec2(0))) && all(lessThan(texel, frameSize)); }
#endif
