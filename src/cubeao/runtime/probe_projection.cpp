#include "cubeao/runtime/probe_projection.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/geometric.hpp>
#include <spdlog/spdlog.h>

#include "common/projection.h"
#include "common/runtime_layout.h"
#include "cubeao/core/cube.h"
#include "cubeao/core/error.h"
#include "cubeao/gl/shader.h"

namespace cubeao {
namespace {

// Page hints are per probe: the grid reads a probe's distance section alone (one read of its pages,
// asked for when it first touches the probe), and the probes it has read are released in batches so
// that building over a cache of any size keeps the RSS bounded.
class TouchedProbes {
public:
    explicit TouchedProbes(const ProbeSource& source) : source_(source), mark_(source.size(), false) {}
    ~TouchedProbes() { releaseAll(); }
    void touch(std::uint32_t id) {
        if (id >= mark_.size() || mark_[id]) return;
        source_.prefetchDepth(ProbeId{id});  // the texels the grid reads come from this section alone
        mark_[id] = true;
        ids_.push_back(id);
        if (ids_.size() >= 256) releaseAll();
    }
    void releaseAll() {
        for (std::uint32_t id : ids_) mark_[id] = false;
        ids_.clear();
        source_.releaseAll();  // per-probe release leaves the neighbours' pages the kernel mapped too
    }

private:
    const ProbeSource& source_;
    std::vector<bool> mark_;
    std::vector<std::uint32_t> ids_;
};

// Cells `cells` (ascending) of a table of k entries per cell into `buffer`: runs of consecutive
// cells, one write each.
void uploadCells(GLuint buffer, const std::vector<std::uint32_t>& table, std::size_t k,
                 std::span<const std::size_t> cells) {
    for (std::size_t i = 0; i < cells.size();) {
        std::size_t j = i + 1;
        while (j < cells.size() && cells[j] == cells[j - 1] + 1) ++j;
        glNamedBufferSubData(buffer, GLintptr(cells[i] * k * sizeof(std::uint32_t)),
                             GLsizeiptr((cells[j - 1] - cells[i] + 1) * k * sizeof(std::uint32_t)),
                             table.data() + cells[i] * k);
        i = j;
    }
}

}  // namespace

// project.comp declares the coarse tier's samplers only for a residency that has one (PROJECT_COARSE_TIER):
// without, every probe is read at level 0 and the shader is the one before the tier, two sampler units
// fewer (with them, LeakSanitizer's tracer crashed at exit in a sanitized `cubeao render` that filled
// pixels with GTAO: docs/RELIABILITY.md).
gl::ShaderDefines ProbeProjectionPass::projectDefines() const {
    gl::ShaderDefines defines;
    if (residency_->coarseLevel() > 0) defines.push_back({"PROJECT_COARSE_TIER", "1"});
    return defines;
}

namespace {

// The cache of a pass, refused before any work when it holds no probe.
const CacheReader& nonEmpty(const CacheReader& cache) {
    if (cache.probeCount() == 0) throw Error("render --method probes: the cache holds no probes");
    return cache;
}

}  // namespace

ProbeProjectionPass::ProbeProjectionPass(const CacheReader& cache, std::span<const glm::vec3> positions,
                                         std::span<const std::uint32_t> indices,
                                         const ProbeProjectionSettings& settings)
    : ProbeProjectionPass(&nonEmpty(cache),
                          withAoFormat(cache.params(), settings.aoFormat.value_or(cache.params().aoFormat)), positions,
                          indices, settings, cache.probeCount()) {}

ProbeProjectionPass::ProbeProjectionPass(const CacheParams& params, std::span<const glm::vec3> positions,
                                         std::span<const std::uint32_t> indices,
                                         const ProbeProjectionSettings& settings, std::size_t expectedProbes)
    : ProbeProjectionPass(nullptr, params, positions, indices, settings, expectedProbes) {}

ProbeProjectionPass::ProbeProjectionPass(const CacheReader* cache, const CacheParams& params,
                                         std::span<const glm::vec3> meshPositions,
                                         std::span<const std::uint32_t> meshIndices,
                                         const ProbeProjectionSettings& settings, std::size_t expectedProbes)
    : source_(cache, params, settings.level), settings_(settings), ranking_(settings.lookaheadFrames) {
    res_ = int(source_.params().res);
    depthRes_ = int(source_.params().depthRes);

    // The grid ranks probes per cell as the pass will, less the confidence (projection.h), reading the
    // distance texel straight from the stored bytes.
    const ProjectSettings project = resolveProjectSettings(settings_.project);
    auto touched = std::make_shared<TouchedProbes>(source_);
    const auto quality = [this, project, touched](std::uint32_t probe, const SurfaceSample& x) {
        touched->touch(probe);
        const glm::vec3 at = source_.position(ProbeId{probe});
        if (x.position == at) return 0.0;  // no direction to look up
        const StoredDistances stored = storedDistances(at, x.position, x.normal, depthRes_, project,
                                                       [&](std::size_t t) { return source_.distance(ProbeId{probe}, t); });
        const double area = visibleFootprint(at, stored, res_, depthRes_, x.position, x.normal, project);
        return area > 0.0 ? 1.0 / area : 0.0;  // 1 / inf = 0: not seen
    };
    ProbeGridSettings gridSettings = settings.grid;
    if (gridSettings.cellSize == 0.0f) gridSettings.cellSize = params.radius;
    glm::vec3 boundsMin(std::numeric_limits<float>::max()), boundsMax(-std::numeric_limits<float>::max());
    for (const glm::vec3& v : meshPositions) boundsMin = glm::min(boundsMin, v), boundsMax = glm::max(boundsMax, v);
    {
        // About 64 points per cell face's area on each side, at most 4M samples.
        const std::size_t count = surfacePointsFor(meshPositions, meshIndices, gridSettings.cellSize / 8.0f, 1u << 22);
        const std::vector<SurfaceSample> points = sampleSurface(meshPositions, meshIndices, count, 0u);
        grid_ = std::make_unique<ProbeGrid>(boundsMin, boundsMax, source_.probes(), points, quality, gridSettings);
    }
    touched->releaseAll();
    candidates_ = grid_->k();

    cells_ = gl::Buffer::create();
    glNamedBufferStorage(cells_.id(), GLsizeiptr(grid_->table().size() * sizeof(std::uint32_t)), grid_->table().data(),
                         GL_DYNAMIC_STORAGE_BIT);
    residentCounts_ = gl::Buffer::create();
    glNamedBufferStorage(residentCounts_.id(), GLsizeiptr(grid_->cellCount() * sizeof(std::uint32_t)), nullptr, 0);
    nearest_ = std::make_unique<NearestProbeLists>(boundsMin, boundsMax, 2.0f * grid_->cellSize(),
                                                   std::max(settings.residentCandidates, 1));
    nearestCells_ = gl::Buffer::create();
    glNamedBufferStorage(nearestCells_.id(), GLsizeiptr(nearest_->table().size() * sizeof(std::uint32_t)),
                         nearest_->table().data(), GL_DYNAMIC_STORAGE_BIT);
    counters_ = gl::Buffer::create();
    glNamedBufferStorage(counters_.id(), kernel::kPassCounterBytes, nullptr, GL_DYNAMIC_STORAGE_BIT);
    sharesRing_ = gl::ReadbackRing<kernel::PassCounters, double>(kSharesRing, kernel::kCounterStripes);
    // An empty start without a budget: a pool for the probes expected, grown as they come.
    residency_ = std::make_unique<ProbeAtlas>(source_, ownGpuBytes(), settings.residency, cache ? 0 : expectedProbes);

    program_ = gl::compileComputeProgram("runtime/project.comp", projectDefines());
    uploadProjectBlock();
    countProgram_ = gl::compileComputeProgram("runtime/cell_residency.comp");  // reads block_ too
}

ProbeProjectionPass::~ProbeProjectionPass() = default;

void ProbeProjectionPass::uploadProjectBlock() {
    const ProjectSettings project = resolveProjectSettings(settings_.project);
    kernel::ProjectBlock b{};
    b.gridOrigin = grid_->origin();
    b.cellSize = grid_->cellSize();
    b.gridDims = grid_->dims();
    b.candidatesPerCell = candidates_;
    b.residentOrigin = nearest_->origin();
    b.residentCellSize = nearest_->cellSize();
    b.residentDims = nearest_->dims();
    b.residentPerCell = std::max(settings_.residentCandidates, 0);
    b.uncoveredAo = uncoveredAo_;
    b.cellCount = std::uint32_t(grid_->cellCount());
    b.params = {project.depthTolerance, project.depthSlope, project.minFacing, res_, depthRes_, project.depthOffset};
    if (block_.id() == 0)
        block_ = gl::UniformBlock::create(b);
    else
        block_.set(b);
}

void ProbeProjectionPass::setDiagnostics(bool on) {
    diagnostics_ = on;
    if (!on) {
        diagnosticsImage_ = {};
        diagnosticsWidth_ = diagnosticsHeight_ = 0;
        return;
    }
    if (diagnosticsProgram_.id() == 0) {
        gl::ShaderDefines defines = projectDefines();
        defines.push_back({"PROJECT_DIAGNOSTICS", "1"});
        diagnosticsProgram_ = gl::compileComputeProgram("runtime/project.comp", defines);
    }
}

std::size_t ProbeProjectionPass::ownGpuBytes() const {
    // cells_, residentCounts_, nearestCells_, counters_, the shares' read-back ring and the parameters
    return (grid_->table().size() + grid_->cellCount() + nearest_->table().size()) * sizeof(std::uint32_t) +
           kernel::kPassCounterBytes + sharesRing_.bytes() + gl::UniformBlock::kBytes<kernel::ProjectBlock>;
}

std::size_t ProbeProjectionPass::gpuBytes() const {
    const std::size_t diagnostics = std::size_t(diagnosticsWidth_) * std::size_t(diagnosticsHeight_) * 16;  // RGBA32F
    return residency_->stats().gpuBytes + ownGpuBytes() + diagnostics;
}

std::size_t ProbeProjectionPass::allocatedGpuBytes() const {
    std::size_t diagnostics = 0;
    if (diagnosticsImage_.id() != 0) {
        GLint w = 0, h = 0;
        glGetTextureLevelParameteriv(diagnosticsImage_.id(), 0, GL_TEXTURE_WIDTH, &w);
        glGetTextureLevelParameteriv(diagnosticsImage_.id(), 0, GL_TEXTURE_HEIGHT, &h);
        diagnostics = std::size_t(w) * std::size_t(h) * 16;
    }
    return residency_->allocatedGpuBytes() + glBufferBytes(cells_.id()) + glBufferBytes(residentCounts_.id()) +
           glBufferBytes(nearestCells_.id()) +
           glBufferBytes(counters_.id()) + glBufferBytes(sharesRing_.buffer()) + glBufferBytes(block_.id()) + diagnostics;
}

void ProbeProjectionPass::setFallback(std::unique_ptr<AoFallback> fallback) {
    fallback_ = std::move(fallback);
    uncoveredAo_ = fallback_ ? kernel::kUncoveredAo : 1.0f;
    uploadProjectBlock();
}

void ProbeProjectionPass::updateResidentLists() {
    if (settings_.residentCandidates <= 0 || residency_->residentVersion() == nearestVersion_) return;
    nearestVersion_ = residency_->residentVersion();
    std::vector<std::uint32_t> ids;
    std::vector<glm::vec3> positions;
    for (std::uint32_t id = 0; id < source_.size(); ++id)
        if (residency_->isServed(ProbeId{id})) ids.push_back(id), positions.push_back(source_.position(ProbeId{id}));
    const std::vector<std::size_t> changed = nearest_->assign(ids, positions);
    uploadCells(nearestCells_.id(), nearest_->table(), std::size_t(nearest_->k()), changed);
}

void ProbeProjectionPass::countResidentCandidates() {
    if (residency_->residentVersion() == countedVersion_ && !cellsChanged_) return;
    countedVersion_ = residency_->residentVersion();
    cellsChanged_ = false;
    glUseProgram(countProgram_.id());
    block_.bind(kernel::kProjectBlock);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kernel::kProbeTableBuffer, residency_->tableBuffer());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kernel::kCandidateBuffer, cells_.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kernel::kCellResidentCountBuffer, residentCounts_.id());
    const std::size_t groups = (grid_->cellCount() + 63) / 64;  // the shader strides past 65,535 groups
    glDispatchCompute(GLuint(std::clamp<std::size_t>(groups, 1, 65535)), 1, 1);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
}

