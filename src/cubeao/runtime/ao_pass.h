// A run-time AO method: turns the camera G-buffer of one frame into a raw (unblurred) AO image.
// The screen-space baselines (src/cubeao/ssao/) and the probe projection implement it; blur and
// composite (blur.h, composite.h) are shared by all of them (runtime/renderer.h wires the passes).
#pragma once

#include <cstdint>

#include "common/runtime_layout.h"
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

// The counters a pass keeps in `buffer` (kernel::kPassCounterBytes: kCounterStripes PassCounters,
// runtime_layout.h), summed. A read-back: waits for the pass.
inline kernel::PassCountTotals readPassCounters(GLuint buffer) {
    kernel::PassCounters stripes[kernel::kCounterStripes];
    glGetNamedBufferSubData(buffer, 0, sizeof stripes, stripes);
    return kernel::sumPassCounters(stripes);
}

// What a method without an answer for some pixels calls to fill them (the probe projection, for
// pixels no resident probe sees: DESIGN.md §4 "Run time that grows"). The runtime library defines
// the interface; the screen-space fallback (GTAO, src/cubeao/ssao/) implements it, so the runtime
// does not depend on the baselines.
class AoFallback {
public:
    virtual ~AoFallback() = default;
    // Replaces every pixel of `aoImage` (R32F, bound as an image) whose value is below 0
    // (kernel::kUncoveredAo) by a screen-space estimate for `gbuffer`, and blends that estimate into
    // covered pixels next to them so no seam shows. Issues GL commands only: no wait, no read-back.
    virtual void fill(const CameraGBuffer& gbuffer, const CameraView& view, std::uint32_t frame, GLuint aoImage) = 0;
    // Pixels of the last frame that took the screen-space value entirely / partly (blended at the
    // boundary), over all pixels. May wait for the frame: call it after the frame, not inside it.
    virtual double filledFraction() const = 0;
    virtual double blendedFraction() const = 0;
};

}  // namespace cubeao
