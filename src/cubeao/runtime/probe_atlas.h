// The probe atlas: which probes are on the GPU (DESIGN.md §4 "Run time that grows"), a fixed pool
// of atlas slots sized from a GPU memory budget, filled from the probes' stored bytes (BC5 AO +
// confidence, or BC4 AO read with confidence 1; the distance cube in its stored format: compressed
// all the way, no decode on the CPU) by a priority the caller computes each frame, at most a fixed
// number of bytes per frame, through a persistently mapped staging ring, so a frame never waits for
// the disk or for the GPU.
//
// Eviction: when a wanted probe needs a slot, the victim is a resident probe that is not wanted, the
// one the pixels used least recently first (sampled feedback of shaders/runtime/project.comp, read
// frames later through fences; never waited for). The caller ranks by that feedback too (what the
// pixels used and what they had to pass over), so a probe the frame's pixels use is never dropped
// while a worse one stays. Those rules are ResidencyPlanner's (residency_planner.h, no GL); this class
// applies its plan: uploads, the probe table, the feedback ring.
//
// The bytes come from a ProbeSource (probe_source.h).
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "cubeao/cache/cache_file.h"
#include "cubeao/gl/handles.h"
#include "cubeao/runtime/probe_source.h"
#include "cubeao/runtime/residency_planner.h"

namespace cubeao {

struct ResidencySettings {
    // GPU bytes for everything the projection allocates (atlases, staging ring, probe table, candidate
    // grid, feedback); 0 = room for every probe of the source at the start.
    std::size_t gpuBudgetBytes = 0;
    // Bytes uploaded per frame at most; 0 → 8 MiB. At least one probe's bytes, and no more than the
    // pool's slots hold (the staging, two regions of this, is sized by what it can hold).
    std::size_t uploadBytesPerFrame = 0;

    // From MiB, as `render`, `bench render`, cubeao-gpubench and cubeao-view take them (--gpu-budget-mb,
    // --upload-mb; not negative).
    static ResidencySettings fromMib(double gpuBudgetMb, double uploadMb) {
        constexpr double kMib = 1024.0 * 1024.0;
        return {std::size_t(gpuBudgetMb * kMib), std::size_t(uploadMb * kMib)};
    }
};

struct ResidencyStats {
    std::size_t slots = 0, resident = 0;  // pool size, probes in it now
    std::size_t loads = 0, evictions = 0;  // since the start
    std::size_t frameUploads = 0, frameUploadBytes = 0;  // of the last update
    double frameUploadMs = 0.0;  // host time the last update spent staging and issuing uploads
    std::size_t maxFrameUploadBytes = 0;  // the largest frameUploadBytes so far (frames after the first)
    std::size_t gpuBytes = 0;  // everything the residency allocated (atlases, staging, table, feedback)
    std::uint32_t coarseLevel = 0;  // the coarse tier's level of detail (0: none)
    std::size_t coarseBytes = 0;    // its atlases, within gpuBytes
    std::size_t damaged = 0;   // loads refused: the probe's stored bytes failed their checksum
};

// GL_BUFFER_SIZE of a buffer, as the driver reports it.
std::size_t glBufferBytes(GLuint buffer);

// One probe's bytes on the GPU: its AO section (6 res² bytes of BC5, half that of BC4) and its
// 6 depthRes² distance texels.
std::size_t probeGpuBytes(const CacheParams& params);

class ProbeAtlas {
public:
    // `fixedBytes`: what the caller allocates besides (grid, counters), counted against the budget.
    // Error when the budget cannot hold one probe, naming what it can hold. Needs a current GL 4.5
    // context.
    // Without a budget the pool starts with room for max(the source's probes, minSlots) and grows.
    ProbeAtlas(const ProbeSource& source, std::size_t fixedBytes, const ResidencySettings& settings,
               std::size_t minSlots = 0);
    ~ProbeAtlas();

    // Slots in the pool. Without a budget the pool holds every live probe and grows (the atlas is
    // copied on the GPU into one twice the size) when probes are added beyond it.
    std::size_t slots() const { return planner_.slots(); }
    std::size_t uploadBound() const { return uploadBound_; }  // bytes per frame at most
    // The staging ring's bytes: held from the start under a budget (counted in it), made on the first
    // upload that needs it without one (a probe added after the first frame).
    std::size_t stagingBytes() const;
    std::int64_t frame() const { return planner_.frame(); }  // frames bound so far
    // Keeps the probe table in step with the source (new ids, removed ones); call after add/remove.
    void syncProbes(const ProbeSource& source);

