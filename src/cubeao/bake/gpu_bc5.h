// BC5 compression of a baked probe on the GPU, right after the AO pass: (AO, confidence) per texel
// in a shader storage buffer → BC5 blocks in another (shaders/bake/bc5_encode.comp; format and
// block order in src/cubeao/cache/bc4.h, whose CPU encoder gives the same bytes).
// Needs a current GL 4.5 context for its whole life (gl/handles.h).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "cubeao/gl/handles.h"
#include "cubeao/gl/uniform_block.h"

namespace cubeao {

class GpuBc5Encoder {
public:
    // Compiles the program and allocates the block buffer (bc::bc5Size(res) bytes). Throws
    // std::invalid_argument unless res is a multiple of 4 in [4, bc::kMaxRes].
    explicit GpuBc5Encoder(int res);

    // Encodes the 6·res² vec2 (AO, confidence) of aoConfidenceBuffer (cube::texelIndex order, the
    // layout of ao_horizon.comp's output) into blocks(). Dispatches and inserts the barrier that
    // makes the result visible to buffer reads and later shaders; does not wait.
    void encode(GLuint aoConfidenceBuffer);

    // The blocks of the last encode(), bc::bc5Size(res) bytes (waits for the GPU).
    std::vector<std::uint8_t> read() const;

    // What the last encode() cost the AO (red) channel against aoConfidenceBuffer, over the texels
    // whose distance in gbufferTexture (6-layer res² array, distance in w) is > 0, measured on the
    // GPU (shaders/bake/bc5_error.comp) so the uncompressed AO never has to be read back. Waits.
    struct AoError {
        double squaredError = 0.0;  // Σ (decoded − AO)²
        std::uint64_t texels = 0;   // surface texels summed over
    };
    AoError aoError(GLuint aoConfidenceBuffer, GLuint gbufferTexture) const;
    // aoError() in two halves, for a caller that must not wait (GpuBaker::step): the dispatch, with
    // the barrier buffer reads need, then the read of its per-tile sums (waits unless a fence issued
    // after the dispatch has signalled). aoError() is the two in a row.
    void dispatchAoError(GLuint aoConfidenceBuffer, GLuint gbufferTexture) const;
    AoError readAoError() const;

    GLuint blocks() const { return blocks_.id(); }
    int res() const { return res_; }

private:
    int res_ = 0;
    std::size_t size_ = 0;  // bytes of blocks_
    gl::Program program_, errorProgram_;
    gl::UniformBlock block_;  // kernel::EncodeBlock
    gl::Buffer blocks_, partial_;  // partial_: (Σ error², texels) per 8×8 tile of blocks
};

}  // namespace cubeao
