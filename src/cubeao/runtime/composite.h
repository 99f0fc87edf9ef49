// Composite for the preview images (DESIGN.md §4 "Projection"): simple direct lighting i_s, Lambert on
// the geometric normal under one directional light plus a constant ambient term, modulated by AO as
//   i = i_s · [(1 − α) + α · ao]
// α = 1 shows the AO at full strength, α = 0 ignores it. Pixels without geometry show the sky colour.
#pragma once

#include <glm/vec3.hpp>

#include "cubeao/gl/handles.h"
#include "cubeao/gl/uniform_block.h"
#include "cubeao/runtime/camera_gbuffer.h"
#include "cubeao/runtime/camera_view.h"

namespace cubeao {

struct CompositeSettings {
    float alpha = 1.0f;                 // α ∈ [0, 1]
    glm::vec3 lightDirection{0.0f};     // world space, towards the light; zero → defaultLightDirection(up)
    float ambient = 0.35f;              // i_s = albedo · (ambient + diffuse · max(0, n·l))
    float diffuse = 0.65f;
    glm::vec3 albedo{0.85f, 0.82f, 0.78f};
    glm::vec3 sky{0.62f, 0.72f, 0.85f};
};

// A light from high up (60° elevation) at a fixed azimuth around the scene's `up`.
glm::vec3 defaultLightDirection(const glm::vec3& up);
// The previews' lighting for a scene whose up axis is `up`: the default light, AO at strength `alpha`.
CompositeSettings previewComposite(const glm::vec3& up, float alpha = 1.0f);

// One lit pixel (view-space normal and light): shaders/common/composite.h, which composite.comp compiles too.
glm::vec3 compositePixel(const glm::vec3& normal, const glm::vec3& light, float ao, const CompositeSettings& s);

class Composite {
public:
    // `settings.lightDirection` must be non-zero (resolve it with defaultLightDirection). Needs a
    // current GL 4.5 context.
    explicit Composite(const CompositeSettings& settings);
    // Writes the lit frame into `output`, an RGBA8 texture of the G-buffer's size (linear values).
    void run(const CameraGBuffer& gbuffer, const CameraView& view, GLuint ao, GLuint output);

private:
    CompositeSettings settings_;
    gl::Program program_;
    gl::UniformBlock block_;  // kernel::CompositeBlock, per frame
};

}  // namespace cubeao
