#include "cubeao/runtime/renderer.h"

#include <chrono>

#include "cubeao/gl/timer.h"

namespace cubeao {

FrameRenderer::FrameRenderer(std::span<const glm::vec3> positions, std::span<const std::uint32_t> indices,
                             std::unique_ptr<AoPass> method, const BlurSettings& blur,
                             const CompositeSettings& composite)
    : pipeline_(positions, indices, std::move(method), blur, composite) {}

FrameRenderer::~FrameRenderer() = default;

RenderedFrame FrameRenderer::render(const CameraView& view, std::uint32_t frame) {
    // The pipeline's stages, not its render(): that one times with its own queries, which would nest
    // with timeGpu's and which llvmpipe does not fill with execution time anyway.
    pipeline_.prepare(view);
    RenderedFrame out;
    out.timings.gbuffer = gl::timeGpu([&] { pipeline_.renderGBuffer(view); }).ms();
    out.timings.ao = gl::timeGpu([&] { pipeline_.runAo(view, frame); }).ms();
    out.timings.blur = gl::timeGpu([&] { pipeline_.runBlur(view); }).ms();
    out.timings.composite = gl::timeGpu([&] { pipeline_.runComposite(view); }).ms();

    const auto start = std::chrono::steady_clock::now();
    const int width = pipeline_.width(), height = pipeline_.height();
    const std::size_t pixels = std::size_t(width) * std::size_t(height);
    out.ao = Image(width, height);
    glGetTextureImage(pipeline_.aoTexture(), 0, GL_RED, GL_FLOAT, GLsizei(pixels * sizeof(float)),
                      out.ao.pixels.data());
    out.shadedRgb.resize(3 * pixels);
    glGetTextureImage(pipeline_.shadedTexture(), 0, GL_RGB, GL_FLOAT, GLsizei(out.shadedRgb.size() * sizeof(float)),
                      out.shadedRgb.data());
    out.timings.readback = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    return out;
}

Image FrameRenderer::readRawAo() const {
    Image raw(pipeline_.width(), pipeline_.height());
    glGetTextureImage(pipeline_.rawAoTexture(), 0, GL_RED, GL_FLOAT, GLsizei(raw.pixels.size() * sizeof(float)),
                      raw.pixels.data());
    return raw;
}

}  // namespace cubeao
