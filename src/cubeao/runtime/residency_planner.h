// The residency's decisions without GL (DESIGN.md §4 "Run time that grows"): how many probe slots a
// GPU budget holds, which wanted probe goes into which slot this frame, whom it evicts, and when the
// per-frame upload bound or the eviction hysteresis says "not this frame". ProbeAtlas (GL) reads
// the pixels' feedback, asks this planner, uploads what it says and writes the probe table; the
// rules live here so that they are tested on the CPU (tests/runtime/test_residency_planner.cpp).
//
// A frame: feedback() for every read-back the GPU has finished, beginFrame(wanted), then next()
// until it gives nothing; the caller reads each load's bytes and calls loaded() (or skipped() when
// they fail their checksum: the next load may take the same slot), then endFrame().
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <vector>

#include "cubeao/runtime/probe_id.h"
#include "cubeao/runtime/probe_set.h"

namespace cubeao {

// Where slot i's six faces live in the array textures: tile t = i mod (tilesX · tilesY) of page
// p = i / (tilesX · tilesY), tiles in rows of tilesX, face f of page p in layer 6p + f; a tile is
// res × res texels in the AO texture and depthRes × depthRes in the distance one. Tiles rather than
// six layers per probe because GL_MAX_ARRAY_TEXTURE_LAYERS is 2048 on llvmpipe and on NVIDIA, i.e.
// 341 probes; a 16384² page holds 1,024 probes at 512² or 10,000 at 16² (bench render's sweep).
struct ProbeAtlasLayout {
    int tilesX = 1, tilesY = 1, pages = 1;
    int tilesPerPage() const { return tilesX * tilesY; }
    std::size_t tiles() const { return std::size_t(tilesPerPage()) * std::size_t(pages); }
    // Slot `slot`'s tile packed as the projection reads it (ProbeEntry::tile, kernel::packAtlasTile).
    std::uint32_t tile(SlotId slot) const;
};

// A near-square page just big enough for `slots` (tilesX = ⌈√slots⌉), at most maxTextureSize / res
// (and kernel::kMaxAtlasTiles) tiles a side, then more pages. Error naming the counts when 6 · pages
// exceeds maxLayers.
ProbeAtlasLayout probeAtlasLayout(std::size_t slots, int res, int maxTextureSize, int maxLayers);

// What a GPU budget has to hold: the residency's and its caller's fixed buffers, the staging regions
// uploads pass through, then whole atlas pages of probes.
struct ResidencyBudget {
    std::size_t budgetBytes = 0;  // 0: no budget (room for every probe, growing with them)
    std::size_t fixedBytes = 0;   // probe table, feedback and the caller's own (grid, counters)
    std::size_t probeBytes = 0;   // one probe's AO and distance texels
    std::size_t probes = 0;       // the probes there are (at least 1 slot is made)
    std::size_t uploadBytes = 0;     // the most a frame may upload (0: one probe)
    std::size_t stagingRegions = 0;  // regions of a frame's uploads the budget also holds (ProbeAtlas: 2)
    int res = 1, maxTextureSize = 1, maxLayers = 6;
};
struct ResidencyPool {
    ProbeAtlasLayout atlas;
    std::size_t slots = 0;       // without a budget exactly `probes`; with one, every tile of its pages
    std::size_t atlasBytes = 0;  // every tile, used or not
    // What a frame uploads at most: uploadBytes, but no more than the pool's slots hold (a frame
    // never loads more probes than there are slots), and at least one probe.
    std::size_t uploadBound = 0;
    std::size_t stagingBytes = 0;  // stagingRegions regions of uploadBound, each rounded up to 16 bytes
};
// Bytes of a staging region for uploads of at most `uploadBound` bytes: rounded up to 16, so every
// region starts where a texel may (GL refuses a PBO offset that is not a multiple of the texel's size).
std::size_t stagingRegionBytes(std::size_t uploadBound);
// The largest pool whose atlas pages and staging fit the budget beside the fixed bytes (the staging
// shrinks with the pool: min(uploadBytes, slots · probeBytes) a region). Error when it cannot hold one
// probe, naming the least budget that can.
ResidencyPool residencyPool(const ResidencyBudget& budget);

// The coarse tier (probe_atlas.h): with a budget and a cache with levels of detail, every probe is also
// held at one coarser level, so a probe the pool has no slot for is drawn coarse rather than not at
// all ("drops to coarser levels before dropping a probe"). Its level: the finest whose bytes
// (tierBytes[k]: the tier of all `probes` at level k; [0] is not read) leave the full-resolution pool
// as many slots as it has without a tier (`slotsBeside(bytes)`: the slots the budget holds beside that
// many bytes of tier, 0 when it holds none), since the slots serve what the camera is near; when every
// level costs slots (the budget sits at a page's edge), the coarsest that leaves one. 0 (no tier) when
// the pool holds every probe anyway, for a cache of one level, or when no level leaves a slot.
std::uint32_t coarseTierLevel(std::span<const std::size_t> tierBytes, std::size_t probes,
                              const std::function<std::size_t(std::size_t)>& slotsBeside);

// Eviction hysteresis: a probe the pixels used within kInUseFrames frames is replaced only by one
// whose demand exceeds kSwapMargin times its own plus kSwapMinimum sampled pixels; a probe wanted
// only by place (no pixel asked for it) does not displace one loaded within kFreshFrames.
struct ResidencyHysteresis {
    static constexpr std::int64_t kInUseFrames = 8;
    static constexpr double kSwapMargin = 1.5, kSwapMinimum = 4.0;
    static constexpr std::int64_t kFreshFrames = 30;
};

class ResidencyPlanner {
public:
    // `uploadBound` bytes a frame at most, `probeBytes` a load.
    ResidencyPlanner(std::size_t slots, std::size_t probeBytes, std::size_t uploadBound);

