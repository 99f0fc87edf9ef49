#include "cubeao/bake/gpu_bvh.h"

namespace cubeao {

namespace {

// glNamedBufferStorage rejects size 0, and the BVH of an empty scene has no triangles: such a
// buffer gets one zeroed element that the traversal never reads (its root is the empty leaf).
template <class T>
gl::Buffer immutableBuffer(const std::vector<T>& items) {
    gl::Buffer buffer = gl::Buffer::create();
    const T zero{};
    const bool empty = items.empty();
    glNamedBufferStorage(buffer.id(), GLsizeiptr(empty ? sizeof(T) : items.size() * sizeof(T)),
                         empty ? &zero : items.data(), 0);
    return buffer;
}

}  // namespace

GpuBvh::GpuBvh(const Bvh& bvh)
    : nodes_(immutableBuffer(bvh.nodes)),
      triangles_(immutableBuffer(bvh.triangles)),
      nodeCount_(bvh.nodes.size()),
      triangleCount_(bvh.triangles.size()) {}

void GpuBvh::bind(GLuint nodeBinding, GLuint triangleBinding) const {
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, nodeBinding, nodes_.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, triangleBinding, triangles_.id());
}

}  // namespace cubeao
