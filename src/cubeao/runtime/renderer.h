// The measuring renderer of `cubeao render` and the benchmarks: one run-time frame, pass by pass
// (DESIGN.md §4 "Projection"), timed and read back. It wraps a FramePipeline (frame_pipeline.h, the
// non-stalling frame loop an engine or the viewer uses: G-buffer → AO method → blur → composite) and
// calls the pipeline's stages one by one, each timed on its own with gl::timeGpu (GL timer queries on
// a real GPU, wall clock around glFinish on llvmpipe, where timer queries see only the hand-over),
// then reads the AO and the preview back. Both stall between passes by design: the figures are per
// pass and right on llvmpipe, and nothing here is a frame loop.
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "cubeao/core/image.h"
#include "cubeao/runtime/ao_pass.h"
#include "cubeao/runtime/blur.h"
#include "cubeao/runtime/camera_gbuffer.h"
#include "cubeao/runtime/composite.h"
#include "cubeao/runtime/frame_pipeline.h"  // PassTimings

namespace cubeao {

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

    AoPass& method() { return pipeline_.method(); }
    const CameraGBuffer& gbuffer() const { return pipeline_.gbuffer(); }
    const Blur& blur() const { return pipeline_.blur(); }
    // The wrapped pipeline, e.g. for its textures. Its render() must not be called inside one of this
    // renderer's frames (its timer queries would nest with timeGpu's).
    FramePipeline& pipeline() { return pipeline_; }

private:
    FramePipeline pipeline_;
};

}  // namespace cubeao
