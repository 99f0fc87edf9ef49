// Cube-map conventions in C++: the shared kernel (shaders/common/cube.h: face order, texel ↔
// direction, GL 4.5 §8.13.1 table 8.19) in the cube:: names the C++ code uses, plus what only the CPU
// needs: texel indices, solid angles and the projection that rasterises a face. tests/bake/test_bake_gl.cpp
// runs the same kernel on the GPU against this compilation of it.
//
// Face f, texel (i, j) of a res × res face covers s ∈ [i, i+1)/res, t ∈ [j, j+1)/res; its centre
// direction is faceDirection(f, 2·(i+0.5)/res − 1, 2·(j+0.5)/res − 1). Texel (i, j) is pixel (i, j)
// of the framebuffer that rasterises the face (row j = 0 at the bottom, as glReadPixels returns it).
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>

#include <glm/geometric.hpp>
#include <glm/mat4x4.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "common/cube.h"

namespace cubeao::cube {

constexpr int kFaces = kernel::kCubeFaces;  // +X, −X, +Y, −Y, +Z, −Z (GL_TEXTURE_CUBE_MAP_POSITIVE_X + f)

// Where a direction lands: face and (sc, tc) ∈ [−1, 1]² before the (·+1)/2 of the GL table.
struct FacePoint {
    int face = 0;
    glm::vec2 sc{0.0f};
};

inline FacePoint faceOf(const glm::vec3& d) {
    FacePoint fp;
    fp.face = kernel::cubeFaceOf(d, fp.sc);
    return fp;
}

inline glm::vec3 faceDirection(int face, const glm::vec2& sc) { return kernel::cubeFaceDirection(face, sc); }

inline glm::vec2 texelCentre(int i, int j, int res) { return kernel::cubeTexelCentre({i, j}, res); }

inline glm::vec3 texelDirection(int face, int i, int j, int res) { return kernel::cubeTexelDirection(face, {i, j}, res); }

inline glm::ivec2 texelOf(const glm::vec2& sc, int res) { return kernel::cubeTexelOf(sc, res); }

// Linear index of a texel in the six-face array: faces in order, rows bottom-up, texels left-right
// (kernel::cubeTexelIndex, widened: a six-face array at 16K² passes 2³²).
inline std::size_t texelIndex(int face, int i, int j, int res) {
    return (std::size_t(face) * std::size_t(res) + std::size_t(j)) * std::size_t(res) + std::size_t(i);
}

inline std::size_t texelIndex(const glm::vec3& d, int res) {
    const FacePoint fp = faceOf(d);
    const glm::ivec2 t = texelOf(fp.sc, res);
    return texelIndex(fp.face, t.x, t.y, res);
}

// Solid angle of texel (i, j) (any face): ∫ dA / (1 + u² + v²)^{3/2} over the texel, in closed form
// via the corner function atan2(uv, √(1+u²+v²)) (used to weight per-texel statistics).
inline double texelSolidAngle(int i, int j, int res) {
    const auto corner = [](double u, double v) { return std::atan2(u * v, std::sqrt(1.0 + u * u + v * v)); };
    const double u0 = 2.0 * i / res - 1.0, u1 = 2.0 * (i + 1) / res - 1.0;
    const double v0 = 2.0 * j / res - 1.0, v1 = 2.0 * (j + 1) / res - 1.0;
    return corner(u1, v1) - corner(u0, v1) - corner(u1, v0) + corner(u0, v0);
}

// clip = clipFromWorld · (world, 1) rasterises face `face` of a probe at `probe`: clip.x/clip.w and
// clip.y/clip.w are the face's (sc, tc), clip.w the major-axis distance, and depth is reversed-Z
// with an infinite far plane, depth = zNear / clip.w (use glClipControl(GL_LOWER_LEFT,
// GL_ZERO_TO_ONE), clear depth to 0, GL_GREATER): float depth then resolves distant surfaces as
// finely as near ones. Only the ordering matters: the G-buffer stores the exact distance separately.
inline glm::mat4 clipFromWorld(int face, const glm::vec3& probe, float zNear) {
    // Rows of the linear map d ↦ (sc·ma, tc·ma, ma) for d = world − probe, read off faceOf.
    static constexpr float kRows[kFaces][3][3] = {
        {{0, 0, -1}, {0, -1, 0}, {1, 0, 0}},  {{0, 0, 1}, {0, -1, 0}, {-1, 0, 0}},
        {{1, 0, 0}, {0, 0, 1}, {0, 1, 0}},    {{1, 0, 0}, {0, 0, -1}, {0, -1, 0}},
        {{1, 0, 0}, {0, -1, 0}, {0, 0, 1}},   {{-1, 0, 0}, {0, -1, 0}, {0, 0, -1}},
    };
    const auto& r = kRows[face];
    const glm::vec3 rowX(r[0][0], r[0][1], r[0][2]), rowY(r[1][0], r[1][1], r[1][2]), rowW(r[2][0], r[2][1], r[2][2]);
    glm::mat4 m(0.0f);  // glm is column-major: m[column][row]
    for (int c = 0; c < 3; ++c) {
        m[c][0] = rowX[c];
        m[c][1] = rowY[c];
        m[c][3] = rowW[c];
    }
    m[3][0] = -glm::dot(rowX, probe);
    m[3][1] = -glm::dot(rowY, probe);
    m[3][2] = zNear;
    m[3][3] = -glm::dot(rowW, probe);
    return m;
}

}  // namespace cubeao::cube