std::vector<std::uint32_t> ProbeProjectionPass::readResidentCandidateCounts() const {
    std::vector<std::uint32_t> counts(grid_->cellCount());
    glGetNamedBufferSubData(residentCounts_.id(), 0, GLsizeiptr(counts.size() * sizeof(std::uint32_t)), counts.data());
    return counts;
}

ProbeId ProbeProjectionPass::addProbe(ProbeRecord probe) {
    const ProbeId id = source_.add(std::move(probe));
    const std::vector<std::size_t> changed = grid_->addProbe(source_.probes(), id);
    residency_->syncProbes(source_);
    uploadCells(cells_.id(), grid_->table(), std::size_t(candidates_), changed);
    cellsChanged_ = true;
    return id;
}

void ProbeProjectionPass::removeProbe(ProbeId id) {
    source_.remove(id);
    const std::vector<std::size_t> changed = grid_->removeProbe(source_.probes(), id);
    residency_->syncProbes(source_);
    uploadCells(cells_.id(), grid_->table(), std::size_t(candidates_), changed);
    cellsChanged_ = true;
}

void ProbeProjectionPass::run(const CameraGBuffer& gbuffer, const CameraView& view, std::uint32_t frame, GLuint aoImage) {
    residency_->update(source_, ranking_.wanted(view, *grid_, source_.probes(), residency_->planner()), unbounded_);
    unbounded_ = false;
    // A damaged probe is left out, as if it had been removed: the walk goes on without it.
    for (const ProbeAtlas::Damaged& d : residency_->takeDamaged()) {
        spdlog::warn("{}; left out: its pixels take the other probes", d.what);
        removeProbe(d.id);
    }
    updateResidentLists();
    countResidentCandidates();
    const GLuint p = diagnostics_ ? diagnosticsProgram_.id() : program_.id();
    glClearNamedBufferData(counters_.id(), GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, nullptr);
    glUseProgram(p);
    block_.bind(kernel::kProjectBlock);
    camera_.upload(view.block(gbuffer.width(), gbuffer.height()), kernel::kCameraBlock);
    glBindTextureUnit(kernel::kGBufferDepthUnit, gbuffer.depthTexture());
    glBindTextureUnit(kernel::kGBufferNormalUnit, gbuffer.normalTexture());
    residency_->bind();
    glBindImageTexture(kernel::kAoImageUnit, aoImage, 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_R32F);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kernel::kPassCountersBuffer, counters_.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kernel::kCandidateBuffer, cells_.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kernel::kResidentCandidateBuffer, nearestCells_.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kernel::kCellResidentCountBuffer, residentCounts_.id());
    if (diagnostics_) {
        if (diagnosticsWidth_ != gbuffer.width() || diagnosticsHeight_ != gbuffer.height()) {
            diagnosticsImage_ = gl::Texture::create(GL_TEXTURE_2D);
            glTextureStorage2D(diagnosticsImage_.id(), 1, GL_RGBA32F, gbuffer.width(), gbuffer.height());
            diagnosticsWidth_ = gbuffer.width(), diagnosticsHeight_ = gbuffer.height();
        }
        glBindImageTexture(kernel::kDiagnosticsImageUnit, diagnosticsImage_.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY,
                           GL_RGBA32F);
    }
    glDispatchCompute(kernel::pixelGroups(gbuffer.width()), kernel::pixelGroups(gbuffer.height()), 1);
    glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
    residency_->endFrame();
    pixels_ = double(gbuffer.width()) * double(gbuffer.height());
    // The counters into the read-back ring (when every slot is still unread, the oldest is read now
    // if it has finished, else dropped: it is only a figure for a panel).
    if (sharesRing_.inFlight() == sharesRing_.slots()) collectShares();
    sharesRing_.push(counters_.id(), pixels_);
    if (fallback_) fallback_->fill(gbuffer, view, frame, aoImage);
}

void ProbeProjectionPass::collectShares() {
    while (const auto slot = sharesRing_.poll()) {  // oldest first: the last one read is the newest
        const kernel::PassCountTotals c = kernel::sumPassCounters(slot->data.data());
        const double n = slot->tag;
        latestShares_ = PixelShares{double(c.geometry) / n, double(c.uncovered) / n, double(c.fallbackProbe) / n};
    }
}

std::optional<ProbeProjectionPass::PixelShares> ProbeProjectionPass::latestPixelShares() {
    collectShares();
    return latestShares_;
}

double ProbeProjectionPass::fetchesPerPixel() const {
    if (pixels_ == 0.0) return 0.0;
    return double(readPassCounters(counters_.id()).fetches) / pixels_;
}

ProbeProjectionPass::PixelShares ProbeProjectionPass::pixelShares() const {
    if (pixels_ == 0.0) return {};
    const kernel::PassCountTotals c = readPassCounters(counters_.id());
    return {double(c.geometry) / pixels_, double(c.uncovered) / pixels_, double(c.fallbackProbe) / pixels_};
}

}  // namespace cubeao
