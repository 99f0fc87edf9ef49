#include "cubeao/ssao/ssao_pass.h"

#include <string>

#include "cubeao/gl/shader.h"

namespace cubeao {
namespace {

constexpr GLuint kGroup = 8;  // local_size_x/y of shaders/common/ssao.glsl

GLuint groups(int n) { return GLuint((n + int(kGroup) - 1) / int(kGroup)); }

void setInt(GLuint program, const char* name, int v) { glProgramUniform1i(program, glGetUniformLocation(program, name), v); }
void setFloat(GLuint program, const char* name, float v) {
    glProgramUniform1f(program, glGetUniformLocation(program, name), v);
}

}  // namespace

SsaoPass::SsaoPass(const SsaoSettings& settings) : settings_(settings) {
    program_ = gl::compileComputeProgram(std::string("ssao/") + ssaoMethodName(settings.method) + ".comp");
    fetchCount_ = gl::Buffer::create();
    glNamedBufferStorage(fetchCount_.id(), 2 * sizeof(std::uint32_t), nullptr, GL_DYNAMIC_STORAGE_BIT);
    const GLuint p = program_.id();
    // Uniforms fixed for the pass's lifetime (GL skips names a method does not use: location −1).
    glProgramUniform1f(p, glGetUniformLocation(p, "radius"), settings.radius);
    setInt(p, "falloff", settings.falloff == Falloff::Smooth ? 1 : 0);
    setInt(p, "directions", settings.directions);
    setInt(p, "steps", settings.steps);
    setFloat(p, "maxRadiusPixels", settings.maxRadiusPixels);
    setFloat(p, "intensity", settings.alchemyIntensity);
    setFloat(p, "contrast", settings.alchemyContrast);
    setFloat(p, "bias", settings.alchemyBias);
    setFloat(p, "epsilon", settings.alchemyEpsilon);
}

void SsaoPass::run(const CameraGBuffer& gbuffer, const CameraView& view, std::uint32_t frame, GLuint aoImage) {
    const GLuint p = program_.id();
    const std::uint32_t zero[2] = {0u, 0u};
    glNamedBufferSubData(fetchCount_.id(), 0, sizeof zero, zero);
    glProgramUniform2i(p, glGetUniformLocation(p, "frameSize"), gbuffer.width(), gbuffer.height());
    glProgramUniform1f(p, glGetUniformLocation(p, "tanHalfFovY"), view.tanHalfFovY);
    glProgramUniform1ui(p, glGetUniformLocation(p, "frameKey"), frame ^ settings_.seed);
    glUseProgram(p);
    glBindTextureUnit(0, gbuffer.depthTexture());
    glBindTextureUnit(1, gbuffer.normalTexture());
    glBindImageTexture(0, aoImage, 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_R32F);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 4, fetchCount_.id());
    glDispatchCompute(groups(gbuffer.width()), groups(gbuffer.height()), 1);
    glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
    pixels_ = double(gbuffer.width()) * double(gbuffer.height());
}

double SsaoPass::fetchesPerPixel() const {
    if (pixels_ == 0.0) return 0.0;
    std::uint32_t words[2] = {0u, 0u};
    glGetNamedBufferSubData(fetchCount_.id(), 0, sizeof words, words);
    return double(std::uint64_t(words[1]) << 32 | words[0]) / pixels_;
}

}  // namespace cubeao
