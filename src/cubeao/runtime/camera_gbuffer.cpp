#include "cubeao/runtime/camera_gbuffer.h"

#include <glm/geometric.hpp>
#include <glm/vec4.hpp>

#include "common/runtime_layout.h"
#include "cubeao/core/error.h"
#include "cubeao/gl/shader.h"
#include "cubeao/gl/state.h"

namespace cubeao {

CameraGBuffer::CameraGBuffer(std::span<const glm::vec3> positions, std::span<const std::uint32_t> indices)
    : mesh_(positions, indices) {
    program_ = gl::compileRenderProgram("runtime/gbuffer.vert", "runtime/gbuffer.frag");
}

CameraGBuffer::~CameraGBuffer() = default;

void CameraGBuffer::resize(int width, int height) {
    if (width == width_ && height == height_) return;
    if (width < 1 || height < 1) throw Error("CameraGBuffer: frame size must be positive");
    width_ = width, height_ = height;
    depth_ = gl::Texture::create(GL_TEXTURE_2D);
    glTextureStorage2D(depth_.id(), 1, GL_R32F, width, height);
    normal_ = gl::Texture::create(GL_TEXTURE_2D);
    glTextureStorage2D(normal_.id(), 1, GL_RGBA32F, width, height);
    zBuffer_ = gl::Renderbuffer::create();
    glNamedRenderbufferStorage(zBuffer_.id(), GL_DEPTH_COMPONENT32F, width, height);
    framebuffer_ = gl::Framebuffer::create();
    glNamedFramebufferTexture(framebuffer_.id(), GL_COLOR_ATTACHMENT0, depth_.id(), 0);
    glNamedFramebufferTexture(framebuffer_.id(), GL_COLOR_ATTACHMENT1, normal_.id(), 0);
    glNamedFramebufferRenderbuffer(framebuffer_.id(), GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, zBuffer_.id());
    const GLenum drawBuffers[2] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1};
    glNamedFramebufferDrawBuffers(framebuffer_.id(), 2, drawBuffers);
    if (glCheckNamedFramebufferStatus(framebuffer_.id(), GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
        throw Error("CameraGBuffer: framebuffer (R32F + RGBA32F + 32F depth) is incomplete on this GL");
}

void CameraGBuffer::render(const CameraView& view) {
    resize(view.width, view.height);
    const GLfloat zero[4] = {0.0f, 0.0f, 0.0f, 0.0f}, clearDepth = 0.0f;  // depth 0 = no geometry
    glClearNamedFramebufferfv(framebuffer_.id(), GL_COLOR, 0, zero);
    glClearNamedFramebufferfv(framebuffer_.id(), GL_COLOR, 1, zero);
    glClearNamedFramebufferfv(framebuffer_.id(), GL_DEPTH, 0, &clearDepth);

    // UPPER_LEFT: NDC y = +1 lands in texel row 0, so the texture is stored top row first like the
    // images; ZERO_TO_ONE + GL_GREATER: reversed-Z (camera_view.h clipFromView).
    {
        const gl::SavedState saved;  // the caller's frame sees none of this
        glClipControl(GL_UPPER_LEFT, GL_ZERO_TO_ONE);
        glEnable(GL_DEPTH_TEST);
        glDepthFunc(GL_GREATER);
        glDisable(GL_CULL_FACE);  // architecture is open and two-sided
        glDisable(GL_BLEND);
        glViewport(0, 0, width_, height_);
        glBindFramebuffer(GL_FRAMEBUFFER, framebuffer_.id());
        glUseProgram(program_.id());
        block_.upload(kernel::GBufferBlock{view.viewFromWorld, view.clipFromView()}, kernel::kGBufferBlock);
        mesh_.bind(kernel::kTriangleNormalsBuffer);
        mesh_.draw();
    }
    glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
}

CameraGBufferImage CameraGBuffer::readBack() const {
    CameraGBufferImage out;
    out.width = width_, out.height = height_;
    const std::size_t n = std::size_t(width_) * std::size_t(height_);
    out.depth.resize(n);
    std::vector<glm::vec4> normals(n);
    glGetTextureImage(depth_.id(), 0, GL_RED, GL_FLOAT, GLsizei(n * sizeof(float)), out.depth.data());
    glGetTextureImage(normal_.id(), 0, GL_RGBA, GL_FLOAT, GLsizei(n * sizeof(glm::vec4)), normals.data());
    out.normal.resize(n);
    for (std::size_t i = 0; i < n; ++i) out.normal[i] = glm::vec3(normals[i]);
    return out;
}

}  // namespace cubeao