    // Frame f: reads the feedback of earlier frames the GPU has finished (polls, never waits), then
    // loads the `wanted` probes (best first; at most slots() of them are kept) that are not resident,
    // evicting as described above, within the per-frame byte bound (`unbounded` lifts it: a viewer's
    // start or a cut to a new place, where the caller prefers one long frame to many poor ones).
    void update(const ProbeSource& source, std::span<const ProbeId> wanted, bool unbounded);
    // Probes update() went to load whose stored bytes failed their checksum, with the reader's
    // message, since the last call: never loaded; the caller leaves them out of the probe set
    // (ProbeProjectionPass), or update() tries them again.
    struct Damaged {
        ProbeId id;
        std::string what;
    };
    std::vector<Damaged> takeDamaged();
    // Frame in which the pixels last used or wanted probe `id` according to the feedback read so far
    // (-1: never), and the newest feedback's demand: sampled pixels (every 4th in x and y) that blended
    // it or had to pass over it while it was not resident.
    std::int64_t lastUsed(ProbeId id) const { return planner_.lastUsed(id); }
    std::uint32_t demand(ProbeId id) const { return planner_.demand(id); }
    bool isResident(ProbeId id) const { return planner_.isResident(id); }
    // Resident at full resolution or held by the coarse tier: the pixels can read it.
    bool isServed(ProbeId id) const {
        return isResident(id) || (coarse_.level > 0 && index(id) < coarse_.loaded.size() && coarse_.loaded[index(id)]);
    }
    // The coarse tier's level (0: none; residency_planner.h coarseTierLevel) and its probes held now.
    std::uint32_t coarseLevel() const { return coarse_.level; }
    std::size_t coarseHeld() const { return coarse_.held; }
    // Changes whenever a probe enters or leaves the pool (a load, an eviction, a removal).
    std::uint64_t residentVersion() const { return residentVersion_; }

    // Binds the atlases, the probe table and this frame's feedback buffer (cleared) for the
    // projection; endFrame() fences the feedback after the dispatch.
    void bind();
    void endFrame();

    const ProbeAtlasLayout& atlas() const { return atlas_; }
    GLuint aoTexture() const { return ao_.id(); }
    GLuint tableBuffer() const { return table_.id(); }  // kernel::ProbeEntry per probe id
    GLuint distanceTexture() const { return distance_.id(); }
    ResidencyStats stats() const;  // the planner's counts and this class's upload figures
    const ResidencyPlanner& planner() const { return planner_; }  // slots, residents, the pixels' demand
    // What GL says the residency's textures and buffers hold (sizes queried from the driver): the
    // check of stats().gpuBytes, for tests.
    std::size_t allocatedGpuBytes() const;

private:
    struct Staging;
    void ensureCapacity(std::size_t probes);
    // The pool for `probes` within `budgetBytes` beside `fixedBytes` (0: exactly that many slots), at
    // this GL's texture limits, a frame uploading at most `uploadBytes` (residency_planner.h).
    ResidencyPool poolFor(std::size_t budgetBytes, std::size_t fixedBytes, std::size_t probes,
                          std::size_t uploadBytes) const;
    void allocateAtlas(const ResidencyPool& pool);
    void growAtlas(std::size_t slots, const ProbeSource& source);
    void updateGpuBytes();
    void makeStaging();  // the staging ring for uploadBound_, counted in the GPU bytes
    // Probe `id`'s table entry; `slotChanged` false: only its fade moved (the resident version stays).
    void writeEntry(ProbeId id, const ProbeSource& source, bool slotChanged = true);
    void readFeedback();
    void upload(const ProbeView& bytes, SlotId slot, bool direct);
    void loadCoarseTier(const ProbeSource& source);

    // The coarse tier: the source's cache probes at one coarser level, probe id i in slot i, loaded on
    // the first update, never evicted. Added probes (one level) have none.
    struct CoarseTier {
        std::uint32_t level = 0;  // 0: no tier
        CacheParams params;       // the level's
        ProbeAtlasLayout atlas;
        gl::Texture ao, distance;
        std::vector<bool> loaded;  // per probe id
        std::size_t held = 0, bytes = 0;
    };
    CoarseTier coarse_;
    // Probes whose full resolution was loaded over their coarse level within kFadeFrames: their entries
    // are written again each update with the next quality scale, from the frame in fadeStart_ (per id; -1: none).
    std::vector<ProbeId> fading_;
    std::vector<std::int64_t> fadeStart_;
    // The tier of `probes` cache probes at `level` (its layout and bytes; no GL texture yet).
    static CoarseTier coarseTierFor(const ProbeSource& source, std::uint32_t level, std::size_t probes);
    CacheParams params_;
    std::size_t capacity_ = 0, uploadBound_ = 0;
    bool unlimited_ = false;  // no budget: grow with the probe set
    ProbeAtlasLayout atlas_;
    gl::Texture ao_, distance_;
    gl::Buffer table_;
    ResidencyPlanner planner_{0, 1, 0};  // slots, residents and the feedback, by probe id
    std::unique_ptr<Staging> staging_;
    std::vector<Damaged> damaged_;
    std::uint64_t residentVersion_ = 0;
    std::size_t atlasBytes_ = 0;
    ResidencyStats stats_;  // slots, resident, loads and evictions are the planner's (stats())
};

}  // namespace cubeao
