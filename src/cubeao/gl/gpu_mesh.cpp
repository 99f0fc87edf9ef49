#include "cubeao/gl/gpu_mesh.h"

#include <algorithm>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/vec4.hpp>

#include "cubeao/core/error.h"

namespace cubeao::gl {

GpuMesh::GpuMesh(std::span<const glm::vec3> positions, std::span<const std::uint32_t> indices) {
    if (indices.size() % 3 != 0) throw Error("GpuMesh: index count is not a multiple of 3");
    triangles_ = indices.size() / 3;
    std::vector<glm::vec4> normals(triangles_);
    for (std::size_t t = 0; t < triangles_; ++t) {
        const glm::vec3 a = positions[indices[3 * t]], b = positions[indices[3 * t + 1]], c = positions[indices[3 * t + 2]];
        const glm::vec3 n = glm::cross(b - a, c - a);
        const float len = glm::length(n);
        normals[t] = glm::vec4(len > 0.0f ? n / len : glm::vec3(0.0f, 1.0f, 0.0f), 0.0f);
    }
    // Zero-sized buffers are not allowed: keep one dummy element for an empty mesh.
    const auto storage = [](Buffer& buffer, std::size_t n, std::size_t size, const void* data) {
        buffer = Buffer::create();
        glNamedBufferStorage(buffer.id(), GLsizeiptr(std::max<std::size_t>(n, 1) * size), n ? data : nullptr, 0);
    };
    storage(positions_, positions.size(), sizeof(glm::vec3), positions.data());
    storage(indices_, indices.size(), sizeof(std::uint32_t), indices.data());
    storage(triangleNormals_, normals.size(), sizeof(glm::vec4), normals.data());
    vao_ = VertexArray::create();
    glVertexArrayVertexBuffer(vao_.id(), 0, positions_.id(), 0, sizeof(glm::vec3));
    glVertexArrayAttribFormat(vao_.id(), 0, 3, GL_FLOAT, GL_FALSE, 0);
    glVertexArrayAttribBinding(vao_.id(), 0, 0);
    glEnableVertexArrayAttrib(vao_.id(), 0);
    glVertexArrayElementBuffer(vao_.id(), indices_.id());
}

void GpuMesh::bind(GLuint normalBinding) const {
    glBindVertexArray(vao_.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, normalBinding, triangleNormals_.id());
}

void GpuMesh::draw() const {
    if (triangles_ > 0) glDrawElements(GL_TRIANGLES, GLsizei(3 * triangles_), GL_UNSIGNED_INT, nullptr);
}

}  // namespace cubeao::gl
