#include "cubeao/ssao/ssao_pass.h"

#include <string>

#include "common/runtime_layout.h"
#include "cubeao/gl/shader.h"

namespace cubeao {

kernel::SsaoBlock ssaoBlock(const SsaoSettings& s) {
    return {s.radius,          falloffUniform(s.falloff), s.directions,     s.steps,         s.maxRadiusPixels,
            s.alchemyIntensity, s.alchemyContrast,        s.alchemyBias,    s.alchemyEpsilon};
}

SsaoPass::SsaoPass(const SsaoSettings& settings) : settings_(settings) {
    program_ = gl::compileComputeProgram(std::string("ssao/") + ssaoMethodName(settings.method) + ".comp");
    fetchCount_ = gl::Buffer::create();
    glNamedBufferStorage(fetchCount_.id(), kernel::kPassCounterBytes, nullptr, GL_DYNAMIC_STORAGE_BIT);
    block_ = gl::UniformBlock::create(ssaoBlock(settings));
}

void SsaoPass::run(const CameraGBuffer& gbuffer, const CameraView& view, std::uint32_t frame, GLuint aoImage) {
    glClearNamedBufferData(fetchCount_.id(), GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, nullptr);
    glUseProgram(program_.id());
    block_.bind(kernel::kSsaoBlock);
    camera_.upload(view.block(gbuffer.width(), gbuffer.height(), frame ^ settings_.seed), kernel::kCameraBlock);
    glBindTextureUnit(kernel::kGBufferDepthUnit, gbuffer.depthTexture());
    glBindTextureUnit(kernel::kGBufferNormalUnit, gbuffer.normalTexture());
    glBindImageTexture(kernel::kAoImageUnit, aoImage, 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_R32F);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kernel::kPassCountersBuffer, fetchCount_.id());
    glDispatchCompute(kernel::pixelGroups(gbuffer.width()), kernel::pixelGroups(gbuffer.height()), 1);
    glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
    pixels_ = double(gbuffer.width()) * double(gbuffer.height());
}

double SsaoPass::fetchesPerPixel() const {
    if (pixels_ == 0.0) return 0.0;
    return double(readPassCounters(fetchCount_.id()).fetches) / pixels_;
}

}  // namespace cubeao
