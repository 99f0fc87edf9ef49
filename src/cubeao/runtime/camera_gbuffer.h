// The camera G-buffer (DESIGN.md §4 "Projection"): what every run-time AO method reads. One raster
// pass of the whole mesh per frame writes, per pixel (x, y) on PinholeCamera::rayDirection(x, y):
//   depth  (R32F)    view depth z along −view.z of the nearest surface; 0 = no geometry there
//   normal (RGBA32F) the triangle's geometric normal in VIEW space, turned to face the camera (xyz),
//                    from a per-triangle table (exact like Embree's Ng, never interpolated); w = 0
// Texel (x, y) is image pixel (x, y) with row 0 at the top (camera_view.h), so read-backs and AO
// images need no flip. View space rather than world space: the screen-space estimators and the
// blur all work relative to the camera, and view-space positions are exact to rounding near the
// camera whatever the scene's world coordinates.
// Textures are reallocated only when the frame size changes, so one CameraGBuffer serves a walk.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

#include "cubeao/gl/gpu_mesh.h"
#include "cubeao/gl/handles.h"
#include "cubeao/gl/uniform_block.h"
#include "cubeao/runtime/camera_view.h"

namespace cubeao {

// A read-back of the G-buffer (tests, CPU twins): row-major, row 0 at the top.
struct CameraGBufferImage {
    int width = 0, height = 0;
    std::vector<float> depth;       // view depth; 0 = no geometry
    std::vector<glm::vec3> normal;  // view space, facing the camera; (0, 0, 0) where depth is 0

    std::size_t index(int x, int y) const { return std::size_t(y) * std::size_t(width) + std::size_t(x); }
    bool empty(int x, int y) const { return !(depth[index(x, y)] > 0.0f); }
};

class CameraGBuffer {
public:
    // Uploads the mesh (three indices per triangle). Needs a current GL 4.5 context.
    CameraGBuffer(std::span<const glm::vec3> positions, std::span<const std::uint32_t> indices);
    ~CameraGBuffer();
    CameraGBuffer(const CameraGBuffer&) = delete;
    CameraGBuffer& operator=(const CameraGBuffer&) = delete;

    // Renders the frame `view` (its width × height; textures follow the size). Leaves GL state as
    // it found it apart from the bound program, VAO and SSBO binding 0.
    void render(const CameraView& view);

    int width() const { return width_; }
    int height() const { return height_; }
    GLuint depthTexture() const { return depth_.id(); }
    GLuint normalTexture() const { return normal_.id(); }
    CameraGBufferImage readBack() const;

private:
    void resize(int width, int height);

    gl::GpuMesh mesh_;
    gl::Program program_;
    gl::UniformBlock block_;  // kernel::GBufferBlock, per frame
    gl::Texture depth_, normal_;
    gl::Renderbuffer zBuffer_;
    gl::Framebuffer framebuffer_;
    int width_ = 0, height_ = 0;
};

}  // namespace cubeao
