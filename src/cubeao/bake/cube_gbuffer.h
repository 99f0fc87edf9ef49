// A probe's cube G-buffer on the CPU: per texel the unit surface normal (turned to face the probe)
// and the distance from the probe along the texel's centre direction. Produced by the GPU pass (read
// back) or by Embree primary rays (the CPU twin); the horizon estimators read it.
#pragma once

#include <cstddef>
#include <vector>

#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "cubeao/core/cube.h"

namespace cubeao {

struct CubeGBuffer {
    int res = 0;
    glm::vec3 probe{0.0f};
    std::vector<glm::vec4> texels;  // (normal, distance) in cube::texelIndex order; distance 0 = empty

    static bool empty(const glm::vec4& texel) { return !(texel.w > 0.0f); }
    std::size_t texelCount() const { return std::size_t(cube::kFaces) * std::size_t(res) * std::size_t(res); }
    // Surface point of texel (face, i, j): where the centre ray of the texel meets the scene.
    glm::vec3 surfacePoint(int face, int i, int j) const {
        return probe + cube::texelDirection(face, i, j, res) * texels[cube::texelIndex(face, i, j, res)].w;
    }
};

}  // namespace cubeao
