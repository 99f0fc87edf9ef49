// The camera of a run-time frame: GLSL twin of src/cubeao/runtime/camera_view.h (read its header for
// the conventions: view space looks down −z, pixel row 0 is the top, G-buffer texel = pixel).
// The including shader sets the uniforms below.
#pragma once

uniform ivec2 frameSize;    // width, height in pixels
uniform float tanHalfFovY;

// View-space ray through continuous pixel position `pixel` (centre of pixel (x, y) = (x + 0.5, y + 0.5)),
// with z = −1, so a surface at view depth z is at pixelRay(...) * z.
vec3 pixelRay(vec2 pixel) {
    float aspect = float(frameSize.x) / float(frameSize.y);
    return vec3((2.0 * pixel.x / float(frameSize.x) - 1.0) * tanHalfFovY * aspect,
                (1.0 - 2.0 * pixel.y / float(frameSize.y)) * tanHalfFovY, -1.0);
}

vec3 viewPosition(ivec2 texel, float depth) { return pixelRay(vec2(texel) + 0.5) * depth; }

// Pixels per view-space unit at view depth 1 (camera_view.h focalPixels).
float focalPixels() { return 0.5 * float(frameSize.y) / tanHalfFovY; }

bool onScreen(ivec2 texel) { return all(greaterThanEqual(texel, ivec2(0))) && all(lessThan(texel, frameSize)); }