    std::size_t slots() const { return owner_.size(); }
    std::size_t probes() const { return slot_.size(); }  // ids known
    std::size_t resident() const { return resident_; }
    std::int64_t frame() const { return frame_; }
    std::size_t loads() const { return loads_; }      // since the start
    std::size_t evictions() const { return evictions_; }
    std::size_t frameLoads() const { return frameLoads_; }

    // More slots, numbered after the existing ones (a pool that grows without a budget).
    void growSlots(std::size_t slots);
    // Probe ids 0 … probes − 1 known (new ones not resident).
    void resizeProbes(std::size_t probes);
    // Probe `id` left the set: its slot, if it held one, is free. Returns that slot (SlotId::None: it
    // held none).
    SlotId remove(ProbeId id);

    SlotId slotOf(ProbeId id) const { return index(id) < slot_.size() ? slot_[index(id)] : SlotId::None; }
    ProbeId ownerOf(SlotId slot) const { return owner_[index(slot)]; }
    bool isResident(ProbeId id) const { return slotOf(id) != SlotId::None; }
    // Frame in which the pixels last used or wanted probe `id` (-1: never), and the newest feedback's
    // demand for it (sampled pixels that blended it or passed over it while it was not resident).
    std::int64_t lastUsed(ProbeId id) const { return index(id) < lastUsed_.size() ? lastUsed_[index(id)] : -1; }
    std::uint32_t demand(ProbeId id) const { return index(id) < demand_.size() ? demand_[index(id)] : 0u; }

    // The pixels' counts per probe id of frame `frame` (read back, oldest first).
    void feedback(std::span<const std::uint32_t> counts, std::int64_t frame);

    // This frame's wanted probes, best first (at most slots() are considered); of them only those live
    // in `probes` (read until the frame's last next(): keep it alive so long) are loaded. `unbounded`
    // lifts the upload bound (a viewer's start, a cut).
    void beginFrame(std::span<const ProbeId> wanted, const ProbeSet& probes, bool unbounded);
    struct Load {
        ProbeId probe = ProbeId::None;
        SlotId slot = SlotId::None;
        ProbeId evicted = ProbeId::None;  // the slot's resident probe, evicted by this load
    };
    // The next load, or nothing: every wanted probe is resident, the bound is reached (readAhead()
    // then names the probes the next frames will load), no slot can be freed, or the hysteresis keeps
    // the residents.
    std::optional<Load> next();
    void loaded(const Load& load);   // the probe is in its slot
    void skipped(const Load& load);  // its bytes could not be read: passed over this frame
    std::span<const ProbeId> readAhead() const { return readAhead_; }
    void endFrame() { ++frame_; }

private:
    void finish() { cursor_ = wanted_.size(); }

    std::size_t probeBytes_, uploadBound_;
    std::vector<SlotId> slot_;             // per probe id
    std::vector<std::int64_t> lastUsed_;   // per probe id
    std::vector<std::uint32_t> demand_;    // per probe id, of frame demandFrame_
    std::vector<std::int64_t> loadedAt_;   // per probe id: frame of its last load
    std::vector<ProbeId> owner_;           // per slot
    std::int64_t demandFrame_ = -1, frame_ = 0;
    std::size_t resident_ = 0, loads_ = 0, evictions_ = 0;
    // The frame being planned.
    std::vector<ProbeId> wanted_, victims_, readAhead_;
    const ProbeSet* probes_ = nullptr;
    bool unbounded_ = false, victimsMade_ = false;
    std::size_t cursor_ = 0, nextFree_ = 0, frameLoads_ = 0;
};

}  // namespace cubeao
