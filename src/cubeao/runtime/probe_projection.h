// The probe cache as a run-time AO method (`render --method probes`, DESIGN.md §4 "Run time that
// grows"): the probes' texels stream into a pool of atlas slots under a GPU memory budget
// (probe_atlas.h), a world grid lists K candidate probes per cell (probe_grid.h), and the
// projection pass (shaders/runtime/project.comp; per-point math and CPU twin in projection.h) shades
// every pixel from the resident candidates of its cell, or, when none of them sees it, from the
// resident probes nearest it (nearest_lists.h). Probes can be added and removed while it runs; a
// pixel no probe tried sees is filled by a screen-space fallback (ao_pass.h AoFallback) when one is
// attached, and counted.
#pragma once

#include <array>
#include <cstddef>
#include <memory>
#include <optional>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

#include "cubeao/cache/cache_file.h"
#include "cubeao/gl/handles.h"
#include "cubeao/gl/shader.h"
#include "cubeao/gl/sync.h"
#include "cubeao/gl/uniform_block.h"
#include "cubeao/runtime/ao_pass.h"
#include "cubeao/runtime/nearest_lists.h"
#include "cubeao/runtime/probe_grid.h"
#include "cubeao/runtime/probe_ranking.h"
#include "cubeao/runtime/probe_atlas.h"
#include "cubeao/runtime/projection.h"

namespace cubeao {

struct ProbeProjectionSettings {
    ProbeGridSettings grid;
    ResidencySettings residency;
    // Frames the residency looks ahead along the camera's motion when it ranks probes.
    float lookaheadFrames = 8.0f;
    // The second list (nearest_lists.h): a pixel none of whose cell's candidates is resident and sees it
    // tries the residentCandidates resident probes nearest its coarse cell (cells of 2 grid cells at
    // least) before the screen-space fallback; 0 = no second list.
    int residentCandidates = 8;
    // The AO format the pass holds a cache's probes in; none: the cache's own. A viewer asks for BC5
    // so that probes baked while it runs (live placement's horizon probes carry a confidence) can join
    // a traced cache stored as BC4 (its probes are then converted as they load: confidence 1).
    std::optional<AoFormat> aoFormat;
    // The level of detail every probe of a cache with levels is held at (0: the finest; Error for a
    // level the cache lacks): `render --level`, which measures what each level costs the picture.
    std::uint32_t level = 0;
    // The depth test's settings (projection.h; zero fields: the defaults): `render --depth-lift`.
    ProjectSettings project;
};

class ProbeProjectionPass : public AoPass {
public:
    // The probes of `cache` (read lazily from its mapping) and the candidate grid over the scene's
    // mesh (its bounds, and points sampled on its surfaces: probe_grid.h), which reads a few distance
    // texels of every probe and nothing of their AO. A probe's checksum is checked when it is first
    // loaded; one that fails is left out with a warning (as removeProbe does; counted in
    // residency().stats().damaged), and the frame goes on. The first frame loads what it wants
    // without the per-frame bound. Needs a current GL 4.5 context; `cache` must outlive the pass.
    ProbeProjectionPass(const CacheReader& cache, std::span<const glm::vec3> positions,
                        std::span<const std::uint32_t> indices, const ProbeProjectionSettings& settings = {});
    // No probes yet: they come through addProbe (a viewer placing probes live). `params` are the
    // probes' (resolutions, depth format, R). Without a budget the pool starts with `expectedProbes`
    // slots and grows; with one, probes beyond what it holds stream as from a cache.
    ProbeProjectionPass(const CacheParams& params, std::span<const glm::vec3> positions,
                        std::span<const std::uint32_t> indices, const ProbeProjectionSettings& settings = {},
                        std::size_t expectedProbes = 64);
    ~ProbeProjectionPass() override;

    const char* name() const override { return "probes"; }
    void run(const CameraGBuffer& gbuffer, const CameraView& view, std::uint32_t frame, GLuint aoImage) override;
    double fetchesPerPixel() const override;

    // Live probe set. addProbe returns the new probe's id and gives the pixels the same probe loaded
    // from a cache gives (same bytes, same grid); the candidate grid chooses again only the cells the
    // probe can affect. Both take effect at the next run().
    ProbeId addProbe(ProbeRecord probe);
    void removeProbe(ProbeId id);
    // Fills the pixels no resident candidate sees (kernel::kUncoveredAo) each frame; without one they
    // stay open (1), as a cache without coverage there would leave them.
    void setFallback(std::unique_ptr<AoFallback> fallback);
    AoFallback* fallback() const { return fallback_.get(); }
    // The next run() loads everything it wants regardless of the per-frame bound (a cut, a teleport).
    void requestUnboundedUpdate() { unbounded_ = true; }

