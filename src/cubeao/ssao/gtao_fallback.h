// The screen-space fallback of the probe projection (runtime/ao_pass.h AoFallback; DESIGN.md §4 "Run
// time that grows"): pixels the projection marks uncovered (raw AO < 0, kernel::kUncoveredAo) take
// the GTAO baseline's value, and covered pixels with geometry within kernel::kFallbackBlendPixels of
// one take mix(probe AO, GTAO, max(0, 1 − d / B)) at Euclidean distance d, so a hole never reads
// "open" and its edge shows no seam. Pixels without geometry keep their value (1).
// B = 2: the pixels next to a hole take half the GTAO, and the blur after it (radius 2, a 5-pixel
// footprint) smooths the rest of the step. Measured on the Sibenik walk (22 probes at 512², 160×90,
// every frame): MAE 0.0211 with the holes left open, 0.0200 with GTAO in the holes alone, 0.0203 at
// B = 2, 0.0215 at B = 4. Most holes there are single silhouette pixels; a wide band puts GTAO's
// error (MAE 0.09 on that walk) on many good probe pixels around each. B ≤ 8 (one tile).
//
// Shaders: shaders/ssao/gtao_fill.comp, three dispatches (mark, select, fill; why there, in short:
// the image is rewritten in place, so who blends is decided from tile masks, never from the image).
// The GTAO is the same kernel as SsaoPass's gtao (ssao_pixel.glsl, gtao_march.glsl), so a filled
// pixel equals the gtao pass's output at that pixel, jitter included. Cost: mark reads the AO image
// once (a frame without holes costs that and nothing more); GTAO runs only for the pixels that take
// it, packed 64 to a work group. fill() issues GL commands only: no wait, no read-back.
#pragma once

#include <cstddef>
#include <cstdint>

#include "common/runtime_layout.h"
#include "cubeao/gl/handles.h"
#include "cubeao/gl/uniform_block.h"
#include "cubeao/runtime/ao_pass.h"
#include "cubeao/ssao/ssao_settings.h"

namespace cubeao {

class GtaoFallback final : public AoFallback {
public:
    // `settings` resolved as the gtao baseline's (resolveSsaoSettings, radius = the cache's R, as
    // cmd_render resolves them); its method must be gtao (cubeao::Error otherwise). Compiles the three
    // programs: needs a current GL 4.5 context.
    explicit GtaoFallback(const SsaoSettings& settings);

    void fill(const CameraGBuffer& gbuffer, const CameraView& view, std::uint32_t frame, GLuint aoImage) override;
    double filledFraction() const override;
    double blendedFraction() const override;
    // The GTAO's G-buffer fetches in the last fill, over all pixels (may wait, like the fractions).
    double fetchesPerPixel() const;
    // The last fill's counters as the GPU wrote them (may wait).
    kernel::FallbackCounters counters() const;
    const SsaoSettings& settings() const { return settings_; }

private:
    SsaoSettings settings_;
    gl::Program mark_, select_, fill_;
    gl::UniformBlock block_;   // kernel::SsaoBlock, fixed: the gtao baseline's
    gl::UniformBlock camera_;  // kernel::CameraBlock, per frame (all three passes)
    gl::Buffer tiles_, tileList_, workList_, counters_;
    gl::Buffer emptyList_;          // kernel::FallbackList {0, 1, 1, 0}: copied to both lists' heads every frame
    std::size_t tileCapacity_ = 0;  // tiles that the buffers hold (the work list: their pixels)
    double pixels_ = 0.0;  // of the last fill
};

}  // namespace cubeao
