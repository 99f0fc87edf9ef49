// A probe's distance cube on the GPU, right after its G-buffer (DESIGN.md §4 "Storage"): the
// G-buffer's distances downsampled (min filter) to depthRes and packed in the cache's depth format
// by shaders/bake/depth_encode.comp; CPU twin and the measured choice of defaults:
// src/cubeao/cache/depth_cube.h. Needs a current GL 4.5 context for its whole life.
#pragma once

#include <cstdint>
#include <vector>

#include "cubeao/cache/cache_file.h"
#include "cubeao/gl/handles.h"
#include "cubeao/gl/uniform_block.h"

namespace cubeao {

struct EncodedDepth {
    std::vector<std::uint8_t> bytes;  // the cache's distance section: 6·depthRes² texels
    float maxDistance = 0.0f;         // largest stored distance (the r16unorm scale)
};

class GpuDepthEncoder {
public:
    // Throws std::invalid_argument unless 1 ≤ depthRes ≤ res and the format is known.
    GpuDepthEncoder(int res, int depthRes, DepthFormat format);

    // Encodes a 6-layer array texture of res² (normal, distance) texels (GpuBaker's G-buffer).
    // Dispatches with the barriers later reads need; does not wait.
    void encode(GLuint gbufferTexture);
    // The result of the last encode() (waits for the GPU).
    EncodedDepth read() const;

    int depthRes() const { return depthRes_; }
    DepthFormat format() const { return format_; }

private:
    int res_ = 0, depthRes_ = 0;
    DepthFormat format_;
    std::size_t bytes_ = 0;
    gl::Program downsample_, pack_;
    gl::UniformBlock block_;  // kernel::EncodeBlock
    gl::Buffer coarse_, maxBits_, packed_;
};

}  // namespace cubeao
