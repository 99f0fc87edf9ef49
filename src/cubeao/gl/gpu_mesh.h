// A triangle mesh on the GPU as every raster pass here draws it: positions as vertex attribute 0,
// indices in the element buffer, and one unit geometric normal per triangle in an SSBO that the
// fragment stage indexes by gl_PrimitiveID (exact like Embree's Ng, never interpolated). Used by the
// probe bake's cube G-buffer and the run time's camera G-buffer.
#pragma once

#include <cstdint>
#include <span>

#include <glm/vec3.hpp>

#include "cubeao/gl/handles.h"

namespace cubeao::gl {

class GpuMesh {
public:
    // Three indices per triangle (cubeao::Error otherwise). Needs a current GL 4.5 context.
    GpuMesh(std::span<const glm::vec3> positions, std::span<const std::uint32_t> indices);

    // Binds the VAO and the normal table (SSBO binding `normalBinding`).
    void bind(GLuint normalBinding) const;
    // Draws every triangle with the bound program (nothing for an empty mesh).
    void draw() const;
    std::size_t triangles() const { return triangles_; }

private:
    std::size_t triangles_ = 0;
    Buffer positions_, indices_, triangleNormals_;
    VertexArray vao_;
};

}  // namespace cubeao::gl
