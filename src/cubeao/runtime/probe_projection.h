// The probe cache as a run-time AO method (`render --method probes`): every probe of a .cubeao cache
// uploaded once (AO + confidence as a BC5 2D array texture, distance cubes as a second one, six
// layers per probe), a world grid of K candidate probes per cell (probe_grid.h), and the projection
// pass (shaders/runtime/project.comp; per-point math and CPU twin in projection.h).
#pragma once

#include <memory>

#include <glm/vec3.hpp>

#include "cubeao/cache/cache_file.h"
#include "cubeao/gl/handles.h"
#include "cubeao/runtime/ao_pass.h"
#include "cubeao/runtime/probe_grid.h"
#include "cubeao/runtime/projection.h"

namespace cubeao {

class ProbeProjectionPass : public AoPass {
public:
    // Reads every probe of `cache` (checksums checked on the way) and builds the candidate grid over
    // the scene's bounds. Needs a current GL 4.5 context.
    ProbeProjectionPass(const CacheReader& cache, const glm::vec3& boundsMin, const glm::vec3& boundsMax,
                        ProbeGridSettings grid = {});
    ~ProbeProjectionPass() override;

    const char* name() const override { return "probes"; }
    void run(const CameraGBuffer& gbuffer, const CameraView& view, std::uint32_t frame, GLuint aoImage) override;
    double fetchesPerPixel() const override;
    // Pixels with geometry that no candidate probe saw, over all pixels of the last frame (their AO
    // falls back to 1, open).
    double uncoveredFraction() const;
    const ProbeGrid& grid() const { return *grid_; }

private:
    int res_ = 0, depthRes_ = 0, candidates_ = 0;
    std::unique_ptr<ProbeGrid> grid_;
    gl::Program program_;
    gl::Texture ao_, distance_;
    gl::Buffer probes_, cells_, counters_;
    double pixels_ = 0.0;
};

}  // namespace cubeao
