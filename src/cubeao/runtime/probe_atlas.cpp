#include "cubeao/runtime/probe_atlas.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstring>
#include <string>
#include <tuple>
#include <utility>

#include <glm/vec3.hpp>

#include "common/runtime_layout.h"
#include "cubeao/cache/depth_cube.h"
#include "cubeao/core/error.h"
#include "cubeao/gl/sync.h"

namespace cubeao {
namespace {

constexpr std::size_t kFeedbackRing = 3;  // feedback read 2 frames late at the latest
constexpr std::size_t kStagingRegions = 2;
constexpr std::size_t kDefaultUploadBytes = std::size_t(8) << 20;
constexpr std::size_t kReleaseBytes = std::size_t(64) << 20;  // unbounded updates drop cache pages this often
constexpr std::uint32_t kNoSlot = kernel::kNoSlot;
constexpr std::int64_t kFadeFrames = 8;  // a probe's full resolution fades in over its coarse level

GLenum aoInternalFormat(AoFormat f) { return f == AoFormat::Bc4 ? GL_COMPRESSED_RED_RGTC1 : GL_COMPRESSED_RG_RGTC2; }
GLenum depthInternalFormat(DepthFormat f) {
    return f == DepthFormat::R16Unorm ? GL_R16 : f == DepthFormat::R16Float ? GL_R16F : GL_R32F;
}
GLenum depthType(DepthFormat f) {
    return f == DepthFormat::R16Unorm ? GL_UNSIGNED_SHORT : f == DepthFormat::R16Float ? GL_HALF_FLOAT : GL_FLOAT;
}
GLint glInteger(GLenum name) {
    GLint v = 0;
    glGetIntegerv(name, &v);
    return v;
}
std::size_t feedbackWords(std::size_t probes) { return std::max<std::size_t>(1, probes); }  // a count per probe

// Texel corner (x, y) and first layer of slot `slot`'s six faces in an atlas of size² tiles: where
// project.comp's atlasTexel reads them.
glm::ivec3 slotCorner(const ProbeAtlasLayout& l, SlotId slot, int size) {
    return kernel::atlasTileCorner(l.tile(slot), size);
}

// The AO and distance array textures of an atlas of `layout` for probes with parameters `p`.
void allocateArrays(const CacheParams& p, const ProbeAtlasLayout& layout, gl::Texture& ao, gl::Texture& distance) {
    const int res = int(p.res), depthRes = int(p.depthRes);
    const auto layers = GLsizei(6 * layout.pages);
    ao = gl::Texture::create(GL_TEXTURE_2D_ARRAY);
    glTextureStorage3D(ao.id(), 1, aoInternalFormat(p.aoFormat), layout.tilesX * res, layout.tilesY * res, layers);
    // BC4 holds AO alone (traced caches, confidence 1): green reads as one, so project.comp's .rg is
    // (AO, confidence) for either format.
    if (p.aoFormat == AoFormat::Bc4) glTextureParameteri(ao.id(), GL_TEXTURE_SWIZZLE_G, GL_ONE);
    distance = gl::Texture::create(GL_TEXTURE_2D_ARRAY);
    glTextureStorage3D(distance.id(), 1, depthInternalFormat(p.depthFormat), layout.tilesX * depthRes,
                       layout.tilesY * depthRes, layers);
}

// Probe `bytes` into `slot`'s tiles of the arrays; `ao` and `depth` point at its sections (host memory
// or offsets into the bound pixel-unpack buffer).
void uploadTiles(const CacheParams& p, const ProbeAtlasLayout& layout, SlotId slot, GLuint aoTexture,
                 GLuint distanceTexture, const void* ao, std::size_t aoBytes, const void* depth) {
    const int res = int(p.res), depthRes = int(p.depthRes);
    const glm::ivec3 a = slotCorner(layout, slot, res), d = slotCorner(layout, slot, depthRes);
    glCompressedTextureSubImage3D(aoTexture, 0, a.x, a.y, a.z, res, res, 6, aoInternalFormat(p.aoFormat),
                                  GLsizei(aoBytes), ao);
    glTextureSubImage3D(distanceTexture, 0, d.x, d.y, d.z, depthRes, depthRes, 6, GL_RED, depthType(p.depthFormat),
                        depth);
}

}  // namespace

// ---- ProbeAtlas ----------------------------------------------------------------------------------

std::size_t probeGpuBytes(const CacheParams& p) { return std::size_t(aoSectionSize(p) + depthSectionSize(p)); }

// The staging ring (persistently mapped, written by the host, read by texture uploads) and the
// feedback ring (written by the projection, read by the host once its copy has finished).
struct ProbeAtlas::Staging {
    gl::UploadRing upload;  // kStagingRegions regions of uploadBound_ bytes, one per frame in turn
    // The projection's atomics go into `demand`, in GPU memory; endFrame copies it into the mapped
    // ring. Atomics straight into the persistently mapped ring cost 14 ms a 1080p frame at 2,000
    // probes and 130 ms at 20 on an H200 (host memory over PCIe, contended per probe), against
    // 0.2–0.3 ms for the whole pass without them (docs/BENCHMARKS.md, "The first GPU figures").
    gl::Buffer demand;
    std::size_t words = 0;                               // demand counts per frame
    gl::ReadbackRing<std::uint32_t, std::int64_t> feedback;  // tagged with the frame
};

ProbeAtlas::ProbeAtlas(const ProbeSource& source, std::size_t fixedBytes, const ResidencySettings& settings,
                       std::size_t minSlots)
    : params_(source.params()), staging_(std::make_unique<Staging>()) {
    const std::size_t perProbe = probeGpuBytes(params_);
    const std::size_t n = std::max<std::size_t>(source.size(), 1);
    // (feedback: the pass's demand counts, and a mapped ring of them, each entry padded to the binding
    // alignment, at most 256 bytes)
    const std::size_t tableBytes =
        n * sizeof(kernel::ProbeEntry) + feedbackWords(n) * 4 + kFeedbackRing * (feedbackWords(n) * 4 + 256);
    unlimited_ = settings.gpuBudgetBytes == 0;
    const std::size_t fixed = fixedBytes + tableBytes;
    const std::size_t uploadBytes = settings.uploadBytesPerFrame ? settings.uploadBytesPerFrame : kDefaultUploadBytes;
    ResidencyPool pool = poolFor(settings.gpuBudgetBytes, fixed, unlimited_ ? std::max(n, minSlots) : n, uploadBytes);
    // A budget that cannot hold every probe: the coarse tier, if the cache has levels, comes out of it
    // first (residency_planner.h coarseTierLevel), and the pool takes what is left.
    const std::size_t cacheProbes = source.size();  // a source's first ids are its cache's probes
    if (!unlimited_ && source.storedLevels() > 1) {
        std::vector<std::size_t> tierBytes(source.storedLevels(), 0);
        for (std::uint32_t k = 1; k < tierBytes.size(); ++k) tierBytes[k] = coarseTierFor(source, k, cacheProbes).bytes;
        const auto slotsBeside = [&](std::size_t bytes) -> std::size_t {
            if (bytes == 0) return pool.slots;
            try {
                return poolFor(settings.gpuBudgetBytes, fixed + bytes, n, uploadBytes).slots;
            } catch (const Error&) {  // the rest holds no probe at full resolution
                return 0;
            }
        };
        if (const std::uint32_t level = coarseTierLevel(tierBytes, cacheProbes, slotsBeside)) {
            coarse_ = coarseTierFor(source, level, cacheProbes);
            pool = poolFor(settings.gpuBudgetBytes, fixed + coarse_.bytes, n, uploadBytes);
            allocateArrays(coarse_.params, coarse_.atlas, coarse_.ao, coarse_.distance);
        }
    }
    uploadBound_ = pool.uploadBound;
    planner_ = ResidencyPlanner(pool.slots, perProbe, uploadBound_);
    allocateAtlas(pool);
    // A budgeted pass streams: its ring now, inside the budget. Without a budget the first frame loads
    // every probe straight from the source, and the ring is made when a probe comes later (live
    // placement), if one does: `cubeao render` never holds its 2 × 8 MiB.
    if (!unlimited_) makeStaging();
    syncProbes(source);
}

ResidencyPool ProbeAtlas::poolFor(std::size_t budgetBytes, std::size_t fixedBytes, std::size_t probes,
                                  std::size_t uploadBytes) const {
    ResidencyBudget budget;
    budget.budgetBytes = budgetBytes;
    budget.fixedBytes = fixedBytes;
    budget.probeBytes = probeGpuBytes(params_);
    budget.probes = probes;
    budget.uploadBytes = uploadBytes;
    budget.stagingRegions = kStagingRegions;
    budget.res = int(params_.res);
    budget.maxTextureSize = glInteger(GL_MAX_TEXTURE_SIZE);
    budget.maxLayers = glInteger(GL_MAX_ARRAY_TEXTURE_LAYERS);
    return residencyPool(budget);
}

ProbeAtlas::~ProbeAtlas() = default;

// Atlases for the pool's layout (the planner has its slots).
void ProbeAtlas::allocateAtlas(const ResidencyPool& pool) {
    atlas_ = pool.atlas;
    atlasBytes_ = pool.atlasBytes;
    allocateArrays(params_, atlas_, ao_, distance_);
}

ProbeAtlas::CoarseTier ProbeAtlas::coarseTierFor(const ProbeSource& source, std::uint32_t level, std::size_t probes) {
    CoarseTier tier;
    tier.level = level;
    tier.params = source.levelParams(level);
    tier.atlas = probeAtlasLayout(probes, int(tier.params.res), glInteger(GL_MAX_TEXTURE_SIZE),
                                  glInteger(GL_MAX_ARRAY_TEXTURE_LAYERS));
    tier.bytes = tier.atlas.tiles() * probeGpuBytes(tier.params);
    tier.loaded.assign(probes, false);
    return tier;
}

// Every live cache probe at the tier's level, straight from the mapping (the first update). A probe
// whose bytes fail their checksum is left to the full-resolution path, which reports it.
void ProbeAtlas::loadCoarseTier(const ProbeSource& source) {
    std::size_t sinceRelease = 0;
    for (std::uint32_t i = 0; i < coarse_.loaded.size(); ++i) {
        const ProbeId id{i};
        if (coarse_.loaded[i] || !source.isLive(id)) continue;
        ProbeView v;
        try {
            v = source.view(id, coarse_.level);
        } catch (const Error&) {
            continue;
        }
        uploadTiles(coarse_.params, coarse_.atlas, SlotId{i}, coarse_.ao.id(), coarse_.distance.id(),
                    v.aoConfidence.data(), v.aoConfidence.size(), v.depth.data());
        coarse_.loaded[i] = true;
        ++coarse_.held;
        if (!isResident(id)) writeEntry(id, source);
        if ((sinceRelease += v.aoConfidence.size() + v.depth.size()) >= kReleaseBytes)
            source.releaseAll(), sinceRelease = 0;
    }
    source.releaseAll();
}

// A pool twice the size (at least `slots`): new atlases, every resident probe's tiles copied on the
// GPU to the same slot number in the new layout. Only without a budget.
void ProbeAtlas::growAtlas(std::size_t slots, const ProbeSource& source) {
    const ProbeAtlasLayout old = atlas_;
    gl::Texture oldAo = std::move(ao_), oldDistance = std::move(distance_);
    const ResidencyPool pool = poolFor(0, 0, std::max(slots, 2 * planner_.slots()), 0);  // no budget: exactly these
    allocateAtlas(pool);
    planner_.growSlots(pool.slots);
    for (std::uint32_t i = 0; i < planner_.slots(); ++i) {
        const SlotId s{i};
        if (planner_.ownerOf(s) == ProbeId::None) continue;
        for (const auto& [from, to, size] : {std::tuple(oldAo.id(), ao_.id(), int(params_.res)),
                                             std::tuple(oldDistance.id(), distance_.id(), int(params_.depthRes))}) {
            const glm::ivec3 a = slotCorner(old, s, size), b = slotCorner(atlas_, s, size);
            glCopyImageSubData(from, GL_TEXTURE_2D_ARRAY, 0, a.x, a.y, a.z, to, GL_TEXTURE_2D_ARRAY, 0, b.x, b.y, b.z,
                               size, size, 6);
        }
        writeEntry(planner_.ownerOf(s), source);  // same slot, another tile
    }
}

void ProbeAtlas::ensureCapacity(std::size_t probes) {
    if (probes <= capacity_ && table_.id() != 0) return;
    const std::size_t old = capacity_;
    capacity_ = std::max({probes, 2 * old, std::size_t(1)});
    gl::Buffer table = gl::Buffer::create();
    glNamedBufferStorage(table.id(), GLsizeiptr(capacity_ * sizeof(kernel::ProbeEntry)), nullptr, GL_DYNAMIC_STORAGE_BIT);
    if (table_.id() != 0 && old > 0)
        glCopyNamedBufferSubData(table_.id(), table.id(), 0, 0, GLsizeiptr(old * sizeof(kernel::ProbeEntry)));
    table_ = std::move(table);
    // A new feedback ring: what the old one held for frames in flight is dropped (a hint, not state).
    staging_->words = feedbackWords(capacity_);
    staging_->feedback = gl::ReadbackRing<std::uint32_t, std::int64_t>(kFeedbackRing, staging_->words);
    staging_->demand = gl::Buffer::create();
    glNamedBufferStorage(staging_->demand.id(), GLsizeiptr(staging_->words * 4), nullptr, GL_DYNAMIC_STORAGE_BIT);
}

std::size_t ProbeAtlas::stagingBytes() const { return kStagingRegions * stagingRegionBytes(uploadBound_); }

void ProbeAtlas::makeStaging() {
    staging_->upload = gl::UploadRing(kStagingRegions, stagingRegionBytes(uploadBound_));
    updateGpuBytes();
}

// What allocateAtlas, ensureCapacity and the staging ring hold now.
void ProbeAtlas::updateGpuBytes() {
    stats_.gpuBytes = atlasBytes_ + staging_->upload.bytes() + capacity_ * sizeof(kernel::ProbeEntry) +
                      staging_->feedback.bytes() + staging_->words * 4 + coarse_.bytes;
    stats_.coarseLevel = coarse_.level, stats_.coarseBytes = coarse_.bytes;
}

void ProbeAtlas::writeEntry(ProbeId id, const ProbeSource& source, bool slotChanged) {
    kernel::ProbeEntry e{};
    e.position = source.position(id);
    e.distanceScale = source.distanceScale(id);
    const SlotId slot = planner_.slotOf(id);
    e.slot = index(slot);
    e.tile = slot == SlotId::None ? kNoSlot : atlas_.tile(slot);
    e.qualityScale = 1.0f;
    const bool coarse = source.isLive(id) && coarse_.level > 0 && index(id) < coarse_.loaded.size() &&
                        coarse_.loaded[index(id)];
    if (slot == SlotId::None && coarse) {  // drawn at the coarse tier's level until a slot holds it
        e.tile = coarse_.atlas.tile(SlotId{index(id)});
        e.level = coarse_.level;
    } else if (slot != SlotId::None && coarse && index(id) < fadeStart_.size() && fadeStart_[index(id)] >= 0) {
        // Its full resolution fades in: the quality goes from the coarse level's (4^-level of it, the
        // texels' area) to its own over kFadeFrames frames, geometrically, so the blend weights move
        // as they do when probes change rank.
        const std::int64_t since = frame() - fadeStart_[index(id)];
        if (since >= kFadeFrames) {
            fadeStart_[index(id)] = -1;
        } else {
            const double t = double(since + 1) / double(kFadeFrames);
            e.qualityScale = float(std::pow(4.0, -double(coarse_.level) * (1.0 - t)));
            fading_.push_back(id);
        }
    }
    if (slotChanged) ++residentVersion_;
    glNamedBufferSubData(table_.id(), GLintptr(index(id) * sizeof e), sizeof e, &e);
}

void ProbeAtlas::syncProbes(const ProbeSource& source) {
    const std::size_t before = planner_.probes();
    const std::size_t live = source.probes().liveCount();
    if (unlimited_ && live > slots() && table_.id() != 0) growAtlas(live, source);
    ensureCapacity(source.size());
    updateGpuBytes();
    planner_.resizeProbes(source.size());
    fadeStart_.resize(source.size(), -1);
    if (source.size() > before) {  // new ids: one write of the whole range
        std::vector<kernel::ProbeEntry> entries(source.size() - before);
        for (std::size_t i = 0; i < entries.size(); ++i) {
            const ProbeId id{std::uint32_t(before + i)};
            entries[i] = {source.position(id), source.distanceScale(id), kNoSlot, kNoSlot, 0u, 1.0f};
        }
        glNamedBufferSubData(table_.id(), GLintptr(before * sizeof(kernel::ProbeEntry)),
                             GLsizeiptr(entries.size() * sizeof(kernel::ProbeEntry)), entries.data());
    }
    for (std::uint32_t i = 0; i < planner_.probes(); ++i)  // removed probes leave their slots
        if (const ProbeId id{i}; !source.isLive(id) && planner_.remove(id) != SlotId::None) writeEntry(id, source);
}

void ProbeAtlas::readFeedback() {
    while (const auto slot = staging_->feedback.poll())  // oldest first
        planner_.feedback(slot->data.first(std::min(staging_->words, slot->data.size())), slot->tag);
}

void ProbeAtlas::upload(const ProbeView& p, SlotId slot, bool direct) {
    const void* ao = p.aoConfidence.data();
    const void* depth = p.depth.data();
    if (!direct) {  // through this frame's staging region: the copy returns before the GPU reads it
        if (staging_->upload.bytes() == 0) makeStaging();
        const std::size_t region = std::size_t(frame() % std::int64_t(kStagingRegions));
        gl::UploadRing& ring = staging_->upload;
        ao = reinterpret_cast<const void*>(ring.write(region, stats_.frameUploadBytes, std::as_bytes(p.aoConfidence)));
        depth = reinterpret_cast<const void*>(
            ring.write(region, stats_.frameUploadBytes + p.aoConfidence.size(), std::as_bytes(p.depth)));
        glBindBuffer(GL_PIXEL_UNPACK_BUFFER, ring.buffer());
    }
    uploadTiles(params_, atlas_, slot, ao_.id(), distance_.id(), ao, p.aoConfidence.size(), depth);
    if (!direct) glBindBuffer(GL_PIXEL_UNPACK_BUFFER, 0);
    stats_.frameUploadBytes += probeGpuBytes(params_);
    ++stats_.frameUploads;
}

void ProbeAtlas::update(const ProbeSource& source, std::span<const ProbeId> wanted, bool unbounded) {
    const auto start = std::chrono::steady_clock::now();
    readFeedback();
    stats_.frameUploads = 0, stats_.frameUploadBytes = 0;
    const std::size_t region = std::size_t(frame() % std::int64_t(kStagingRegions));
    if (!unbounded && staging_->upload.bytes() > 0 && !staging_->upload.writable(region)) {  // (unbounded uploads go straight from the source's memory)
        stats_.frameUploadMs = 0.0;  // the GPU still reads this region: load nothing this frame
        return;
    }
    std::size_t releasedAt = 0;
    GLint unpackAlignment = 4;
    glGetIntegerv(GL_UNPACK_ALIGNMENT, &unpackAlignment);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);  // distance rows are 2 · depthRes bytes: odd depthRes is not 4-aligned
    if (coarse_.level > 0 && frame() == 0) loadCoarseTier(source);
    planner_.beginFrame(wanted, source.probes(), unbounded);
    while (const std::optional<ResidencyPlanner::Load> load = planner_.next()) {
        // The probe's bytes are read (a cache probe's checksum checked on first use) before its slot
        // is freed.
        ProbeView bytes;
        try {
            source.prefetch(load->probe);  // one read of its pages, if the frames before did not ask already
            bytes = source.view(load->probe);
        } catch (const Error& e) {
            damaged_.push_back({load->probe, e.what()});
            ++stats_.damaged;
            planner_.skipped(*load);
            continue;
        }
        planner_.loaded(*load);
        // A bounded frame's load over the probe's coarse level fades in (writeEntry); a start or a cut
        // shows it at once.
        fadeStart_[index(load->probe)] = unbounded ? -1 : frame();
        if (load->evicted != ProbeId::None) writeEntry(load->evicted, source);
        upload(bytes, load->slot, unbounded);
        // An unbounded update (the first frame, a cut) reads every probe it loads straight from the
        // mapping: drop the pages every kReleaseBytes, or the whole pool's worth stays resident
        // until the end of the batch (peak RSS = pool + its copy in the page cache).
        if (unbounded && stats_.frameUploadBytes - releasedAt >= kReleaseBytes) {
            source.releaseAll();
            releasedAt = stats_.frameUploadBytes;
        }
        writeEntry(load->probe, source);
    }
    // One step further for the probes fading in (loaded in an earlier frame; this frame's have their first).
    for (const ProbeId id : std::exchange(fading_, {})) {
        if (!planner_.isResident(id)) continue;
        if (fadeStart_[index(id)] == frame())
            fading_.push_back(id);
        else
            writeEntry(id, source, false);
    }
    for (const ProbeId id : planner_.readAhead()) source.prefetch(id);  // in memory when their frame comes
    glPixelStorei(GL_UNPACK_ALIGNMENT, unpackAlignment);
    if (stats_.frameUploads > 0) source.releaseAll();  // the bytes are staged (or copied by the driver)
    if (!unbounded && stats_.frameUploads > 0) staging_->upload.fence(region);
    if (frame() > 0 && !unbounded) stats_.maxFrameUploadBytes = std::max(stats_.maxFrameUploadBytes, stats_.frameUploadBytes);
    stats_.frameUploadMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

ResidencyStats ProbeAtlas::stats() const {
    ResidencyStats s = stats_;
    s.slots = planner_.slots(), s.resident = planner_.resident();
    s.loads = planner_.loads(), s.evictions = planner_.evictions();
    return s;
}

std::vector<ProbeAtlas::Damaged> ProbeAtlas::takeDamaged() { return std::exchange(damaged_, {}); }

std::size_t glBufferBytes(GLuint buffer) {
    GLint64 size = 0;
    glGetNamedBufferParameteri64v(buffer, GL_BUFFER_SIZE, &size);
    return std::size_t(size);
}

namespace {

// Level 0 of an array texture: width × height × layers × the bytes per texel of its internal format.
std::size_t glTextureBytes(GLuint texture) {
    GLint w = 0, h = 0, layers = 0, format = 0;
    glGetTextureLevelParameteriv(texture, 0, GL_TEXTURE_WIDTH, &w);
    glGetTextureLevelParameteriv(texture, 0, GL_TEXTURE_HEIGHT, &h);
    glGetTextureLevelParameteriv(texture, 0, GL_TEXTURE_DEPTH, &layers);
    glGetTextureLevelParameteriv(texture, 0, GL_TEXTURE_INTERNAL_FORMAT, &format);
    const std::size_t texels = std::size_t(w) * std::size_t(h) * std::size_t(layers);
    if (format == GL_COMPRESSED_RED_RGTC1) return texels / 2;
    return texels * (format == GL_COMPRESSED_RG_RGTC2 ? 1 : format == GL_R32F ? 4 : 2);
}

}  // namespace

std::size_t ProbeAtlas::allocatedGpuBytes() const {
    const std::size_t coarse =
        coarse_.level > 0 ? glTextureBytes(coarse_.ao.id()) + glTextureBytes(coarse_.distance.id()) : 0;
    return coarse + glTextureBytes(ao_.id()) + glTextureBytes(distance_.id()) + glBufferBytes(table_.id()) +
           glBufferBytes(staging_->upload.buffer()) + glBufferBytes(staging_->feedback.buffer()) +
           glBufferBytes(staging_->demand.id());
}

void ProbeAtlas::bind() {
    // Every slot unread: read what has passed now; endFrame's push drops the oldest if it has not (a hint).
    if (staging_->feedback.inFlight() == staging_->feedback.slots()) readFeedback();
    glClearNamedBufferData(staging_->demand.id(), GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, nullptr);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kernel::kProbeFeedbackBuffer, staging_->demand.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kernel::kProbeTableBuffer, table_.id());
    glBindTextureUnit(kernel::kProbeAoUnit, ao_.id());
    glBindTextureUnit(kernel::kProbeDistanceUnit, distance_.id());
    // Without a tier no probe has a level above 0 and the shader never reads these units.
    glBindTextureUnit(kernel::kProbeCoarseAoUnit, coarse_.level > 0 ? coarse_.ao.id() : ao_.id());
    glBindTextureUnit(kernel::kProbeCoarseDistanceUnit, coarse_.level > 0 ? coarse_.distance.id() : distance_.id());
}

void ProbeAtlas::endFrame() {
    staging_->feedback.push(staging_->demand.id(), frame());  // the pass's atomics, read a frame or more later
    planner_.endFrame();
}

}  // namespace cubeao
