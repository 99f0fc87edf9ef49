#include "cubeao/bake/horizon.h"

#include "common/horizon.h"

namespace cubeao {
namespace {

// The kernel's view of a G-buffer and the settings (shaders/common/horizon.h, whose GLSL compilation
// is shaders/bake/ao_horizon.comp).
kernel::HorizonParams params(const CubeGBuffer& g, const BakeSettings& s) {
    return {g.probe, g.res, s.ao.radius, s.directions, s.steps, falloffUniform(s.ao.falloff), g.texels.data()};
}

}  // namespace

HorizonEstimate horizonSplitAo(const CubeGBuffer& g, const glm::vec3& p, const glm::vec3& n, const BakeSettings& s,
                               std::uint32_t key) {
    std::uint32_t fetches = 0;
    const glm::vec2 r = kernel::horizonSplitAo(params(g, s), p, n, key, fetches);
    return {r.x, r.y, fetches};
}

HorizonEstimate gtaoAo(const CubeGBuffer& g, const glm::vec3& p, const glm::vec3& n, const BakeSettings& s,
                       std::uint32_t key) {
    std::uint32_t fetches = 0;
    const glm::vec2 r = kernel::gtaoAo(params(g, s), p, n, key, fetches);
    return {r.x, r.y, fetches};
}

}  // namespace cubeao
