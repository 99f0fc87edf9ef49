#include "cubeao/runtime/camera_gbuffer.h"

#include <glm/geometric.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <glm/vec4.hpp>

#include "cubeao/core/error.h"
#include "cubeao/gl/shader.h"

namespace cubeao {

CameraGBuffer::CameraGBuffer(std::span<const glm::vec3> positions, std::span<const std::uint32_t> indices) {
    if (indices.size() % 3 != 0) throw Error("CameraGBuffer: index count is not a multiple of 3");
    triangles_ = indices.size() / 3;
    // One geometric normal per triangle, looked up by gl_PrimitiveID (as the bake's cube G-buffer).
    std::vector<glm::vec4> normals(triangles_);
    for (std::size_t t = 0; t < triangles_; ++t) {
        const glm::vec3 a = positions[indices[3 * t]], b = positions[indices[3 * t + 1]], c = positions[indices[3 * t + 2]];
        const glm::vec3 n = glm::cross(b - a, c - a);
        const float len = glm::length(n);
        normals[t] = glm::vec4(len > 0.0f ? n / len : glm::vec3(0.0f, 1.0f, 0.0f), 0.0f);
    }
    // Zero-sized buffers are not allowed: keep one dummy element for an empty mesh.
    const auto bytes = [](std::size_t n, std::size_t size) { return GLsizeiptr(std::max<std::size_t>(n, 1) * size); };
    positions_ = gl::Buffer::create();
    glNamedBufferStorage(positions_.id(), bytes(positions.size(), sizeof(glm::vec3)), positions.empty() ? nullptr : positions.data(), 0);
    indices_ = gl::Buffer::create();
    glNamedBufferStorage(indices_.id(), bytes(indices.size(), sizeof(std::uint32_t)), indices.empty() ? nullptr : indices.data(), 0);
    triangleNormals_ = gl::Buffer::create();
    glNamedBufferStorage(triangleNormals_.id(), bytes(normals.size(), sizeof(glm::vec4)), normals.empty() ? nullptr : normals.data(), 0);
    vao_ = gl::VertexArray::create();
    glVertexArrayVertexBuffer(vao_.id(), 0, positions_.id(), 0, sizeof(glm::vec3));
    glVertexArrayAttribFormat(vao_.id(), 0, 3, GL_FLOAT, GL_FALSE, 0);
    glVertexArrayAttribBinding(vao_.id(), 0, 0);
    glEnableVertexArrayAttrib(vao_.id(), 0);
    glVertexArrayElementBuffer(vao_.id(), indices_.id());
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
    GLint oldOrigin = 0, oldDepthMode = 0, oldViewport[4];
    glGetIntegerv(GL_CLIP_ORIGIN, &oldOrigin);
    glGetIntegerv(GL_CLIP_DEPTH_MODE, &oldDepthMode);
    glGetIntegerv(GL_VIEWPORT, oldViewport);
    const GLboolean depthTest = glIsEnabled(GL_DEPTH_TEST), cull = glIsEnabled(GL_CULL_FACE);
    GLint oldDepthFunc = GL_LESS;
    glGetIntegerv(GL_DEPTH_FUNC, &oldDepthFunc);

    glClipControl(GL_UPPER_LEFT, GL_ZERO_TO_ONE);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_GREATER);
    glDisable(GL_CULL_FACE);  // architecture is open and two-sided
    glViewport(0, 0, width_, height_);
    glBindFramebuffer(GL_FRAMEBUFFER, framebuffer_.id());
    glUseProgram(program_.id());
    const glm::mat3 rotation = view.viewFromWorldRotation();
    const glm::mat4 clip = view.clipFromView();
    glProgramUniformMatrix4fv(program_.id(), glGetUniformLocation(program_.id(), "viewFromWorld"), 1, GL_FALSE,
                              glm::value_ptr(view.viewFromWorld));
    glProgramUniformMatrix4fv(program_.id(), glGetUniformLocation(program_.id(), "clipFromView"), 1, GL_FALSE,
                              glm::value_ptr(clip));
    glProgramUniformMatrix3fv(program_.id(), glGetUniformLocation(program_.id(), "viewFromWorldRotation"), 1,
                              GL_FALSE, glm::value_ptr(rotation));
    glBindVertexArray(vao_.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, triangleNormals_.id());
    if (triangles_ > 0) glDrawElements(GL_TRIANGLES, GLsizei(3 * triangles_), GL_UNSIGNED_INT, nullptr);

    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    glClipControl(GLenum(oldOrigin), GLenum(oldDepthMode));
    glDepthFunc(GLenum(oldDepthFunc));
    if (!depthTest) glDisable(GL_DEPTH_TEST);
    if (cull) glEnable(GL_CULL_FACE);
    glViewport(oldViewport[0], oldViewport[1], oldViewport[2], oldViewport[3]);
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
