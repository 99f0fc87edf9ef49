#include "cubeao/runtime/renderer.h"

#include <chrono>

#include "cubeao/core/error.h"
#include "cubeao/gl/timer.h"

namespace cubeao {

FrameRenderer::FrameRenderer(std::span<const glm::vec3> positions, std::span<const std::uint32_t> indices,
                             std::unique_ptr<AoPass> method, const BlurSettings& blur, const CompositeSettings& composite)
    : gbuffer_(positions, indices), method_(std::move(method)), blur_(blur), composite_(composite) {
    if (!method_) throw Error("FrameRenderer: no AO method");
}

FrameRenderer::~FrameRenderer() = default;

void FrameRenderer::resize(int width, int height) {
    if (width == width_ && height == height_) return;
    const auto texture = [&](GLenum format) {
        gl::Texture t = gl::Texture::create(GL_TEXTURE_2D);
        glTextureStorage2D(t.id(), 1, format, width, height);
        return t;
    };
    rawAo_ = texture(GL_R32F);
    ao_ = texture(GL_R32F);
    shaded_ = texture(GL_RGBA8);
    width_ = width, height_ = height;
}

RenderedFrame FrameRenderer::render(const CameraView& view, std::uint32_t frame) {
    resize(view.width, view.height);
    RenderedFrame out;
    out.timings.gbuffer = gl::timeGpu([&] { gbuffer_.render(view); }).ms();
    out.timings.ao = gl::timeGpu([&] { method_->run(gbuffer_, view, frame, rawAo_.id()); }).ms();
    out.timings.blur = gl::timeGpu([&] { blur_.run(gbuffer_, view, rawAo_.id(), ao_.id()); }).ms();
    out.timings.composite = gl::timeGpu([&] { composite_.run(gbuffer_, view, ao_.id(), shaded_.id()); }).ms();

    const auto start = std::chrono::steady_clock::now();
    const std::size_t pixels = std::size_t(width_) * std::size_t(height_);
    out.ao = Image(width_, height_);
    glGetTextureImage(ao_.id(), 0, GL_RED, GL_FLOAT, GLsizei(pixels * sizeof(float)), out.ao.pixels.data());
    out.shadedRgb.resize(3 * pixels);
    glGetTextureImage(shaded_.id(), 0, GL_RGB, GL_FLOAT, GLsizei(out.shadedRgb.size() * sizeof(float)),
                      out.shadedRgb.data());
    out.timings.readback = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    return out;
}

Image FrameRenderer::readRawAo() const {
    Image raw(width_, height_);
    glGetTextureImage(rawAo_.id(), 0, GL_RED, GL_FLOAT, GLsizei(raw.pixels.size() * sizeof(float)), raw.pixels.data());
    return raw;
}

}  // namespace cubeao
