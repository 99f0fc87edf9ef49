#include "cubeao/bake/gpu_depth.h"

#include <bit>
#include <stdexcept>
#include <string>

#include "common/bake_layout.h"
#include "cubeao/gl/shader.h"

namespace cubeao {
namespace {

// Binding points and group sizes of shaders/bake/depth_encode.comp (common/bake_layout.h): PASS 0
// runs kBakeTileSize² per group, PASS 1 kBakeListGroupSize.
using kernel::kBakeGBufferUnit, kernel::kBakeCoarseBuffer, kernel::kBakeMaxDistanceBuffer, kernel::kBakeDepthWordsBuffer;
using kernel::bakeGroups, kernel::kBakeTileSize, kernel::kBakeListGroupSize;

int checked(int res, int depthRes, DepthFormat format) {
    if (res < 1 || depthRes < 1 || depthRes > res || depthBytesPerTexel(format) == 0)
        throw std::invalid_argument("GpuDepthEncoder: depthRes " + std::to_string(depthRes) + " not in 1.." +
                                    std::to_string(res) + ", or an unknown depth format");
    return depthRes;
}

}  // namespace

GpuDepthEncoder::GpuDepthEncoder(int res, int depthRes, DepthFormat format)
    : res_(res),
      depthRes_(checked(res, depthRes, format)),
      format_(format),
      bytes_(std::size_t(6) * std::size_t(depthRes) * std::size_t(depthRes) * depthBytesPerTexel(format)),
      downsample_(gl::compileComputeProgram("bake/depth_encode.comp", {{"PASS", "0"}})),
      pack_(gl::compileComputeProgram("bake/depth_encode.comp", {{"PASS", "1"}})),
      coarse_(gl::Buffer::create()),
      maxBits_(gl::Buffer::create()),
      packed_(gl::Buffer::create()) {
    const std::size_t texels = std::size_t(6) * std::size_t(depthRes) * std::size_t(depthRes);
    glNamedBufferStorage(coarse_.id(), GLsizeiptr(texels * sizeof(float)), nullptr, 0);
    glNamedBufferStorage(maxBits_.id(), sizeof(std::uint32_t), nullptr, GL_DYNAMIC_STORAGE_BIT);
    glNamedBufferStorage(packed_.id(), GLsizeiptr(bytes_), nullptr, 0);  // bytes_ is a multiple of 4
    block_ = gl::UniformBlock::create(kernel::EncodeBlock{res, depthRes, int(format)});  // both passes'
}

void GpuDepthEncoder::encode(GLuint gbufferTexture) {
    const std::uint32_t zero = 0;
    glNamedBufferSubData(maxBits_.id(), 0, sizeof zero, &zero);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kBakeCoarseBuffer, coarse_.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kBakeMaxDistanceBuffer, maxBits_.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kBakeDepthWordsBuffer, packed_.id());
    block_.bind(kernel::kEncodeBlock);
    glUseProgram(downsample_.id());
    glBindTextureUnit(kBakeGBufferUnit, gbufferTexture);
    glDispatchCompute(bakeGroups(std::size_t(depthRes_), kBakeTileSize), bakeGroups(std::size_t(depthRes_), kBakeTileSize), 6);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
    glUseProgram(pack_.id());
    const std::size_t words = bytes_ / 4;
    glDispatchCompute(bakeGroups(words, kBakeListGroupSize), 1, 1);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
}

EncodedDepth GpuDepthEncoder::read() const {
    EncodedDepth out;
    out.bytes.resize(bytes_);
    glGetNamedBufferSubData(packed_.id(), 0, GLsizeiptr(bytes_), out.bytes.data());
    std::uint32_t bits = 0;
    glGetNamedBufferSubData(maxBits_.id(), 0, sizeof bits, &bits);
    out.maxDistance = std::bit_cast<float>(bits);
    return out;
}

}  // namespace cubeao
