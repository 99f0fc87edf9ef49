#include "cubeao/bake/gpu_bc5.h"

#include "common/bake_layout.h"
#include "cubeao/cache/bc4.h"
#include "cubeao/gl/shader.h"

namespace cubeao {

namespace {

// Binding points and group size of bc5_encode.comp and bc5_error.comp (common/bake_layout.h): the
// input is where ao_horizon.comp writes.
using kernel::kBakeAoBuffer, kernel::kBakeBlocksBuffer, kernel::kBakeErrorTilesBuffer, kernel::kBakeGBufferUnit;

GLuint groups(int n) { return kernel::bakeGroups(std::size_t(n), kernel::kBakeTileSize); }

}  // namespace

GpuBc5Encoder::GpuBc5Encoder(int res)
    : res_(res),
      size_(bc::bc5Size(res)),  // checks res before any GL work
      program_(gl::compileComputeProgram("bake/bc5_encode.comp")),
      errorProgram_(gl::compileComputeProgram("bake/bc5_error.comp")),
      blocks_(gl::Buffer::create()),
      partial_(gl::Buffer::create()) {
    glNamedBufferStorage(blocks_.id(), GLsizeiptr(size_), nullptr, 0);
    const GLuint tiles = groups(res / bc::kBlockSize);
    glNamedBufferStorage(partial_.id(), GLsizeiptr(std::size_t(6) * tiles * tiles * sizeof(float) * 2), nullptr, 0);
    block_ = gl::UniformBlock::create(kernel::EncodeBlock{res, 0, 0});  // both programs read res alone
}

void GpuBc5Encoder::encode(GLuint aoConfidenceBuffer) {
    const int blocksPerSide = res_ / bc::kBlockSize;
    glUseProgram(program_.id());
    block_.bind(kernel::kEncodeBlock);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kBakeAoBuffer, aoConfidenceBuffer);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kBakeBlocksBuffer, blocks_.id());
    glDispatchCompute(groups(2 * blocksPerSide), groups(blocksPerSide), 6);  // x: 2·bx + channel
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT | GL_PIXEL_BUFFER_BARRIER_BIT);
}

GpuBc5Encoder::AoError GpuBc5Encoder::aoError(GLuint aoConfidenceBuffer, GLuint gbufferTexture) const {
    dispatchAoError(aoConfidenceBuffer, gbufferTexture);
    return readAoError();
}

void GpuBc5Encoder::dispatchAoError(GLuint aoConfidenceBuffer, GLuint gbufferTexture) const {
    const GLuint tiles = groups(res_ / bc::kBlockSize);
    glUseProgram(errorProgram_.id());
    block_.bind(kernel::kEncodeBlock);
    glBindTextureUnit(kBakeGBufferUnit, gbufferTexture);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kBakeAoBuffer, aoConfidenceBuffer);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kBakeBlocksBuffer, blocks_.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kBakeErrorTilesBuffer, partial_.id());
    glDispatchCompute(tiles, tiles, 6);
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
}

GpuBc5Encoder::AoError GpuBc5Encoder::readAoError() const {
    const GLuint tiles = groups(res_ / bc::kBlockSize);
    std::vector<float> partial(std::size_t(6) * tiles * tiles * 2);
    glGetNamedBufferSubData(partial_.id(), 0, GLsizeiptr(partial.size() * sizeof(float)), partial.data());
    AoError e;
    for (std::size_t t = 0; t < partial.size(); t += 2) {  // tile sums are small: float is exact enough
        e.squaredError += double(partial[t]);
        e.texels += std::uint64_t(partial[t + 1]);  // ≤ 1024 per tile: exact in float
    }
    return e;
}

std::vector<std::uint8_t> GpuBc5Encoder::read() const {
    std::vector<std::uint8_t> out(size_);
    glGetNamedBufferSubData(blocks_.id(), 0, GLsizeiptr(out.size()), out.data());
    return out;
}

}  // namespace cubeao
