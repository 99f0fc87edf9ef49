// The probe cache as a run-time AO method (`render --method probes`): every probe of a .cubeao cache
// uploaded once (AO + confidence as a BC5 2D array texture, distance cubes as a second one, both laid
// out as probe atlases: ProbeAtlasLayout), a world grid of K candidate probes per cell (probe_grid.h),
// and the projection pass (shaders/runtime/project.comp; per-point math and CPU twin in projection.h).
#pragma once

#include <cstddef>
#include <memory>
#include <span>

#include <glm/vec3.hpp>

#include "cubeao/cache/cache_file.h"
#include "cubeao/gl/handles.h"
#include "cubeao/runtime/ao_pass.h"
#include "cubeao/runtime/probe_grid.h"
#include "cubeao/runtime/projection.h"

namespace cubeao {

// Where probe i's six faces live in the array textures: tile t = i mod (tilesX · tilesY) of page
// p = i / (tilesX · tilesY), tiles in rows of tilesX, face f of page p in layer 6p + f; a tile is
// res × res texels in the AO texture and depthRes × depthRes in the distance one. Tiles rather than
// six layers per probe because GL_MAX_ARRAY_TEXTURE_LAYERS is 2048 on llvmpipe and on NVIDIA, i.e.
// 341 probes; a 16384² page holds 1,024 probes at 512² or 10,000 at 16² (bench render's sweep).
struct ProbeAtlasLayout {
    int tilesX = 1, tilesY = 1, pages = 1;
    int tilesPerPage() const { return tilesX * tilesY; }
};

// A near-square page just big enough for `probes` (tilesX = ⌈√probes⌉), at most maxTextureSize / res
// tiles a side, then more pages. Error naming the counts when 6 · pages exceeds maxLayers.
ProbeAtlasLayout probeAtlasLayout(std::size_t probes, int res, int maxTextureSize, int maxLayers);

class ProbeProjectionPass : public AoPass {
public:
    // Reads every probe of `cache` (checksums checked on the way) and builds the candidate grid over
    // the scene's mesh (its bounds, and points sampled on its surfaces: probe_grid.h). Needs a
    // current GL 4.5 context.
    ProbeProjectionPass(const CacheReader& cache, std::span<const glm::vec3> positions,
                        std::span<const std::uint32_t> indices, ProbeGridSettings grid = {});
    ~ProbeProjectionPass() override;

    const char* name() const override { return "probes"; }
    void run(const CameraGBuffer& gbuffer, const CameraView& view, std::uint32_t frame, GLuint aoImage) override;
    double fetchesPerPixel() const override;
    // Pixels with geometry that no candidate probe saw, over all pixels of the last frame (their AO
    // falls back to 1, open).
    double uncoveredFraction() const;
    const ProbeGrid& grid() const { return *grid_; }
    const ProbeAtlasLayout& atlas() const { return atlas_; }
    // GPU memory the probes take: both atlases, the probe table and the candidate grid.
    std::size_t gpuBytes() const { return gpuBytes_; }

private:
    int res_ = 0, depthRes_ = 0, candidates_ = 0;
    ProbeAtlasLayout atlas_;
    std::size_t gpuBytes_ = 0;
    std::unique_ptr<ProbeGrid> grid_;
    gl::Program program_;
    gl::Texture ao_, distance_;
    gl::Buffer probes_, cells_, counters_;
    double pixels_ = 0.0;
};

}  // namespace cubeao
