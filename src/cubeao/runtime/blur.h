// Edge-aware AO blur (DESIGN.md §4 "Projection"): separable (a horizontal then a vertical pass,
// paper 000 §3.2.4), 2r + 1 taps per pass, tap i (−r..r) of a pixel weighted by
//   exp(−i² / (2 (r/2)²))                                  spatial term: a Gaussian with σ = r/2
//   · ((n_c·n_s + 1)/2)^k_n                                normal term, paper 000 eq. 3.2.2, k_n = 10
//   · max(0, 1 − |n_c·(p_s − p_c)| / (τ · z_c))            relative depth term, paper 002 listing 3.16
// with n, p the view-space normal and surface point of the centre c and the tap s, and z_c the centre's
// view depth.
//  - Spatial term: paper 000 uses a box and names a Gaussian as the future improvement; measured on
//    the cloister (8 frames, 640×360, vs the Embree reference) GTAO's MAE is 0.0276 with the best box
//    (r = 1) and 0.0274 with the Gaussian at r = 2 (SSIM 0.919 → 0.923); a box at paper 000's r = 3
//    smears crease shadows (MAE 0.0291).
//  - Depth term: 002's relative weight (a tap may lie τ = 10 % of the centre's depth away), scale-free
//    unlike paper 000's (1/(1 + |Δd|))², which depends on the scene's length unit, and measured as the
//    tap's distance from the centre's tangent plane rather than its depth difference, so a surface seen
//    at a grazing angle (a floor down a corridor) blurs like a facing one, while a step between two
//    surfaces more than τ·z_c apart gets weight exactly 0: no AO crosses such an edge.
// Pixels without geometry are neither blurred nor used as taps. blurAoCpu is the CPU twin (tests
// compare the two to 1e-4); its weights are the shader's (shaders/common/bilateral.h), the tap loop is
// written again here because the shader's reads are texture fetches and the twin's an Image.
#pragma once

#include "cubeao/gl/handles.h"
#include "cubeao/gl/uniform_block.h"
#include "cubeao/core/image.h"
#include "cubeao/runtime/camera_gbuffer.h"
#include "cubeao/runtime/camera_view.h"

namespace cubeao {

struct BlurSettings {
    int radius = 2;             // taps on each side of the centre per pass; 0 = no blur (paper 000: 3, a box)
    float normalPower = 10.0f;  // k_n, paper 000 fig. 3.2.2
    float depthTolerance = 0.1f;  // τ, fraction of the centre's view depth, paper 002 listing 3.16
};

// The probes' blur (`render` without --blur, the viewer, `bench render`; the screen-space methods keep
// BlurSettings{}, 2 taps): 1 tap a side while one probe texel, at the probe's distance from the
// surface seen from as far by the camera, spans at most 3 pixels (height / (res · tan(fovY / 2)) ≤ 3),
// else 2. The probes' error is fixed in the world at texel scale: where texels are smaller than a few
// pixels a wider blur only smears the crease darkening the reference keeps; where they are larger
// it hides their steps. Measured against Embree references (docs/BENCHMARKS.md "Current figures"):
// 1 tap wins in MAE and flicker at 0.3–1.2 pixels per texel (Sibenik and FZK-Haus at 512² and 256²,
// 160×90 and 320×180; the cloister's 128² at 160×90), ties at 2.4 (128², 320×180), loses at 4.9
// (128², 640×360: the demo).
BlurSettings probeBlurSettings(int res, int height, float tanHalfFovY);

// Checks ranges, listing every problem in one UsageError.
void validateBlurSettings(const BlurSettings& s);

// Weight of tap s for centre c (both with geometry): the normal and depth terms above, the kernel of
// shaders/common/bilateral.h that blur.comp compiles too.
float bilateralWeight(const glm::vec3& centreNormal, const glm::vec3& centrePoint, float centreDepth,
                      const glm::vec3& tapNormal, const glm::vec3& tapPoint, const BlurSettings& s);

// The spatial term of tap i for `radius` (1 for radius 0): bilateral.h's bilateralSpatialWeight.
float spatialWeight(int tap, int radius);

// CPU twin of Blur::run: both passes on a read-back G-buffer.
Image blurAoCpu(const Image& ao, const CameraGBufferImage& gbuffer, const CameraView& view, const BlurSettings& s);

class Blur {
public:
    explicit Blur(const BlurSettings& settings);  // needs a current GL 4.5 context
    // Blurs R32F `input` into R32F `output` (same size as the G-buffer), using an internal
    // intermediate texture. With radius 0 it copies.
    void run(const CameraGBuffer& gbuffer, const CameraView& view, GLuint input, GLuint output);
    const BlurSettings& settings() const { return settings_; }
    // Another width or weights from the next run on (the viewer re-chooses the probes' width when its
    // window changes size). Error for invalid settings, as the constructor.
    void setSettings(const BlurSettings& settings);
    // Texture fetches per pixel with geometry for both passes: 2 × (2r + 1) taps × (AO, depth,
    // normal) less the centre's reuse. Planned, not counted.
    int fetchesPerPixel() const { return settings_.radius == 0 ? 0 : 2 * (3 * 2 * settings_.radius + 3); }

private:
    BlurSettings settings_;
    gl::Program program_;
    gl::UniformBlock block_;   // kernel::BlurBlock: the settings, and the axis of the pass being run
    gl::UniformBlock camera_;  // kernel::CameraBlock, per frame
    gl::Texture intermediate_;
    int width_ = 0, height_ = 0;
};

}  // namespace cubeao
