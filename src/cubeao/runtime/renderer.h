// One run-time frame, pass by pass (DESIGN.md §4 "Projection"): camera G-buffer → AO method (any
// AoPass: a screen-space baseline or the probe projection) → edge-aware blur → composite, then the
// read-back of the AO and the preview. Every pass is timed on its own (gl::timeGpu: GL timer
// queries on a real GPU, wall clock around glFinish on llvmpipe), which stalls between passes:
// this is the measuring renderer of `cubeao render`, not a frame loop.
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "cubeao/gl/handles.h"
#include "cubeao/core/image.h"
#include "cubeao/runtime/ao_pass.h"
#include "cubeao/runtime/blur.h"
#include "cubeao/runtime/camera_gbuffer.h"
#include "cubeao/runtime/composite.h"

namespace cubeao {

struct PassTimings {  // milliseconds, by the clock gl::trustedClock() picks
    double gbuffer = 0.0, ao = 0.0, blur = 0.0, composite = 0.0, readback = 0.0;
};

struct RenderedFrame {
    Image ao;                      // after the blur; 1 = open, 1 where no geometry (row 0 = top)
    std::vector<float> shadedRgb;  // the composite, linear RGB interleaved, 3 · width · height
    PassTimings timings;
};

class FrameRenderer {
public:
    // Uploads the mesh and compiles every pass: needs a current GL 4.5 context. `composite` must
    // have its light direction resolved (defaultLightDirection).
    FrameRenderer(std::span<const glm::vec3> positions, std::span<const std::uint32_t> indices,
                  std::unique_ptr<AoPass> method, const BlurSettings& blur, const CompositeSettings& composite);
    ~FrameRenderer();

    // Renders the camera path's frame `frame` as seen by `view` and reads it back.
    RenderedFrame render(const CameraView& view, std::uint32_t frame);
    // The last frame's AO before the blur (another read-back; for tests and diagnostics).
    Image readRawAo() const;

    AoPass& method() { return *method_; }
    const CameraGBuffer& gbuffer() const { return gbuffer_; }
    const Blur& blur() const { return blur_; }

private:
    void resize(int width, int height);

    CameraGBuffer gbuffer_;
    std::unique_ptr<AoPass> method_;
    Blur blur_;
    Composite composite_;
    gl::Texture rawAo_, ao_, shaded_;
    int width_ = 0, height_ = 0;
};

}  // namespace cubeao
