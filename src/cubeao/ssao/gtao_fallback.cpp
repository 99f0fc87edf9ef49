#include "cubeao/ssao/gtao_fallback.h"

#include <string>

#include "cubeao/core/error.h"
#include "cubeao/gl/shader.h"
#include "cubeao/ssao/ssao_pass.h"

namespace cubeao {

GtaoFallback::GtaoFallback(const SsaoSettings& settings) : settings_(settings) {
    if (settings.method != SsaoMethod::Gtao)
        throw Error(std::string("GtaoFallback: settings for ") + ssaoMethodName(settings.method) + ", expected gtao");
    mark_ = gl::compileComputeProgram("ssao/gtao_fill.comp", {{"GTAO_FILL_PASS", "0"}});
    select_ = gl::compileComputeProgram("ssao/gtao_fill.comp", {{"GTAO_FILL_PASS", "1"}});
    fill_ = gl::compileComputeProgram("ssao/gtao_fill.comp", {{"GTAO_FILL_PASS", "2"}});
    counters_ = gl::Buffer::create();
    glNamedBufferStorage(counters_.id(), sizeof(kernel::FallbackCounters), nullptr, 0);
    const kernel::FallbackList emptyList{0u, 1u, 1u, 0u};  // an indirect dispatch of no group
    emptyList_ = gl::Buffer::create();
    glNamedBufferStorage(emptyList_.id(), sizeof emptyList, &emptyList, 0);
    block_ = gl::UniformBlock::create(ssaoBlock(settings));  // as SsaoPass's gtao: the same estimate per pixel
}

void GtaoFallback::fill(const CameraGBuffer& gbuffer, const CameraView& view, std::uint32_t frame, GLuint aoImage) {
    const int w = gbuffer.width(), h = gbuffer.height();
    if (w > kernel::kFallbackMaxFrameSide || h > kernel::kFallbackMaxFrameSide)
        throw Error("GtaoFallback: frame " + std::to_string(w) + " x " + std::to_string(h) + " exceeds " +
                    std::to_string(kernel::kFallbackMaxFrameSide) + " pixels a side");
    const GLuint groupsX = kernel::pixelGroups(w), groupsY = kernel::pixelGroups(h);
    const std::size_t tileCount = std::size_t(groupsX) * groupsY;
    if (tileCount > tileCapacity_) {  // immutable storage: new buffers when the frame grows
        const std::size_t pixels = tileCount * std::size_t(kernel::kPixelGroupSize * kernel::kPixelGroupSize);
        const auto create = [](gl::Buffer& b, std::size_t bytes) {
            b = gl::Buffer::create();
            glNamedBufferStorage(b.id(), GLsizeiptr(bytes), nullptr, 0);
        };
        create(tiles_, tileCount * sizeof(kernel::FallbackTile));
        create(tileList_, sizeof(kernel::FallbackList) + tileCount * sizeof(std::uint32_t));
        create(workList_, sizeof(kernel::FallbackList) + pixels * sizeof(std::uint32_t));
        tileCapacity_ = tileCount;
    }
    // Reset on the GPU, in order with the dispatches: no upload that could wait for the last frame.
    glClearNamedBufferSubData(tiles_.id(), GL_R32UI, 0, GLsizeiptr(tileCount * sizeof(kernel::FallbackTile)),
                              GL_RED_INTEGER, GL_UNSIGNED_INT, nullptr);
    glCopyNamedBufferSubData(emptyList_.id(), tileList_.id(), 0, 0, sizeof(kernel::FallbackList));
    glCopyNamedBufferSubData(emptyList_.id(), workList_.id(), 0, 0, sizeof(kernel::FallbackList));
    glClearNamedBufferData(counters_.id(), GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, nullptr);

    block_.bind(kernel::kSsaoBlock);
    camera_.upload(view.block(w, h, frame ^ settings_.seed), kernel::kCameraBlock);
    glBindTextureUnit(kernel::kGBufferDepthUnit, gbuffer.depthTexture());
    glBindTextureUnit(kernel::kGBufferNormalUnit, gbuffer.normalTexture());
    glBindImageTexture(kernel::kAoImageUnit, aoImage, 0, GL_FALSE, 0, GL_READ_WRITE, GL_R32F);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kernel::kFallbackTileBuffer, tiles_.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kernel::kFallbackTileListBuffer, tileList_.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kernel::kFallbackWorkBuffer, workList_.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kernel::kFallbackCountersBuffer, counters_.id());

    // The AO method's image stores before our loads (its pass ends with this barrier too; cheap twice).
    glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
    glUseProgram(mark_.id());
    glDispatchCompute(kernel::pixelGroups(int(groupsX)), groupsY, 1);  // an invocation per tile row
    // Each list's head is the next dispatch's indirect command.
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_COMMAND_BARRIER_BIT);
    glUseProgram(select_.id());
    glBindBuffer(GL_DISPATCH_INDIRECT_BUFFER, tileList_.id());
    glDispatchComputeIndirect(0);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_COMMAND_BARRIER_BIT);
    glUseProgram(fill_.id());
    glBindBuffer(GL_DISPATCH_INDIRECT_BUFFER, workList_.id());
    glDispatchComputeIndirect(0);
    glBindBuffer(GL_DISPATCH_INDIRECT_BUFFER, 0);
    glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
    pixels_ = double(w) * double(h);
}

kernel::FallbackCounters GtaoFallback::counters() const {
    kernel::FallbackCounters c{};
    if (pixels_ > 0.0) glGetNamedBufferSubData(counters_.id(), 0, sizeof c, &c);
    return c;
}

double GtaoFallback::filledFraction() const { return pixels_ > 0.0 ? double(counters().filled) / pixels_ : 0.0; }

double GtaoFallback::blendedFraction() const { return pixels_ > 0.0 ? double(counters().blended) / pixels_ : 0.0; }

double GtaoFallback::fetchesPerPixel() const {
    if (pixels_ == 0.0) return 0.0;
    const kernel::FallbackCounters c = counters();
    return double(kernel::joinWords(c.fetchesLow, c.fetchesHigh)) / pixels_;
}

}  // namespace cubeao
