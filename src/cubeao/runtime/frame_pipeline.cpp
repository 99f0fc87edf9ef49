#include "cubeao/runtime/frame_pipeline.h"

#include "cubeao/core/error.h"
#include "cubeao/gl/timer.h"

namespace cubeao {

FramePipeline::FramePipeline(std::span<const glm::vec3> positions, std::span<const std::uint32_t> indices,
                             std::unique_ptr<AoPass> method, const BlurSettings& blur,
                             const CompositeSettings& composite)
    : gbuffer_(positions, indices), method_(std::move(method)), blur_(blur), composite_(composite) {
    if (!method_) throw Error("FramePipeline: no AO method");
    for (TimingSlot& slot : ring_)
        for (gl::Query& q : slot.queries) q = gl::Query::create(GL_TIME_ELAPSED);
    timesAreExecution_ = gl::trustedClock() == gl::GpuClock::TimerQuery;
}

// Deleting a query whose result is pending may wait for it in some drivers (llvmpipe does): fine
// here, a pipeline is destroyed outside the frame loop.
FramePipeline::~FramePipeline() = default;

void FramePipeline::prepare(const CameraView& view) {
    if (view.width == width_ && view.height == height_) return;
    const auto texture = [&](GLenum format) {
        gl::Texture t = gl::Texture::create(GL_TEXTURE_2D);
        glTextureStorage2D(t.id(), 1, format, view.width, view.height);
        return t;
    };
    rawAo_ = texture(GL_R32F);
    ao_ = texture(GL_R32F);
    shaded_ = texture(GL_RGBA8);
    width_ = view.width, height_ = view.height;
}

void FramePipeline::renderGBuffer(const CameraView& view) { gbuffer_.render(view); }

void FramePipeline::runAo(const CameraView& view, std::uint32_t frame) {
    method_->run(gbuffer_, view, frame, rawAo_.id());
}

void FramePipeline::runBlur(const CameraView& view) { blur_.run(gbuffer_, view, rawAo_.id(), ao_.id()); }

void FramePipeline::runComposite(const CameraView& view) {
    composite_.run(gbuffer_, view, ao_.id(), shaded_.id());
}

void FramePipeline::render(const CameraView& view, std::uint32_t frame) {
    // Take whatever earlier frames have finished, then claim this frame's slot. A slot still
    // pending after kTimingFrames frames means the GPU (or the driver) is further behind than the
    // ring: waiting for it would be exactly the stall this class exists to avoid, so its timings go.
    for (TimingSlot& slot : ring_)
        if (slot.pending) collect(slot);
    TimingSlot& slot = ring_[serial_ % kTimingFrames];
    if (slot.pending) {
        slot.pending = false;
        ++dropped_;
    }
    slot.timings = PipelineTimings{serial_, frame, {}};
    ++serial_;

    prepare(view);
    const auto timed = [](gl::Query& query, auto&& stage) {
        glBeginQuery(GL_TIME_ELAPSED, query.id());
        stage();
        glEndQuery(GL_TIME_ELAPSED);
    };
    timed(slot.queries[0], [&] { renderGBuffer(view); });
    timed(slot.queries[1], [&] { runAo(view, frame); });
    timed(slot.queries[2], [&] { runBlur(view); });
    timed(slot.queries[3], [&] { runComposite(view); });
    slot.pending = true;
    // Without a flush the commands may sit in the driver until the next implicit one, and the queries
    // with them; llvmpipe even finishes the whole pipeline when a query still in an unflushed batch
    // is begun again. glFlush only submits: it does not wait.
    glFlush();
}

bool FramePipeline::collect(TimingSlot& slot) {
    for (const gl::Query& q : slot.queries) {
        GLint available = GL_FALSE;
        glGetQueryObjectiv(q.id(), GL_QUERY_RESULT_AVAILABLE, &available);
        if (available != GL_TRUE) return false;
    }
    // Every result is available; GL_QUERY_RESULT_NO_WAIT (GL 4.4) leaves the value untouched rather
    // than waiting if it were not, so this read can never stall whatever the driver answered above.
    double* const ms[4] = {&slot.timings.passes.gbuffer, &slot.timings.passes.ao, &slot.timings.passes.blur,
                           &slot.timings.passes.composite};
    for (std::size_t i = 0; i < slot.queries.size(); ++i) {
        GLuint64 ns = 0;
        glGetQueryObjectui64v(slot.queries[i].id(), GL_QUERY_RESULT_NO_WAIT, &ns);
        *ms[i] = static_cast<double>(ns) * 1e-6;
    }
    slot.pending = false;
    if (!latest_ || slot.timings.serial > latest_->serial) latest_ = slot.timings;
    return true;
}

std::optional<PipelineTimings> FramePipeline::latestTimings() {
    for (TimingSlot& slot : ring_)
        if (slot.pending) collect(slot);
    return latest_;
}

}  // namespace cubeao
