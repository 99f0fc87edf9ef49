#include "cubeao/bake/gpu_bc5.h"

#include "cubeao/cache/bc4.h"
#include "cubeao/gl/shader.h"

namespace cubeao {

namespace {

// Binding points of shaders/bake/bc5_encode.comp: the input is where ao_horizon.comp writes.
constexpr GLuint kAoConfidenceBinding = 1, kBlocksBinding = 3;
constexpr GLuint kGroupSize = 8;  // local_size_x and local_size_y

GLuint groups(int n) { return (GLuint(n) + kGroupSize - 1) / kGroupSize; }

}  // namespace

GpuBc5Encoder::GpuBc5Encoder(int res)
    : res_(res),
      size_(bc::bc5Size(res)),  // checks res before any GL work
      program_(gl::compileComputeProgram("bake/bc5_encode.comp")),
      blocks_(gl::Buffer::create()) {
    glNamedBufferStorage(blocks_.id(), GLsizeiptr(size_), nullptr, 0);
    glProgramUniform1i(program_.id(), glGetUniformLocation(program_.id(), "res"), res);
}

void GpuBc5Encoder::encode(GLuint aoConfidenceBuffer) {
    const int blocksPerSide = res_ / bc::kBlockSize;
    glUseProgram(program_.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kAoConfidenceBinding, aoConfidenceBuffer);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kBlocksBinding, blocks_.id());
    glDispatchCompute(groups(2 * blocksPerSide), groups(blocksPerSide), 6);  // x: 2·bx + channel
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT | GL_PIXEL_BUFFER_BARRIER_BIT);
}

std::vector<std::uint8_t> GpuBc5Encoder::read() const {
    std::vector<std::uint8_t> out(size_);
    glGetNamedBufferSubData(blocks_.id(), 0, GLsizeiptr(out.size()), out.data());
    return out;
}

}  // namespace cubeao