    // Per-pixel diagnostics for the viewer's modes (tools/cubeao-view/view_modes.h). On, run() uses a
    // variant of project.comp built with PROJECT_DIAGNOSTICS that also writes diagnosticsTexture():
    // RGBA32F at the frame's size, row 0 at the top, r = probe0's id (−1 none), g = its texel footprint
    // at the point (world units per texel), b = its confidence there, a = path (0 sky, 1 probe,
    // 2 fallback probe, 3 uncovered; the layout is described at the top of project.comp). The AO, the
    // pixel counters (pixelShares, fetchesPerPixel) and the residency's feedback are the same bit for
    // bit with it on or off. Off frees the texture. The texture counts in gpuBytes() but lies outside
    // the residency's budget (a debugging aid, not part of the method).
    void setDiagnostics(bool on);
    bool diagnostics() const { return diagnostics_; }
    // 0 while diagnostics are off or before the first run() with them on; a new texture when the
    // frame's size changes, so a viewer asks for it every frame.
    GLuint diagnosticsTexture() const { return diagnosticsImage_.id(); }

    // Shares of the last frame's pixels, over all pixels, from one read-back of the pass's counters:
    // call after the frame.
    struct PixelShares {
        double geometry = 0.0;       // pixels with geometry (the rest show the sky)
        double uncovered = 0.0;      // no resident candidate saw them (screen space, or open without a fallback)
        double fallbackProbe = 0.0;  // covered, but a better-ranked candidate was not resident and was passed over
    };
    PixelShares pixelShares() const;
    // The same for a frame some frames back, without waiting: each run() copies its counters into a
    // read-back ring of kSharesRing slots (gl::ReadbackRing), read once the copy has finished (polled,
    // never waited on). The newest frame read so far; nullopt until one has been. For a frame loop.
    static constexpr std::size_t kSharesRing = 3;
    std::optional<PixelShares> latestPixelShares();
    double uncoveredFraction() const { return pixelShares().uncovered; }

    const ProbeGrid& grid() const { return *grid_; }
    const ProbeSource& source() const { return source_; }
    const ProbeAtlas& residency() const { return *residency_; }
    const ProbeAtlasLayout& atlas() const { return residency_->atlas(); }
    // GPU memory the pass holds: the residency's (atlases, staging, table, feedback), the candidate
    // grid and the counters.
    std::size_t gpuBytes() const;
    // The same as GL reports it for every texture and buffer the pass holds (for tests).
    std::size_t allocatedGpuBytes() const;
    // Per candidate cell, how many of its candidates were resident at the last run(), as the GPU
    // counted them (cell_residency.comp; for tests).
    std::vector<std::uint32_t> readResidentCandidateCounts() const;

private:
    gl::ShaderDefines projectDefines() const;
    ProbeProjectionPass(const CacheReader* cache, const CacheParams& params, std::span<const glm::vec3> positions,
                        std::span<const std::uint32_t> indices, const ProbeProjectionSettings& settings,
                        std::size_t expectedProbes);
    std::size_t ownGpuBytes() const;  // the candidate grid and the counters: what the residency does not hold
    void updateResidentLists();  // the second list over the pool's probes, when the pool changed
    void countResidentCandidates();  // residentCounts_, when the pool or the cells changed
    void uploadProjectBlock();  // project.comp's fixed parameters (kernel::ProjectBlock) into block_

    ProbeSource source_;
    ProbeProjectionSettings settings_;
    int res_ = 0, depthRes_ = 0, candidates_ = 0;
    std::unique_ptr<ProbeGrid> grid_;
    std::unique_ptr<ProbeAtlas> residency_;
    std::unique_ptr<NearestProbeLists> nearest_;
    std::uint64_t nearestVersion_ = ~std::uint64_t(0);  // the residency's residentVersion() they were built for
    std::unique_ptr<AoFallback> fallback_;
    gl::Program program_;
    gl::Program diagnosticsProgram_;  // project.comp with PROJECT_DIAGNOSTICS, built on first use
    gl::UniformBlock block_;          // both programs' parameters (and the cell count's)
    gl::UniformBlock camera_;         // the frame's CameraBlock
    gl::Texture diagnosticsImage_;
    int diagnosticsWidth_ = 0, diagnosticsHeight_ = 0;
    bool diagnostics_ = false;
    float uncoveredAo_ = 1.0f;  // what project.comp writes for an uncovered pixel (setFallback)
    gl::Buffer cells_, nearestCells_, counters_;
    // Per candidate cell, how many of its candidates are resident (cell_residency.comp), counted again
    // when the residency's version or the cells change.
    gl::Buffer residentCounts_;
    gl::Program countProgram_;
    std::uint64_t countedVersion_ = ~std::uint64_t(0);
    bool cellsChanged_ = true;
    // latestPixelShares' ring: each run()'s counters, tagged with its pixel count.
    gl::ReadbackRing<kernel::PassCounters, double> sharesRing_;
    std::optional<PixelShares> latestShares_;
    void collectShares();
    double pixels_ = 0.0;
    bool unbounded_ = true;
    ProbeRanking ranking_;  // what each frame wants resident
};

}  // namespace cubeao
