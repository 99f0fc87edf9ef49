// The run-time frame pipeline (DESIGN.md §4 "Run time that grows"): camera G-buffer → AO method (any
// AoPass: a screen-space baseline or the probe projection) → edge-aware blur → composite, issued
// without ever waiting for the GPU. An engine or the viewer calls render() once per frame and samples
// the output textures; nothing here blocks the CPU on the GPU:
//  - no glFinish, no read-back (glGetTextureImage, glReadPixels, buffer reads or read mappings);
//  - per-pass GPU times come from GL_TIME_ELAPSED queries kept in a ring of kTimingFrames frames and
//    collected frames later by polling GL_QUERY_RESULT_AVAILABLE; a result is only read once it is
//    available, and with GL_QUERY_RESULT_NO_WAIT, so even a wrong availability answer cannot stall. A
//    frame whose queries are still pending when its slot comes round again loses its timings (counted
//    in droppedTimings()) rather than making the new frame wait.
// Caveat of the clock: on Mesa llvmpipe a GL_TIME_ELAPSED query covers only handing the work over to
// the rasteriser threads, not running it (gl/timer.h); measured (Mesa 22.3, Debian 12) it even reads
// 0 for compute passes and the host's uptime for the G-buffer's draw, as gl::timeGpu's query does
// there. These times mean something on a real GPU only: timesAreExecution() says which.
// The measuring wrapper FrameRenderer (renderer.h) times the same stage calls with gl::timeGpu (wall
// clock around glFinish on llvmpipe) and reads the frame back: the renderer of `cubeao render` and
// the benchmarks, not a frame loop. tests/runtime/test_frame_pipeline.cpp checks the no-wait promise through
// a GL wrapper that counts every waiting or reading GL call.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>

#include <glm/vec3.hpp>

#include "cubeao/gl/handles.h"
#include "cubeao/runtime/ao_pass.h"
#include "cubeao/runtime/blur.h"
#include "cubeao/runtime/camera_gbuffer.h"
#include "cubeao/runtime/camera_view.h"
#include "cubeao/runtime/composite.h"

namespace cubeao {

struct PassTimings {  // milliseconds; FrameRenderer: by the clock gl::trustedClock() picks
    double gbuffer = 0.0, ao = 0.0, blur = 0.0, composite = 0.0;
    double readback = 0.0;  // FrameRenderer only: the pipeline never reads back (always 0 there)
};

// GL_TIME_ELAPSED per pass of one frame the pipeline rendered, collected frames later.
struct PipelineTimings {
    std::uint64_t serial = 0;  // which render() call: 0 for the pipeline's first frame, then 1, 2, …
    std::uint32_t frame = 0;   // the camera path's frame index that call was given
    PassTimings passes;        // readback is 0
};

class FramePipeline {
public:
    // Frames whose timer queries may be in flight at once. A real GPU runs 1–3 frames behind the
    // CPU, so results of frame n are usually available by frame n + 2; four slots leave slack
    // before a frame's timings are dropped.
    static constexpr std::size_t kTimingFrames = 4;

    // Uploads the mesh and compiles every pass: needs a current GL 4.5 context. `composite` must
    // have its light direction resolved (defaultLightDirection).
    FramePipeline(std::span<const glm::vec3> positions, std::span<const std::uint32_t> indices,
                  std::unique_ptr<AoPass> method, const BlurSettings& blur, const CompositeSettings& composite);
    ~FramePipeline();
    FramePipeline(const FramePipeline&) = delete;
    FramePipeline& operator=(const FramePipeline&) = delete;

    // Issues the camera path's frame `frame` as seen by `view`: every stage below, each inside a
    // timer query of this frame's ring slot, then a glFlush so the work (and with it the queries)
    // starts now rather than at the next implicit flush. Returns without waiting for any of it.
    void render(const CameraView& view, std::uint32_t frame);

    // The stages render() issues, in order, untimed, for a caller that times or inspects them itself
    // (FrameRenderer wraps each in gl::timeGpu; GL_TIME_ELAPSED queries cannot nest, so these must
    // not open one). prepare() first: it sizes the output textures to the view (reallocated only
    // when the size changes, so one pipeline serves a walk). None of them waits.
    void prepare(const CameraView& view);
    void renderGBuffer(const CameraView& view);
    void runAo(const CameraView& view, std::uint32_t frame);  // G-buffer → rawAoTexture()
    void runBlur(const CameraView& view);                     // rawAoTexture() → aoTexture()
    void runComposite(const CameraView& view);                // G-buffer, aoTexture() → shadedTexture()

    // Collects every ring slot whose queries have all become available (polling only) and returns
    // the newest frame collected so far; nullopt until one has been. Results arrive frames late:
    // call it once per frame, or after a few frames, not right after render().
    std::optional<PipelineTimings> latestTimings();
    // Frames whose timings were dropped because their queries were still pending when the ring
    // came round to their slot again.
    std::uint64_t droppedTimings() const { return dropped_; }
    // Whether the timings measure execution on this renderer: false on llvmpipe and softpipe
    // (gl::trustedClock), where only the measuring FrameRenderer's wall clock does.
    bool timesAreExecution() const { return timesAreExecution_; }

    // The outputs of the last frame, width() × height(), row 0 at the top (camera_view.h): raw AO
    // and blurred AO (R32F, 1 = open), the composite (RGBA8, linear). Read them only after the GPU
    // is done (a fence, or glGetTextureImage in a tool that may wait).
    GLuint rawAoTexture() const { return rawAo_.id(); }
    GLuint aoTexture() const { return ao_.id(); }
    GLuint shadedTexture() const { return shaded_.id(); }
    int width() const { return width_; }
    int height() const { return height_; }

    AoPass& method() { return *method_; }
    const AoPass& method() const { return *method_; }
    const CameraGBuffer& gbuffer() const { return gbuffer_; }
    const Blur& blur() const { return blur_; }
    Blur& blur() { return blur_; }

private:
    // One frame's timer queries, one per stage, reused round the ring.
    struct TimingSlot {
        std::array<gl::Query, 4> queries;  // gbuffer, ao, blur, composite
        bool pending = false;              // issued, result not collected yet
        PipelineTimings timings;           // serial and frame of the pending frame
    };

    bool collect(TimingSlot& slot);  // true when the slot's results were available and taken

    CameraGBuffer gbuffer_;
    std::unique_ptr<AoPass> method_;
    Blur blur_;
    Composite composite_;
    gl::Texture rawAo_, ao_, shaded_;
    int width_ = 0, height_ = 0;

    std::array<TimingSlot, kTimingFrames> ring_;
    std::uint64_t serial_ = 0;  // render() calls so far
    std::uint64_t dropped_ = 0;
    std::optional<PipelineTimings> latest_;
    bool timesAreExecution_ = true;
};

}  // namespace cubeao
