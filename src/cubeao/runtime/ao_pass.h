// A run-time AO method: turns the camera G-buffer of one frame into a raw (unblurred) AO image.
// The screen-space baselines (src/cubeao/ssao/) and the probe projection implement it; blur and
// composite (blur.h, composite.h) are shared by all of them (runtime/renderer.h wires the passes).
#pragma once

#include <cstdint>

#include "cubeao/gl/gl.h"
#include "cubeao/runtime/camera_gbuffer.h"
#include "cubeao/runtime/camera_view.h"

namespace cubeao {

class AoPass {
public:
    virtual ~AoPass() = default;
    virtual const char* name() const = 0;
    // Writes AO for every pixel of `gbuffer` (rendered for `view`) into `aoImage`, an R32F texture of
    // the same size, bound as an image: 1 = open, 0 = fully occluded, the quantity of DESIGN.md §4
    // ("What AO means here"); pixels without geometry get 1, as in the reference. `frame` is the
    // camera path's frame index: a method with per-pixel noise mixes it with its seed, as the
    // reference does (key = hash(x, y, frame ^ seed)).
    virtual void run(const CameraGBuffer& gbuffer, const CameraView& view, std::uint32_t frame, GLuint aoImage) = 0;
    // Texture fetches per pixel that the last run made, averaged over all pixels of the frame (may
    // wait for the run to finish: call it after the frame, not inside it).
    virtual double fetchesPerPixel() const = 0;
};

}  // namespace cubeao
