// A Bvh (bvh.h) in two immutable shader storage buffers, for shaders that #include "bvh.glsl".
// Needs a current GL 4.5 context for its whole life (gl/handles.h).
#pragma once

#include <cstddef>

#include "cubeao/bake/bvh.h"
#include "cubeao/gl/handles.h"

namespace cubeao {

class GpuBvh {
public:
    explicit GpuBvh(const Bvh& bvh);

    // Binds the node and triangle arrays to these indexed GL_SHADER_STORAGE_BUFFER points: the
    // values the shader was built with for BVH_NODE_BINDING and BVH_TRIANGLE_BINDING (bvh.glsl's
    // defaults, common/bvh.h, unless it defined them).
    void bind(GLuint nodeBinding = kernel::kBvhNodeBuffer, GLuint triangleBinding = kernel::kBvhTriangleBuffer) const;

    std::size_t nodeCount() const { return nodeCount_; }
    std::size_t triangleCount() const { return triangleCount_; }
    GLuint nodeBuffer() const { return nodes_.id(); }
    GLuint triangleBuffer() const { return triangles_.id(); }

private:
    gl::Buffer nodes_, triangles_;
    std::size_t nodeCount_ = 0, triangleCount_ = 0;
};

}  // namespace cubeao
