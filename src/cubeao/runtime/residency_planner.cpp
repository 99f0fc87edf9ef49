#include "cubeao/runtime/residency_planner.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "common/runtime_layout.h"
#include "cubeao/core/error.h"

namespace cubeao {

static_assert(index(SlotId::None) == kernel::kNoSlot && index(ProbeId::None) == kernel::kNoProbe);

namespace {

std::string mib(std::size_t bytes) { return std::to_string(double(bytes) / double(1 << 20)).substr(0, 6) + " MiB"; }

}  // namespace

std::uint32_t ProbeAtlasLayout::tile(SlotId slot) const {
    const int t = int(index(slot)) % tilesPerPage();
    return kernel::packAtlasTile(t % tilesX, t / tilesX, int(index(slot)) / tilesPerPage());
}

ProbeAtlasLayout probeAtlasLayout(std::size_t slots, int res, int maxTextureSize, int maxLayers) {
    const std::size_t perSide =
        std::size_t(std::clamp(maxTextureSize / std::max(res, 1), 1, kernel::kMaxAtlasTiles - 1));
    const std::size_t n = std::max<std::size_t>(slots, 1);
    const std::size_t x = std::min(perSide, std::size_t(std::ceil(std::sqrt(double(n)))));
    const std::size_t y = std::min(perSide, (n + x - 1) / x);
    const std::size_t pages = (n + x * y - 1) / (x * y);
    if (6 * pages > std::size_t(std::max(std::min(maxLayers, 6 * 1023), 0)))  // packAtlasTile: pages < 1024
        throw Error(std::to_string(slots) + " probes at " + std::to_string(res) + "² per face need " +
                    std::to_string(6 * pages) + " texture layers of " + std::to_string(x * std::size_t(res)) + "×" +
                    std::to_string(y * std::size_t(res)) + "; this GL allows " + std::to_string(maxLayers) +
                    " layers of at most " + std::to_string(maxTextureSize) + "²");
    return {int(x), int(y), int(pages)};
}

std::size_t stagingRegionBytes(std::size_t uploadBound) { return (uploadBound + 15) / 16 * 16; }

ResidencyPool residencyPool(const ResidencyBudget& b) {
    const auto layout = [&](std::size_t slots) { return probeAtlasLayout(slots, b.res, b.maxTextureSize, b.maxLayers); };
    const std::size_t p = std::max<std::size_t>(b.probeBytes, 1);
    const auto bound = [&](std::size_t slots) { return std::max(p, std::min(b.uploadBytes, slots * p)); };
    const auto staging = [&](std::size_t slots) { return b.stagingRegions * stagingRegionBytes(bound(slots)); };
    const auto finish = [&](ProbeAtlasLayout atlas, std::size_t slots) {
        ResidencyPool pool;
        pool.atlas = atlas;
        pool.slots = slots;
        pool.atlasBytes = slots * b.probeBytes;
        pool.uploadBound = bound(slots);
        pool.stagingBytes = staging(slots);
        return pool;
    };
    if (b.budgetBytes == 0) {  // exactly the probes, growing with them
        const std::size_t slots = std::max<std::size_t>(b.probes, 1);
        const ProbeAtlasLayout atlas = layout(slots);
        ResidencyPool pool = finish(atlas, slots);
        pool.atlasBytes = atlas.tiles() * b.probeBytes;
        return pool;
    }
    const std::size_t least = b.fixedBytes + staging(1) + b.probeBytes;
    if (b.budgetBytes < least)
        throw Error("GPU budget " + mib(b.budgetBytes) + " cannot hold one probe: a probe takes " + mib(b.probeBytes) +
                    " (" + std::to_string(b.res) + "² faces), and the grid, probe table and the staging of its upload " +
                    mib(b.fixedBytes + staging(1)) + "; give at least " + mib(least));
    // A partly used page costs as much as a full one: fewer probes until whole pages (and the staging
    // their uploads need) fit.
    const auto cost = [&](std::size_t slots) {
        const std::size_t tiles = layout(slots).tiles();
        return b.fixedBytes + staging(tiles) + tiles * b.probeBytes;
    };
    std::size_t want = std::min(std::max<std::size_t>(b.probes, 1), (b.budgetBytes - b.fixedBytes) / b.probeBytes);
    while (want > 1 && cost(want) > b.budgetBytes) --want;
    const ProbeAtlasLayout atlas = layout(want);
    return finish(atlas, atlas.tiles());  // every tile of the pages paid for is a slot
}

std::uint32_t coarseTierLevel(std::span<const std::size_t> tierBytes, std::size_t probes,
                              const std::function<std::size_t(std::size_t)>& slotsBeside) {
    if (tierBytes.size() < 2 || probes == 0) return 0;
    const std::size_t without = slotsBeside(0);
    if (without == 0 || without >= probes) return 0;  // no slot at all; every probe at full resolution
    for (std::size_t k = 1; k < tierBytes.size(); ++k)
        if (slotsBeside(tierBytes[k]) >= without) return std::uint32_t(k);
    const std::size_t coarsest = tierBytes.size() - 1;
    return slotsBeside(tierBytes[coarsest]) >= 1 ? std::uint32_t(coarsest) : 0u;
}

// ---- ResidencyPlanner ----------------------------------------------------------------------------

ResidencyPlanner::ResidencyPlanner(std::size_t slots, std::size_t probeBytes, std::size_t uploadBound)
    : probeBytes_(std::max<std::size_t>(probeBytes, 1)), uploadBound_(uploadBound), owner_(slots, ProbeId::None) {}

void ResidencyPlanner::growSlots(std::size_t slots) {
    if (slots > owner_.size()) owner_.resize(slots, ProbeId::None);
}

void ResidencyPlanner::resizeProbes(std::size_t probes) {
    slot_.resize(probes, SlotId::None);
    lastUsed_.resize(probes, -1);
    demand_.resize(probes, 0u);
    loadedAt_.resize(probes, -1);
}

SlotId ResidencyPlanner::remove(ProbeId id) {
    const std::uint32_t i = index(id);
    if (i >= slot_.size()) return SlotId::None;
    const SlotId slot = slot_[i];
    if (slot != SlotId::None) {
        owner_[index(slot)] = ProbeId::None;
        slot_[i] = SlotId::None;
        --resident_;
    }
    return slot;
}

void ResidencyPlanner::feedback(std::span<const std::uint32_t> counts, std::int64_t frame) {
    const bool newest = frame > demandFrame_;
    if (newest) std::fill(demand_.begin(), demand_.end(), 0u), demandFrame_ = frame;
    for (std::size_t id = 0; id < std::min(counts.size(), lastUsed_.size()); ++id) {
        if (counts[id] == 0) continue;
        lastUsed_[id] = std::max(lastUsed_[id], frame);
        if (newest) demand_[id] = counts[id];
    }
}

void ResidencyPlanner::beginFrame(std::span<const ProbeId> wanted, const ProbeSet& probes, bool unbounded) {
    probes_ = &probes;
    if (wanted.size() > slots()) wanted = wanted.first(slots());
    wanted_.assign(wanted.begin(), wanted.end());
    victims_.clear();
    readAhead_.clear();
    unbounded_ = unbounded;
    victimsMade_ = false;
    cursor_ = 0, nextFree_ = 0, frameLoads_ = 0;
}

std::optional<ResidencyPlanner::Load> ResidencyPlanner::next() {
    using H = ResidencyHysteresis;
    for (; cursor_ < wanted_.size(); ++cursor_) {
        const ProbeId id = wanted_[cursor_];
        const std::uint32_t i = index(id);
        if (i >= slot_.size() || !probes_->isLive(id) || slot_[i] != SlotId::None) continue;
        if (!unbounded_ && (frameLoads_ + 1) * probeBytes_ > uploadBound_) {
            // The next ones, so that their bytes are in memory when their frame comes.
            const std::size_t end = std::min(wanted_.size(), cursor_ + 2 * uploadBound_ / probeBytes_);
            for (std::size_t a = cursor_; a < end; ++a)
                if (!isResident(wanted_[a])) readAhead_.push_back(wanted_[a]);
            finish();
            return std::nullopt;
        }
        while (nextFree_ < owner_.size() && owner_[nextFree_] != ProbeId::None) ++nextFree_;
        if (nextFree_ < owner_.size()) return Load{id, SlotId{std::uint32_t(nextFree_)}, ProbeId::None};
        if (!victimsMade_) {  // resident, not wanted: the least demanded, then least recently used, first
            std::vector<bool> isWanted(slot_.size(), false);
            for (const ProbeId v : wanted_)
                if (index(v) < isWanted.size()) isWanted[index(v)] = true;
            for (const ProbeId owner : owner_)
                if (owner != ProbeId::None && !isWanted[index(owner)]) victims_.push_back(owner);
            std::sort(victims_.begin(), victims_.end(), [&](ProbeId a, ProbeId b) {
                if (demand(a) != demand(b)) return demand(a) > demand(b);
                return lastUsed(a) != lastUsed(b) ? lastUsed(a) > lastUsed(b) : a > b;
            });  // taken from the back
            victimsMade_ = true;
        }
        if (victims_.empty()) break;  // every resident probe is wanted more
        const ProbeId victim = victims_.back();
        // Hysteresis: a probe the pixels use gives way only to one they want clearly more, or two
        // probes of similar demand would swap places every frame (and every swap is an upload).
        // A probe only ranked by place (no pixel asked for it yet) does not displace one loaded
        // within kFreshFrames: as the camera moves, the places near the cut of the ranking swap.
        const bool victimInUse = lastUsed(victim) >= frame_ - H::kInUseFrames;
        if (victimInUse && double(demand(id)) <= H::kSwapMargin * double(demand(victim)) + H::kSwapMinimum) break;
        if (demand(id) == 0 && loadedAt_[index(victim)] >= frame_ - H::kFreshFrames) break;
        return Load{id, slotOf(victim), victim};
    }
    finish();
    return std::nullopt;
}

void ResidencyPlanner::loaded(const Load& load) {
    if (load.evicted != ProbeId::None) {
        victims_.pop_back();  // next() offered the back of the list
        slot_[index(load.evicted)] = SlotId::None;
        ++evictions_;
        --resident_;
    }
    owner_[index(load.slot)] = load.probe;
    slot_[index(load.probe)] = load.slot;
    loadedAt_[index(load.probe)] = frame_;
    ++loads_, ++resident_, ++frameLoads_;
    ++cursor_;
}

void ResidencyPlanner::skipped(const Load&) { ++cursor_; }

}  // namespace cubeao
