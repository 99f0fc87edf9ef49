#include "cubeao/runtime/composite.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

#include "common/composite.h"
#include "common/runtime_layout.h"
#include "cubeao/core/error.h"
#include "cubeao/gl/shader.h"

namespace cubeao {

glm::vec3 defaultLightDirection(const glm::vec3& up) {
    const glm::vec3 u = glm::normalize(up);
    // Any fixed horizontal direction: the axis least aligned with up, made orthogonal to it.
    const glm::vec3 a = std::abs(u.x) < 0.9f ? glm::vec3(1.0f, 0.0f, 0.0f) : glm::vec3(0.0f, 0.0f, 1.0f);
    const glm::vec3 h = glm::normalize(a - u * glm::dot(a, u));
    const glm::vec3 h2 = glm::cross(u, h);
    const float elevation = 1.0471976f;  // 60°
    return glm::normalize(std::sin(elevation) * u + std::cos(elevation) * glm::normalize(h + 0.6f * h2));
}

CompositeSettings previewComposite(const glm::vec3& up, float alpha) {
    CompositeSettings c;
    c.alpha = alpha;
    c.lightDirection = defaultLightDirection(up);
    return c;
}

glm::vec3 compositePixel(const glm::vec3& normal, const glm::vec3& light, float ao, const CompositeSettings& s) {
    return kernel::compositeColour(normal, light, ao, s.albedo, s.ambient, s.diffuse, s.alpha);
}

Composite::Composite(const CompositeSettings& settings) : settings_(settings) {
    if (!(glm::length(settings.lightDirection) > 0.0f)) throw Error("Composite: light direction is zero");
    if (!(settings.alpha >= 0.0f && settings.alpha <= 1.0f)) throw UsageError("--alpha must lie in [0, 1]");
    settings_.lightDirection = glm::normalize(settings.lightDirection);
    program_ = gl::compileComputeProgram("runtime/composite.comp");
}

void Composite::run(const CameraGBuffer& gbuffer, const CameraView& view, GLuint ao, GLuint output) {
    const CompositeSettings& s = settings_;
    const glm::vec3 light = glm::normalize(view.viewFromWorldRotation() * s.lightDirection);
    glUseProgram(program_.id());
    block_.upload(kernel::CompositeBlock{light, s.alpha, s.albedo, s.ambient, s.sky, s.diffuse,
                                         {gbuffer.width(), gbuffer.height()}},
                  kernel::kCompositeBlock);
    glBindTextureUnit(kernel::kGBufferDepthUnit, gbuffer.depthTexture());
    glBindTextureUnit(kernel::kGBufferNormalUnit, gbuffer.normalTexture());
    glBindTextureUnit(kernel::kAoInputUnit, ao);
    glBindImageTexture(kernel::kShadedImageUnit, output, 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA8);
    glDispatchCompute(kernel::pixelGroups(gbuffer.width()), kernel::pixelGroups(gbuffer.height()), 1);
    glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_TEXTURE_UPDATE_BARRIER_BIT);
}

}  // namespace cubeao
