#include "cubeao/ssao/ssao_pass.h"

#include <string>

#include "common/runtime_layout.h"
#include "cubeao/gl/shader.h"

namespace cubeao {
namespace {

void setInt(GLuint program, const char* name, int v) { glProgramUniform1i(program, gl::uniformLocation(program, name), v); }
void setFloat(GLuint program, const char* name, float v) {
    glProgramUniform1f(program, gl::uniformLocation(program, name), v);
}

}  // namespace

void setSsaoUniforms(GLuint p, SsaoMethod method, const SsaoSettings& settings) {
    setFloat(p, "radius", settings.radius);
    setInt(p, "falloff", falloffUniform(settings.falloff));
    setInt(p, "directions", settings.directions);
    setInt(p, "steps", settings.steps);
    setFloat(p, "maxRadiusPixels", settings.maxRadiusPixels);
    if (method != SsaoMethod::Alchemy) return;
    setFloat(p, "intensity", settings.alchemyIntensity);
    setFloat(p, "contrast", settings.alchemyContrast);
    setFloat(p, "bias", settings.alchemyBias);
    setFloat(p, "epsilon", settings.alchemyEpsilon);
}

SsaoPass::SsaoPass(const SsaoSettings& settings) : settings_(settings) {
    program_ = gl::compileComputeProgram(std::string("ssao/") + ssaoMethodName(settings.method) + ".comp");
    fetchCount_ = gl::Buffer::create();
    glNamedBufferStorage(fetchCount_.id(), kernel::kPassCounterBytes, nullptr, GL_DYNAMIC_STORAGE_BIT);
    setSsaoUniforms(program_.id(), settings.method, settings);  // fixed for the pass's lifetime
}

void SsaoPass::run(const CameraGBuffer& gbuffer, const CameraView& view, std::uint32_t frame, GLuint aoImage) {
    const GLuint p = program_.id();
    glClearNamedBufferData(fetchCount_.id(), GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, nullptr);
    glProgramUniform2i(p, gl::uniformLocation(p, "frameSize"), gbuffer.width(), gbuffer.height());
    glProgramUniform1f(p, gl::uniformLocation(p, "tanHalfFovY"), view.tanHalfFovY);
    glProgramUniform1ui(p, gl::uniformLocation(p, "frameKey"), frame ^ settings_.seed);
    glUseProgram(p);
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
