#include "cubeao/runtime/probe_projection.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/geometric.hpp>
#include <glm/gtc/type_ptr.hpp>

#include "common/runtime_layout.h"
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

// Location of a uniform the shader must use: a name that drifted from project.comp fails loudly.
GLint uniformLocation(GLuint program, const char* name) {
    const GLint location = glGetUniformLocation(program, name);
    if (location < 0) throw Error(std::string("runtime/project.comp: no active uniform ") + name);
    return location;
}

GLint glInteger(GLenum name) {
    GLint v = 0;
    glGetIntegerv(name, &v);
    return v;
}

}  // namespace

ProbeAtlasLayout probeAtlasLayout(std::size_t probes, int res, int maxTextureSize, int maxLayers) {
    const std::size_t perSide = std::size_t(std::max(1, maxTextureSize / std::max(res, 1)));
    const std::size_t n = std::max<std::size_t>(probes, 1);
    const std::size_t x = std::min(perSide, std::size_t(std::ceil(std::sqrt(double(n)))));
    const std::size_t y = std::min(perSide, (n + x - 1) / x);
    const std::size_t pages = (n + x * y - 1) / (x * y);
    if (6 * pages > std::size_t(std::max(maxLayers, 0)))
        throw Error(std::to_string(probes) + " probes at " + std::to_string(res) + "² per face need " +
                    std::to_string(6 * pages) + " texture layers of " + std::to_string(x * std::size_t(res)) + "×" +
                    std::to_string(y * std::size_t(res)) + "; this GL allows " + std::to_string(maxLayers) +
                    " layers of at most " + std::to_string(maxTextureSize) + "²");
    return {int(x), int(y), int(pages)};
}

ProbeProjectionPass::ProbeProjectionPass(const CacheReader& cache, std::span<const glm::vec3> meshPositions,
                                         std::span<const std::uint32_t> meshIndices, ProbeGridSettings gridSettings) {
    const CacheParams& params = cache.params();
    const std::size_t n = cache.probeCount();
    if (n == 0) throw Error("render --method probes: the cache holds no probes");
    res_ = int(params.res);
    depthRes_ = int(params.depthRes);
    atlas_ = probeAtlasLayout(n, res_, glInteger(GL_MAX_TEXTURE_SIZE), glInteger(GL_MAX_ARRAY_TEXTURE_LAYERS));
    const auto layers = GLsizei(6 * atlas_.pages);

    ao_ = gl::Texture::create(GL_TEXTURE_2D_ARRAY);
    glTextureStorage3D(ao_.id(), 1, GL_COMPRESSED_RG_RGTC2, atlas_.tilesX * res_, atlas_.tilesY * res_, layers);
    distance_ = gl::Texture::create(GL_TEXTURE_2D_ARRAY);
    glTextureStorage3D(distance_.id(), 1, depthInternalFormat(params.depthFormat), atlas_.tilesX * depthRes_,
                       atlas_.tilesY * depthRes_, layers);
    GLint unpackAlignment = 4;
    glGetIntegerv(GL_UNPACK_ALIGNMENT, &unpackAlignment);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);  // distance rows are 2 · depthRes bytes: odd depthRes is not 4-aligned

    std::vector<kernel::ProbeEntry> probeTable(n);
    std::vector<glm::vec3> positions(n);
    std::vector<std::vector<float>> distances(n);  // decoded, for the grid's visibility tests
    for (std::size_t i = 0; i < n; ++i) {
        const ProbeView p = cache.probe(i);  // checks the probe's checksum
        const int tile = int(i % std::size_t(atlas_.tilesPerPage()));
        const int tx = tile % atlas_.tilesX, ty = tile / atlas_.tilesX;
        const auto layer = GLint(6 * (i / std::size_t(atlas_.tilesPerPage())));
        glCompressedTextureSubImage3D(ao_.id(), 0, tx * res_, ty * res_, layer, res_, res_, 6, GL_COMPRESSED_RG_RGTC2,
                                      GLsizei(p.aoConfidence.size()), p.aoConfidence.data());
        glTextureSubImage3D(distance_.id(), 0, tx * depthRes_, ty * depthRes_, layer, depthRes_, depthRes_, 6, GL_RED,
                            depthType(params.depthFormat), p.depth.data());
        const float scale = params.depthFormat == DepthFormat::R16Unorm ? p.maxDistance : 1.0f;
        probeTable[i] = {p.position, scale};
        positions[i] = p.position;
        if (!depth::decode(p.depth, depthRes_, params.depthFormat, p.maxDistance, distances[i]))
            throw Error("probe " + std::to_string(p.index) + ": distance cube has the wrong size");
    }
    glPixelStorei(GL_UNPACK_ALIGNMENT, unpackAlignment);
    // The grid ranks probes per cell as the pass will, less the confidence (projection.h).
    const ProjectSettings project = resolveProjectSettings({});
    const auto quality = [&](std::uint32_t probe, const SurfacePoint& x) {
        const DecodedProbe view{positions[probe], res_, {}, {}, depthRes_, distances[probe]};
        const double area = visibleFootprint(view, x.position, x.normal, project);
        return area > 0.0 ? 1.0 / area : 0.0;  // 1 / inf = 0: not seen
    };
    if (gridSettings.cellSize == 0.0f) gridSettings.cellSize = params.radius;
    glm::vec3 boundsMin(std::numeric_limits<float>::max()), boundsMax(-std::numeric_limits<float>::max());
    for (const glm::vec3& v : meshPositions) boundsMin = glm::min(boundsMin, v), boundsMax = glm::max(boundsMax, v);
    const std::vector<SurfacePoint> points = sampleSurface(meshPositions, meshIndices, gridSettings.cellSize / 8.0f);
    grid_ = std::make_unique<ProbeGrid>(boundsMin, boundsMax, positions, points, quality, gridSettings);
    candidates_ = grid_->k();

    probes_ = gl::Buffer::create();
    glNamedBufferStorage(probes_.id(), GLsizeiptr(probeTable.size() * sizeof(kernel::ProbeEntry)), probeTable.data(), 0);
    cells_ = gl::Buffer::create();
    glNamedBufferStorage(cells_.id(), GLsizeiptr(grid_->table().size() * sizeof(std::uint32_t)), grid_->table().data(), 0);
    counters_ = gl::Buffer::create();
    glNamedBufferStorage(counters_.id(), sizeof(kernel::PassCounters), nullptr, GL_DYNAMIC_STORAGE_BIT);
    const std::size_t faceTiles = std::size_t(6 * atlas_.pages) * std::size_t(atlas_.tilesPerPage());
    gpuBytes_ = faceTiles * std::size_t(res_ * res_) /* BC5: 1 byte per texel */ +
                faceTiles * std::size_t(depthRes_ * depthRes_) * depthBytesPerTexel(params.depthFormat) +
                probeTable.size() * sizeof(kernel::ProbeEntry) + grid_->table().size() * sizeof(std::uint32_t);

    program_ = gl::compileComputeProgram("runtime/project.comp");
    const GLuint p = program_.id();
    glProgramUniform3fv(p, uniformLocation(p, "gridOrigin"), 1, glm::value_ptr(grid_->origin()));
    glProgramUniform1f(p, uniformLocation(p, "cellSize"), grid_->cellSize());
    glProgramUniform3iv(p, uniformLocation(p, "gridDims"), 1, glm::value_ptr(grid_->dims()));
    glProgramUniform1i(p, uniformLocation(p, "candidatesPerCell"), candidates_);
    glProgramUniform1i(p, uniformLocation(p, "tilesX"), atlas_.tilesX);
    glProgramUniform1i(p, uniformLocation(p, "tilesPerPage"), atlas_.tilesPerPage());
    // kernel::ProjectionParams, member by member (a plain uniform struct has no buffer layout).
    glProgramUniform1f(p, uniformLocation(p, "params.depthTolerance"), project.depthTolerance);
    glProgramUniform1f(p, uniformLocation(p, "params.depthSlope"), project.depthSlope);
    glProgramUniform1f(p, uniformLocation(p, "params.minFacing"), project.minFacing);
    glProgramUniform1i(p, uniformLocation(p, "params.res"), res_);
    glProgramUniform1i(p, uniformLocation(p, "params.depthRes"), depthRes_);
}

