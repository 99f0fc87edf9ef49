#include "cubeao/runtime/probe_projection.h"

#include <glm/geometric.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <glm/vec4.hpp>

#include "cubeao/bake/cube.h"
#include "cubeao/cache/depth_cube.h"
#include "cubeao/core/error.h"
#include "cubeao/gl/shader.h"

namespace cubeao {
namespace {

GLenum depthInternalFormat(DepthFormat f) {
    return f == DepthFormat::R16Unorm ? GL_R16 : f == DepthFormat::R16Float ? GL_R16F : GL_R32F;
}
GLenum depthType(DepthFormat f) {
    return f == DepthFormat::R16Unorm ? GL_UNSIGNED_SHORT : f == DepthFormat::R16Float ? GL_HALF_FLOAT : GL_FLOAT;
}

}  // namespace

ProbeProjectionPass::ProbeProjectionPass(const CacheReader& cache, const glm::vec3& boundsMin,
                                         const glm::vec3& boundsMax, ProbeGridSettings gridSettings) {
    const CacheParams& params = cache.params();
    const std::size_t n = cache.probeCount();
    if (n == 0) throw Error("render --method probes: the cache holds no probes");
    res_ = int(params.res);
    depthRes_ = int(params.depthRes);
    const auto layers = GLsizei(6 * n);

    ao_ = gl::Texture::create(GL_TEXTURE_2D_ARRAY);
    glTextureStorage3D(ao_.id(), 1, GL_COMPRESSED_RG_RGTC2, res_, res_, layers);
    distance_ = gl::Texture::create(GL_TEXTURE_2D_ARRAY);
    glTextureStorage3D(distance_.id(), 1, depthInternalFormat(params.depthFormat), depthRes_, depthRes_, layers);

    std::vector<glm::vec4> probeTable(n);
    std::vector<glm::vec3> positions(n);
    std::vector<std::vector<float>> distances(n);  // decoded, for the grid's visibility tests
    for (std::size_t i = 0; i < n; ++i) {
        const ProbeView p = cache.probe(i);  // checks the probe's checksum
        glCompressedTextureSubImage3D(ao_.id(), 0, 0, 0, GLint(6 * i), res_, res_, 6, GL_COMPRESSED_RG_RGTC2,
                                      GLsizei(p.aoConfidence.size()), p.aoConfidence.data());
        glTextureSubImage3D(distance_.id(), 0, 0, 0, GLint(6 * i), depthRes_, depthRes_, 6, GL_RED,
                            depthType(params.depthFormat), p.depth.data());
        const float scale = params.depthFormat == DepthFormat::R16Unorm ? p.maxDistance : 1.0f;
        probeTable[i] = glm::vec4(p.position, scale);
        positions[i] = p.position;
        if (!depth::decode(p.depth, depthRes_, params.depthFormat, p.maxDistance, distances[i]))
            throw Error("probe " + std::to_string(p.index) + ": distance cube has the wrong size");
    }
    // A probe sees a free-space point when its distance cube reaches at least that far in its
    // direction (or saw nothing there at all).
    const auto sees = [&](std::uint32_t probe, const glm::vec3& point) {
        const glm::vec3 d = point - positions[probe];
        const float stored = distances[probe][cube::texelIndex(d, depthRes_)];
        return !(stored > 0.0f) || glm::length(d) <= stored * (1.0f + depth::kDepthTolerance);
    };
    if (gridSettings.cellSize == 0.0f) gridSettings.cellSize = params.radius;
    grid_ = std::make_unique<ProbeGrid>(boundsMin, boundsMax, positions, sees, gridSettings);
    candidates_ = grid_->k();

    probes_ = gl::Buffer::create();
    glNamedBufferStorage(probes_.id(), GLsizeiptr(probeTable.size() * sizeof(glm::vec4)), probeTable.data(), 0);
    cells_ = gl::Buffer::create();
    glNamedBufferStorage(cells_.id(), GLsizeiptr(grid_->table().size() * sizeof(std::uint32_t)), grid_->table().data(), 0);
    counters_ = gl::Buffer::create();
    glNamedBufferStorage(counters_.id(), 3 * sizeof(std::uint32_t), nullptr, GL_DYNAMIC_STORAGE_BIT);

    program_ = gl::compileComputeProgram("runtime/project.comp");
    const GLuint p = program_.id();
    glProgramUniform3fv(p, glGetUniformLocation(p, "gridOrigin"), 1, glm::value_ptr(grid_->origin()));
    glProgramUniform1f(p, glGetUniformLocation(p, "cellSize"), grid_->cellSize());
    glProgramUniform3iv(p, glGetUniformLocation(p, "gridDims"), 1, glm::value_ptr(grid_->dims()));
    glProgramUniform1i(p, glGetUniformLocation(p, "candidatesPerCell"), candidates_);
    glProgramUniform1i(p, glGetUniformLocation(p, "res"), res_);
    glProgramUniform1i(p, glGetUniformLocation(p, "depthRes"), depthRes_);
    const ProjectSettings project = resolveProjectSettings({});
    glProgramUniform1f(p, glGetUniformLocation(p, "depthTolerance"), project.depthTolerance);
    glProgramUniform1f(p, glGetUniformLocation(p, "depthSlope"), project.depthSlope);
    glProgramUniform1f(p, glGetUniformLocation(p, "minFacing"), project.minFacing);
}

ProbeProjectionPass::~ProbeProjectionPass() = default;

void ProbeProjectionPass::run(const CameraGBuffer& gbuffer, const CameraView& view, std::uint32_t, GLuint aoImage) {
    const GLuint p = program_.id();
    const std::uint32_t zero[3] = {0u, 0u, 0u};
    glNamedBufferSubData(counters_.id(), 0, sizeof zero, zero);
    glProgramUniform2i(p, glGetUniformLocation(p, "frameSize"), gbuffer.width(), gbuffer.height());
    glProgramUniform1f(p, glGetUniformLocation(p, "tanHalfFovY"), view.tanHalfFovY);
    const glm::mat4 worldFromView = view.worldFromView();
    glProgramUniformMatrix4fv(p, glGetUniformLocation(p, "worldFromView"), 1, GL_FALSE, glm::value_ptr(worldFromView));
    glUseProgram(p);
    glBindTextureUnit(0, gbuffer.depthTexture());
    glBindTextureUnit(1, gbuffer.normalTexture());
    glBindTextureUnit(2, ao_.id());
    glBindTextureUnit(3, distance_.id());
    glBindImageTexture(0, aoImage, 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_R32F);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 4, counters_.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 5, probes_.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 6, cells_.id());
    glDispatchCompute(GLuint((gbuffer.width() + 7) / 8), GLuint((gbuffer.height() + 7) / 8), 1);
    glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
    pixels_ = double(gbuffer.width()) * double(gbuffer.height());
}

double ProbeProjectionPass::fetchesPerPixel() const {
    if (pixels_ == 0.0) return 0.0;
    std::uint32_t words[3] = {0u, 0u, 0u};
    glGetNamedBufferSubData(counters_.id(), 0, sizeof words, words);
    return double(std::uint64_t(words[2]) << 32 | words[1]) / pixels_;
}

double ProbeProjectionPass::uncoveredFraction() const {
    if (pixels_ == 0.0) return 0.0;
    std::uint32_t uncovered = 0;
    glGetNamedBufferSubData(counters_.id(), 0, sizeof uncovered, &uncovered);
    return double(uncovered) / pixels_;
}

}  // namespace cubeao
