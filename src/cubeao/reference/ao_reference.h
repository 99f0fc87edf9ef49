// Embree ray-traced ambient occlusion: the ground truth of every quality figure (DESIGN.md §4
// "What AO means here"): AO_R(p) = 1 − (1/π) ∫ V_R(p, ω) cos θ dω, 1 = open, 0 = fully occluded.
#pragma once

#include <cstdint>
#include <string>

#include <glm/vec3.hpp>

#include "cubeao/core/falloff.h"
#include "cubeao/core/image.h"
#include "cubeao/reference/embree_scene.h"
#include "cubeao/scene/camera_path.h"

namespace cubeao {

class Progress;

struct AoSettings {
    float radius = 0.0f;  // world units, > 0 (commands resolve 0 to the scene default: 2 % of the bbox diagonal)
    int spp = 64;         // rays per pixel or texel
    Falloff falloff = Falloff::None;
    std::uint32_t seed = 0;  // changes every pixel's rotation of the sample set
};

struct AoEstimate {
    float ao = 1.0f;
    float stdError = 0.0f;  // standard error of `ao` as if the samples were independent (an upper
                            // bound in practice: the stratified set converges faster)
};

// AO at surface point p with unit normal n (facing the side to evaluate), `key` choosing the rotation
// of the sample set (e.g. a pixel or texel id). Deterministic: same inputs, same rays, same answer.
AoEstimate ambientOcclusion(const EmbreeScene& scene, const glm::vec3& p, const glm::vec3& n,
                            const AoSettings& settings, std::uint32_t key);

struct ReferenceFrame {
    Image ao;                       // 1 = open; pixels that see no geometry are 1
    double noise = 0.0;             // standard error over the pixels that show geometry (see below)
    double backgroundFraction = 0;  // pixels whose primary ray hit nothing
    std::uint64_t aoRays = 0;
};

// One camera image, all cores. The key of pixel (x, y) is hashKey(x, y, frame ^ seed).
//
// Noise. The rays of one pixel are a rotated Hammersley set, which converges faster than independent
// rays, so the independent-ray standard error (AoEstimate::stdError) overstates the error, about
// 4× at 256 rays on the Sibenik walk. With `replicas` = K ≥ 2 the pixel's settings.spp rays are
// split into K sets of spp/K rays, each with its own rotation (replica 0 keeps the pixel's key,
// replica r the key hashed with r), and the pixel is their mean. The spread of the K replica means
// is an unbiased estimate of each pixel's variance, and the frame's `noise` is the root mean square
// standard error sqrt(mean(s²/K)) over the pixels that show geometry: measured, not bounded, and by
// Jensen's inequality at least the mean standard error. With K = 1, `noise` is the mean of the
// independent-ray bound. settings.spp must be a multiple of K.
//
// Anti-aliasing (`aa` = N ≥ 2, `reference --aa N`): N×N stratified primary rays per pixel, each jittered
// inside its cell of the pixel, box-filtered, as offline renderers (Blender Cycles) make their images;
// each sub-sample traces spp/N² AO rays (spp must be a multiple of N²·K), so a pixel still costs spp AO
// rays; sub-samples that see no geometry count as open (1). With N = 1 the primary ray goes through the
// pixel centre, as the run time's G-buffer does: the image to compare `render` against.
ReferenceFrame renderReferenceFrame(const EmbreeScene& scene, const PinholeCamera& camera, const AoSettings& settings,
                                    std::uint32_t frameIndex, Progress* progress, int replicas = 1, int aa = 1);

}  // namespace cubeao