ProbeProjectionPass::~ProbeProjectionPass() = default;

void ProbeProjectionPass::run(const CameraGBuffer& gbuffer, const CameraView& view, std::uint32_t, GLuint aoImage) {
    const GLuint p = program_.id();
    const kernel::PassCounters zero{};
    glNamedBufferSubData(counters_.id(), 0, sizeof zero, &zero);
    glProgramUniform2i(p, uniformLocation(p, "frameSize"), gbuffer.width(), gbuffer.height());
    glProgramUniform1f(p, uniformLocation(p, "tanHalfFovY"), view.tanHalfFovY);
    const glm::mat4 worldFromView = view.worldFromView();
    glProgramUniformMatrix4fv(p, uniformLocation(p, "worldFromView"), 1, GL_FALSE, glm::value_ptr(worldFromView));
    glUseProgram(p);
    glBindTextureUnit(kernel::kGBufferDepthUnit, gbuffer.depthTexture());
    glBindTextureUnit(kernel::kGBufferNormalUnit, gbuffer.normalTexture());
    glBindTextureUnit(kernel::kProbeAoUnit, ao_.id());
    glBindTextureUnit(kernel::kProbeDistanceUnit, distance_.id());
    glBindImageTexture(kernel::kAoImageUnit, aoImage, 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_R32F);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kernel::kPassCountersBuffer, counters_.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kernel::kProbeTableBuffer, probes_.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kernel::kCandidateBuffer, cells_.id());
    glDispatchCompute(kernel::pixelGroups(gbuffer.width()), kernel::pixelGroups(gbuffer.height()), 1);
    glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
    pixels_ = double(gbuffer.width()) * double(gbuffer.height());
}

namespace {

kernel::PassCounters readCounters(const gl::Buffer& buffer) {
    kernel::PassCounters c{};
    glGetNamedBufferSubData(buffer.id(), 0, sizeof c, &c);
    return c;
}

}  // namespace

double ProbeProjectionPass::fetchesPerPixel() const {
    if (pixels_ == 0.0) return 0.0;
    const kernel::PassCounters c = readCounters(counters_);
    return double(kernel::joinWords(c.fetchesLow, c.fetchesHigh)) / pixels_;
}

double ProbeProjectionPass::uncoveredFraction() const {
    if (pixels_ == 0.0) return 0.0;
    return double(readCounters(counters_).uncovered) / pixels_;
}

}  // namespace cubeao
